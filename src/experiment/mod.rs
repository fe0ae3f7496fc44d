//! The dispatch-policy experiment seed 2 is missing (`mavtempo experiment dispatch`): the shipped missions,
//! planned once, executed by the executive ([`crate::exec::mission::run_mission`]) under each policy while a
//! ground station uploads goals at random (seeded Poisson arrivals, random targets and windows, see
//! [`arrivals`]); the vehicle ([`vehicle`]) travels at seeded speeds on a manual clock.
//!
//! Per scenario and policy it counts the uploaded goals' fates (achieved, rejected with the reason, pending
//! at the end — they add up to the arrivals), the mean time from upload to achievement, the vehicle's idle
//! time, the distance travelled, the travel wasted (a leg driven back at once, with nothing done at its
//! end), complete replannings and plan repairs, and how many of the mission's own goals were achieved.

pub mod arrivals;
pub mod vehicle;

use std::collections::{BTreeMap, HashMap};
use std::sync::Arc;

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::Serialize;

use self::arrivals::{arrivals, Arrival, ArrivalModel, Target};
use self::vehicle::{Done, KinematicPacer, KinematicVehicle, TaskTime};
use crate::config_check::resolve_mapping;
use crate::dispatch::PolicyKind;
use crate::exec::config::ExecConfig;
use crate::exec::executive::{Executive, Fate};
use crate::exec::goal_request::Rejection;
use crate::exec::mission::{run_mission, MissionOptions, MissionReport};
use crate::exec::outcome::FateReason;
use crate::exec::trace::TraceEvent;
use crate::exec::DomainMapping;
use crate::lang;
use crate::model::{Position, Problem, Time};
use crate::plan::PartialPlan;
use crate::planner::{Budget, Search, StepOutcome};
use crate::vehicle::config::Mapping;
use crate::vehicle::{Enu, GoalKind};

const MIN: Time = 60_000;
const HOUR: Time = 60 * MIN;

/// Why a scenario could not be prepared.
#[derive(Debug, thiserror::Error)]
pub enum ExperimentError {
    #[error("{scenario}: {reason}")]
    Load { scenario: String, reason: String },
    #[error("{scenario}: the planner found no initial plan ({outcome})")]
    NoPlan { scenario: String, outcome: String },
}

/// A scenario: the mission, how the vehicle performs its tasks, what the ground station asks for.
struct Spec {
    name: &'static str,
    domain: (&'static str, &'static str),
    problem: (&'static str, &'static str),
    /// Coordinates given to places the problem file leaves without (shopping's walks of 15–20 min).
    positions: &'static [(&'static str, f64, f64, f64)],
    times: Vec<(&'static str, TaskTime)>,
    targets: Vec<(GoalKind, &'static str)>,
    /// The executive's `[mapping]` for this domain, as a vehicle configuration would give it.
    mapping: &'static str,
    achieve_ms: Time,
}

fn specs() -> Vec<Spec> {
    vec![
        Spec {
            name: "auv",
            domain: (
                "domains/auv/auv.ixt",
                include_str!("../../domains/auv/auv.ixt"),
            ),
            problem: (
                "domains/auv/problems/vents.ixt",
                include_str!("../../domains/auv/problems/vents.ixt"),
            ),
            positions: &[],
            // Inside the domain's 1–1.5 m/s and fast enough for the 300 m leg (200–300 s) to end before its
            // late-preemptive stop at ub − ts.
            times: vec![
                ("go", TaskTime::Travel { lo: 1.3, hi: 1.45 }),
                ("survey", TaskTime::exactly(10 * MIN)),
                ("sample", TaskTime::exactly(10 * MIN)),
            ],
            targets: vec![
                (GoalKind::SampleAt, "vent1"),
                (GoalKind::SampleAt, "vent2"),
                (GoalKind::BeAt, "vent1"),
                (GoalKind::BeAt, "vent2"),
                (GoalKind::BeAt, "surface"),
            ],
            // No `position`: a walk stopped short (late-preemptive stop at ub - ts) counts as arrived, as
            // the route graph has no place between two places to plan from (a mid-route place would be
            // CONNECTED to nothing and end the mission).
            mapping: r#"
                location_type = "location"
                goals.waypoint = { attribute = "AUV_AT" }
                goals.sample = { attribute = "SAMPLED" }
            "#,
            achieve_ms: 30 * MIN,
        },
        Spec {
            name: "shopping",
            domain: (
                "domains/shopping/shopping.ixt",
                include_str!("../../domains/shopping/shopping.ixt"),
            ),
            problem: (
                "domains/shopping/problems/day.ixt",
                include_str!("../../domains/shopping/problems/day.ixt"),
            ),
            // 1.2 km apart: 15–20 min at 1–1.33 m/s; walks end before their stop at 19 min.
            positions: &[
                ("home", 0.0, 0.0, 0.0),
                ("clothing", 1_200.0, 0.0, 0.0),
                ("grocery", 2_400.0, 0.0, 0.0),
            ],
            times: vec![
                ("go", TaskTime::Travel { lo: 1.1, hi: 1.3 }),
                ("buy", TaskTime::exactly(5 * MIN)),
            ],
            targets: vec![
                (GoalKind::BeAt, "home"),
                (GoalKind::BeAt, "clothing"),
                (GoalKind::BeAt, "grocery"),
            ],
            // No `position`, as for the AUV.
            mapping: r#"
                location_type = "place"
                goals.waypoint = { attribute = "AT" }
            "#,
            achieve_ms: 20 * MIN,
        },
    ]
}

/// The scenarios `experiment dispatch` runs. The rover missions are left out while the planner does not
/// solve them (issue 4).
pub fn scenario_names() -> Vec<&'static str> {
    specs().iter().map(|s| s.name).collect()
}

/// A scenario with its initial plan.
pub struct Prepared {
    pub name: String,
    plan: PartialPlan,
    mapping: DomainMapping,
    times: HashMap<String, TaskTime>,
    targets: Vec<Target>,
    model: ArrivalModel,
}

fn prepare(spec: &Spec, per_hour: f64) -> Result<Prepared, ExperimentError> {
    let load = |reason: String| ExperimentError::Load {
        scenario: spec.name.into(),
        reason,
    };
    let domain =
        lang::parse_domain(spec.domain.0, spec.domain.1).map_err(|e| load(e.to_string()))?;
    let mut problem: Problem = lang::parse_problem(spec.problem.0, spec.problem.1, &domain)
        .map_err(|e| load(e.to_string()))?;
    for &(name, east, north, up) in spec.positions {
        let o = problem
            .object_id(name)
            .ok_or_else(|| load(format!("no place {name}")))?;
        problem.objects[o.index()].position = Some(Position::Local { east, north, up });
    }
    let home = problem.home;
    let mut targets = Vec::new();
    for &(kind, place) in &spec.targets {
        let o = problem
            .object_id(place)
            .and_then(|o| problem.object(o))
            .ok_or_else(|| load(format!("no place {place}")))?;
        let (e, n, u) = o
            .local(home.as_ref())
            .ok_or_else(|| load(format!("{place} has no position")))?;
        targets.push(Target {
            kind,
            place: place.into(),
            at: Enu::new(e, n, u),
        });
    }
    let horizon = problem.horizon;
    let mapping: Mapping =
        toml::from_str(spec.mapping).map_err(|e| load(format!("mapping: {e}")))?;
    let mapping = resolve_mapping(&mapping, &domain, Some(&problem), None).map_err(|issues| {
        let lines: Vec<String> = issues.iter().map(|i| i.to_string()).collect();
        load(lines.join("; "))
    })?;
    let root =
        PartialPlan::new(Arc::new(domain), Arc::new(problem)).map_err(|e| load(e.to_string()))?;
    let mut search = Search::new(root);
    match search.run(Budget::steps(50_000)) {
        StepOutcome::Solved => {}
        other => {
            return Err(ExperimentError::NoPlan {
                scenario: spec.name.into(),
                outcome: format!("{other:?}"),
            })
        }
    }
    Ok(Prepared {
        name: spec.name.into(),
        plan: search.into_plan(),
        mapping,
        times: spec
            .times
            .iter()
            .map(|(t, tt)| (t.to_string(), tt.clone()))
            .collect(),
        targets,
        model: ArrivalModel {
            per_hour,
            until_ms: horizon - 2 * HOUR,
            max_delay_ms: HOUR,
            width_ms: (30 * MIN, 4 * HOUR),
            achieve_ms: spec.achieve_ms,
            horizon_ms: horizon,
        },
    })
}

/// What one mission gave.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct MissionOutcome {
    pub arrived: u64,
    pub achieved: u64,
    pub rejected: BTreeMap<String, u64>,
    pub pending: u64,
    /// Upload to achievement, per achieved goal, ms.
    pub time_to_achieve_ms: Vec<Time>,
    pub idle_ms: Time,
    pub distance_m: f64,
    pub wasted_m: f64,
    pub replans: u64,
    pub repairs: u64,
    /// The problem file's own goals: achieved / all.
    pub mission_goals_achieved: u64,
    pub mission_goals: u64,
}

/// Short names for the rejection reasons (src/executive/src/exec/outcome.rs); `None`: the mission ended before the goal
/// arrived.
fn reason_class(reason: Option<&FateReason>) -> String {
    let class = match reason.map(FateReason::cause) {
        None => "mission-over",
        Some(FateReason::Acceptance(Rejection::TooLate { .. })) => "too-late",
        Some(FateReason::WindowPassed { .. }) => "window-passed",
        Some(FateReason::Acceptance(Rejection::Window { .. })) => "window",
        Some(FateReason::Acceptance(Rejection::Running { .. })) => "running",
        Some(FateReason::ReplanBudgetSpent { .. } | FateReason::Abandoned { .. }) => "replanning",
        Some(FateReason::InsertionFailed { .. }) => "insertion-failed",
        Some(FateReason::InsertionTimedOut { .. }) => "insertion-timeout",
        Some(FateReason::Unreachable { .. }) => "unreachable",
        Some(FateReason::PlanChurn(_)) => "plan-change-bound",
        Some(FateReason::InstanceBanned { .. } | FateReason::NeedsBanned { .. }) => {
            "repeated-failure"
        }
        Some(FateReason::HorizonPassed) => "horizon",
        Some(_) => "other",
    };
    class.into()
}

/// Time with no action running between the origin and `end`.
fn idle(log: &[Done], end: Time) -> Time {
    let mut spans: Vec<(Time, Time)> = log
        .iter()
        .map(|d| (d.start_ms as Time, (d.end_ms as Time).min(end)))
        .collect();
    spans.sort_unstable();
    let (mut busy, mut reach) = (0, 0);
    for (s, e) in spans {
        let s = s.max(reach);
        if e > s {
            busy += e - s;
            reach = e;
        }
    }
    (end - busy).max(0)
}

/// Travel wasted: a leg `A → B` followed at once by `B → A`, nothing done at `B` in between.
fn wasted(log: &[Done]) -> f64 {
    let mut w = 0.0;
    let mut i = 0;
    while i + 1 < log.len() {
        if let (Some((a, b, d1)), Some((b2, a2, d2))) = (&log[i].leg, &log[i + 1].leg) {
            if a == a2 && b == b2 {
                w += d1 + d2;
                // A leg is wasted once, even inside a longer back-and-forth.
                i += 2;
                continue;
            }
        }
        i += 1;
    }
    w
}

fn outcome(
    report: &MissionReport,
    ex: &Executive,
    uploads: &[Arrival],
    log: &[Done],
    problem_goals: &[String],
) -> MissionOutcome {
    let mut out = MissionOutcome {
        arrived: uploads.len() as u64,
        idle_ms: idle(log, report.duration_ms),
        distance_m: log.iter().filter_map(|d| d.leg.as_ref()).map(|l| l.2).sum(),
        wasted_m: wasted(log),
        replans: ex.counters().replans,
        repairs: ex.counters().repairs,
        ..MissionOutcome::default()
    };
    let mut achieved_at: HashMap<&str, Time> = HashMap::new();
    let mut rejected_at_intake: HashMap<&str, &FateReason> = HashMap::new();
    for c in &report.cycles {
        for e in &c.events {
            match e {
                TraceEvent::GoalAchieved { goal } => {
                    achieved_at.entry(goal.as_str()).or_insert(c.time_ms);
                }
                TraceEvent::GoalRejected { goal, reason } => {
                    rejected_at_intake.entry(goal.as_str()).or_insert(reason);
                }
                _ => {}
            }
        }
    }
    let fates: HashMap<&str, (&Fate, Option<&FateReason>)> = report
        .goals
        .iter()
        .map(|g| (g.name.as_str(), (&g.fate, g.reason.as_ref())))
        .collect();
    for up in uploads {
        let name = up.goal.name.as_str();
        let reason = match fates.get(name) {
            Some((Fate::Achieved, _)) => {
                out.achieved += 1;
                if let Some(t) = achieved_at.get(name) {
                    out.time_to_achieve_ms.push(t - up.at_ms);
                }
                continue;
            }
            Some((Fate::Rejected | Fate::Cancelled, reason)) => *reason,
            Some((Fate::Pending, _)) => {
                out.pending += 1;
                continue;
            }
            None => match rejected_at_intake.get(name) {
                Some(reason) => Some(*reason),
                None if up.at_ms > report.duration_ms => None,
                None => {
                    out.pending += 1;
                    continue;
                }
            },
        };
        *out.rejected.entry(reason_class(reason)).or_insert(0) += 1;
    }
    for name in problem_goals {
        out.mission_goals += 1;
        if matches!(fates.get(name.as_str()), Some((Fate::Achieved, _))) {
            out.mission_goals_achieved += 1;
        }
    }
    out
}

/// One mission of `p` under `policy` with the goals and vehicle of `seed`.
pub fn run_one(p: &Prepared, policy: PolicyKind, seed: u64, repair_steps: u64) -> MissionOutcome {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let uploads = arrivals(&p.model, &p.targets, &mut rng);
    let mut v = KinematicVehicle::new(ChaCha8Rng::seed_from_u64(seed ^ 0x5eed), p.times.clone());
    if p.mapping.position.is_none() {
        v = v.without_positions();
    }
    for up in &uploads {
        v.goals_at(up.at_ms.max(0) as u64, vec![up.goal.clone()]);
    }
    let cfg = ExecConfig {
        timestep_ms: MIN,
        // Deterministic budgets: μ·n repair steps per cycle, 40·n per replanning attempt (the mission clock
        // stands still while the planner runs, so these bound the experiment's cost).
        repair_max_steps: Some(repair_steps),
        replan_slack_ms: MIN,
        dispatch: policy,
        ..ExecConfig::default()
    };
    let problem_goals: Vec<String> = p
        .plan
        .problem()
        .goals
        .iter()
        .map(|g| g.name.clone())
        .collect();
    let mut ex = Executive::new(p.plan.clone(), cfg).with_mapping(p.mapping.clone());
    let opts = MissionOptions {
        time_limit_ms: p.model.horizon_ms + MIN,
        ..MissionOptions::default()
    };
    let report = run_mission(&mut ex, &mut v, &mut KinematicPacer, &opts, &mut |_, _| {});
    outcome(&report, &ex, &uploads, &v.log, &problem_goals)
}

/// The totals of one scenario under one policy over all seeds.
#[derive(Clone, Debug, Serialize)]
pub struct Row {
    pub scenario: String,
    pub policy: String,
    pub seeds: u64,
    pub arrived: u64,
    pub achieved: u64,
    pub rejected: u64,
    pub rejected_reasons: BTreeMap<String, u64>,
    pub pending: u64,
    /// Mean time from upload to achievement over the achieved goals, minutes.
    pub mean_time_to_achieve_min: Option<f64>,
    /// Per mission, means.
    pub idle_h: f64,
    pub distance_km: f64,
    pub wasted_km: f64,
    pub replans: f64,
    pub repairs: f64,
    /// The problem file's own goals (e.g. the apple, home by 20:00), achieved / all, over all seeds.
    pub mission_goals_achieved: u64,
    pub mission_goals: u64,
}

impl Row {
    fn new(scenario: &str, policy: PolicyKind, outcomes: &[MissionOutcome]) -> Row {
        let n = outcomes.len().max(1) as f64;
        let sum = |f: &dyn Fn(&MissionOutcome) -> f64| outcomes.iter().map(f).sum::<f64>();
        let mut reasons = BTreeMap::new();
        for o in outcomes {
            for (k, v) in &o.rejected {
                *reasons.entry(k.clone()).or_insert(0) += v;
            }
        }
        let times: Vec<Time> = outcomes
            .iter()
            .flat_map(|o| o.time_to_achieve_ms.clone())
            .collect();
        Row {
            scenario: scenario.into(),
            policy: policy.to_string(),
            seeds: outcomes.len() as u64,
            arrived: outcomes.iter().map(|o| o.arrived).sum(),
            achieved: outcomes.iter().map(|o| o.achieved).sum(),
            rejected: reasons.values().sum(),
            rejected_reasons: reasons,
            pending: outcomes.iter().map(|o| o.pending).sum(),
            mean_time_to_achieve_min: (!times.is_empty())
                .then(|| times.iter().sum::<Time>() as f64 / times.len() as f64 / MIN as f64),
            idle_h: sum(&|o| o.idle_ms as f64) / n / HOUR as f64,
            distance_km: sum(&|o| o.distance_m) / n / 1000.0,
            wasted_km: sum(&|o| o.wasted_m) / n / 1000.0,
            replans: sum(&|o| o.replans as f64) / n,
            repairs: sum(&|o| o.repairs as f64) / n,
            mission_goals_achieved: outcomes.iter().map(|o| o.mission_goals_achieved).sum(),
            mission_goals: outcomes.iter().map(|o| o.mission_goals).sum(),
        }
    }
}

/// What to run.
#[derive(Clone, Debug)]
pub struct ExperimentOptions {
    pub seeds: u64,
    pub first_seed: u64,
    pub policies: Vec<PolicyKind>,
    /// Scenario names (all when empty).
    pub scenarios: Vec<String>,
    /// Mean goals uploaded per hour.
    pub per_hour: f64,
    /// The executive's deterministic planning budget n (ExecConfig::repair_max_steps).
    pub repair_steps: u64,
}

impl Default for ExperimentOptions {
    fn default() -> Self {
        ExperimentOptions {
            seeds: 20,
            first_seed: 1,
            policies: vec![
                PolicyKind::Earliest,
                PolicyKind::Latest,
                PolicyKind::GoalDriven(crate::dispatch::SupportForm::Marking),
            ],
            scenarios: Vec::new(),
            per_hour: 0.4,
            repair_steps: 10,
        }
    }
}

/// Runs every scenario under every policy for every seed; `progress(done, total)` after each mission.
pub fn run(
    opts: &ExperimentOptions,
    progress: &mut dyn FnMut(u64, u64),
) -> Result<Vec<Row>, ExperimentError> {
    let specs: Vec<Spec> = specs()
        .into_iter()
        .filter(|s| opts.scenarios.is_empty() || opts.scenarios.iter().any(|n| n == s.name))
        .collect();
    let prepared = specs
        .iter()
        .map(|s| prepare(s, opts.per_hour))
        .collect::<Result<Vec<_>, _>>()?;
    let total = prepared.len() as u64 * opts.policies.len() as u64 * opts.seeds;
    let mut done = 0;
    let mut rows = Vec::new();
    for p in &prepared {
        for &policy in &opts.policies {
            let mut outcomes = Vec::new();
            for seed in opts.first_seed..opts.first_seed + opts.seeds {
                outcomes.push(run_one(p, policy, seed, opts.repair_steps));
                done += 1;
                progress(done, total);
            }
            rows.push(Row::new(&p.name, policy, &outcomes));
        }
    }
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn idle_time_is_the_complement_of_the_union_of_busy_spans() {
        let d = |s: u64, e: u64| Done {
            task: "x".into(),
            start_ms: s,
            end_ms: e,
            leg: None,
        };
        assert_eq!(idle(&[d(10, 20), d(15, 30), d(50, 60)], 100), 100 - 30);
        assert_eq!(idle(&[], 100), 100);
    }

    #[test]
    fn wasted_travel_is_a_leg_driven_straight_back() {
        let leg = |a: &str, b: &str, m: f64| Done {
            task: "go".into(),
            start_ms: 0,
            end_ms: 1,
            leg: Some((a.into(), b.into(), m)),
        };
        let buy = Done {
            task: "buy".into(),
            start_ms: 0,
            end_ms: 1,
            leg: None,
        };
        assert_eq!(wasted(&[leg("h", "c", 5.0), leg("c", "h", 5.0)]), 10.0);
        assert_eq!(wasted(&[leg("h", "c", 5.0), buy, leg("c", "h", 5.0)]), 0.0);
        assert_eq!(wasted(&[leg("h", "c", 5.0), leg("c", "g", 5.0)]), 0.0);
        let there_and_back_twice = [leg("h", "c", 5.0), leg("c", "h", 5.0), leg("h", "c", 5.0)];
        assert_eq!(wasted(&there_and_back_twice), 10.0);
    }
}
