//! The IxTeT planner (seed 1 §2.2, §3.4): ordered depth-first search in the space of partial plans, one
//! *planning step* at a time, with backtracking on the plan's trail.
//!
//! A step selects a flaw ([`select`]), computes its resolvers in order ([`resolvers`]) and applies the first
//! that keeps the networks consistent; when none does, the search backtracks to the previous choice point and
//! applies its next resolver. The search state (the plan and the stack of choice points) persists between
//! steps, so the executive can plan until its deadline and resume in the next cycle (§3.2) — or keep the
//! tree across cycles when nothing changed. The root of a search is whatever plan it is given: a problem's
//! root plan for planning, the partially executed *ExecutingPlan* for plan repair (§3.4).

mod controllability;
pub mod forward;
pub mod hierarchy;
pub mod reachability;
pub mod resolvers;
pub mod select;

use std::time::Instant;

use crate::plan::{ActionId, Flaw, PartialPlan, PlanLevel};
pub use controllability::DcMode;
pub use resolvers::Resolver;

/// Why the search stopped without a plan.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum FailReason {
    /// A flaw of the root plan has no (applicable) resolver: no plan exists from this root.
    #[error("no resolver for the root flaw: {flaw}")]
    NoResolver { flaw: String },
    /// Every branch was explored.
    #[error("search exhausted after {steps} steps")]
    Exhausted { steps: u64 },
    /// Every branch within the bound on same-task regressions failed, and the search was built not to
    /// deepen it ([`Search::bounded_regress`]): not a proof that no plan exists.
    #[error("every way within {limit} repeated insertions fails ({steps} steps)")]
    Bounded { steps: u64, limit: u32 },
    /// The budget (time or steps) ran out; the search can be resumed.
    #[error("deadline reached after {steps} steps")]
    Deadline { steps: u64 },
    /// Every branch was explored and the plans found were not dynamically controllable
    /// ([`DcMode::Require`]); `reason` is the last one's.
    #[error("no dynamically controllable plan after {steps} steps; the last plan found: {reason}")]
    NotControllable { steps: u64, reason: String },
}

/// What a planning step achieved.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum StepOutcome {
    /// The current plan has no flaw.
    Solved,
    /// A resolver was applied (possibly after backtracking).
    Progress,
    Failed(FailReason),
}

/// How long [`Search::run`] may go on.
#[derive(Copy, Clone, Debug, Default)]
pub struct Budget {
    pub max_steps: Option<u64>,
    pub deadline: Option<Instant>,
}

impl Budget {
    pub fn steps(n: u64) -> Self {
        Budget {
            max_steps: Some(n),
            deadline: None,
        }
    }
}

/// A choice point: the plan before the choice, the flaw, its resolvers and the next one to try.
#[derive(Clone, Debug)]
struct Choice {
    level: PlanLevel,
    flaw: Flaw,
    resolvers: Vec<Resolver>,
    next: usize,
    applied_any: bool,
    /// Discrepancies taken on the branch above this choice (see [`Search`]'s iterations).
    discrepancies: u32,
}

#[derive(Clone, Debug, PartialEq, Eq)]
enum Status {
    Running,
    Solved,
    Failed(FailReason),
}

/// A resumable plan-space search.
#[derive(Clone, Debug)]
pub struct Search {
    plan: PartialPlan,
    stack: Vec<Choice>,
    steps: u64,
    backtracks: u64,
    status: Status,
    hierarchy: hierarchy::Hierarchy,
    /// The next step's selection when [`Search::next_is_backtrack`] or [`Search::next_is_solution`] already
    /// made it (`Some(None)`: no flaw left); valid until the plan changes.
    peeked: Option<Option<(Flaw, Vec<Resolver>)>>,
    /// Limited discrepancy search: a branch may depart from the resolver order at most this many times
    /// in the current iteration; when the tree so limited is exhausted and some resolver was left out for
    /// the limit, the search starts again from the root with one more. Depth-first search alone drowns in
    /// the subtree of one early wrong choice; this visits every resolver order in the end (complete).
    discrepancy_limit: u32,
    /// Whether the current iteration left a resolver out for the limit.
    cut: bool,
    /// Why the last resolver rejected was rejected, or the last flaw found without any (for explaining a
    /// failure: [`reachability`]).
    last_rejection: Option<String>,
    /// The last step stopped backtracking after [`MAX_REJECTED_PER_STEP`] rejected resolvers: the next
    /// step goes on with it instead of selecting a flaw.
    resume: bool,
    /// The order of the open conditions ([`select::Order`]).
    order: select::Order,
    /// What a solution's dynamic controllability decides ([`DcMode`]).
    dc: DcMode,
    /// Why the last plan found was not dynamically controllable (`None`: it was, or none found yet).
    not_dc: Option<crate::plan::NotControllable>,
    /// Whether a tree exhausted against the regression bound is searched again with a deeper bound
    /// (complete), or ends in [`FailReason::Bounded`] (the executive's repairs, whose budgets are counted
    /// in steps and cycles: deepening there turns a quick failure into a search to the step cap).
    deepen_regress: bool,
}

/// Resolvers a planning step may try and see rejected before it returns, its backtracking resumed by the
/// next step. Without it one step could back up through a deep branch trying thousands of resolvers, each
/// costing a propagation, unseen by every step budget (a plan repair's cycle, a replanning's cap).
pub const MAX_REJECTED_PER_STEP: u32 = 32;

/// Largest root network (timepoints) whose matrix of paths a search builds ([`crate::stn::paths`]); the
/// matrix then grows with the plan up to [`crate::stn::paths::MAX_TIMEPOINTS`].
pub const PATHS_ROOT_MAX: usize = 256;

impl Search {
    /// A search whose root is `plan` (the incremental flaw detection is rebuilt from scratch).
    pub fn new(mut plan: PartialPlan) -> Self {
        plan.recompute_candidates();
        // Ordering queries by look-up rather than by search (the answers are the same). Built from the
        // root's network in one Dijkstra per timepoint: a large executing plan's repair, whose tree is
        // rebuilt every cycle, keeps its searches.
        if plan.stn.num_timepoints() <= PATHS_ROOT_MAX {
            plan.stn.maintain_paths();
        }
        let hierarchy = hierarchy::Hierarchy::new(&plan.domain);
        Search {
            hierarchy,
            peeked: None,
            plan,
            stack: Vec::new(),
            steps: 0,
            backtracks: 0,
            status: Status::Running,
            discrepancy_limit: 0,
            cut: false,
            last_rejection: None,
            resume: false,
            order: select::Order::default(),
            dc: DcMode::default(),
            not_dc: None,
            deepen_regress: true,
        }
    }

    /// This search does not deepen the regression bound: a tree exhausted against it fails with
    /// [`FailReason::Bounded`] instead of starting again.
    pub fn bounded_regress(mut self) -> Self {
        self.deepen_regress = false;
        self
    }

    /// A search whose root is `plan` that takes the open conditions in `order`.
    pub fn with_order(plan: PartialPlan, order: select::Order) -> Self {
        Search {
            order,
            ..Search::new(plan)
        }
    }

    /// A search whose root is `plan` that never leaves a resolver out: plain chronological depth-first
    /// search (seed 1's), for comparisons and for tests of the order of its steps.
    pub fn depth_first(plan: PartialPlan) -> Self {
        Search {
            discrepancy_limit: u32::MAX,
            ..Search::new(plan)
        }
    }

    /// The current iteration's discrepancy limit (0 in the first, heuristic-only, dive).
    pub fn discrepancy_limit(&self) -> u32 {
        self.discrepancy_limit
    }

    /// Discrepancies taken above a choice pushed now: those of the top choice, plus one if the resolver it
    /// applied was not its first.
    fn next_discrepancies(&self) -> u32 {
        self.stack
            .last()
            .map_or(0, |c| c.discrepancies + u32::from(c.next > 1))
    }

    /// The current node's partial plan.
    pub fn plan(&self) -> &PartialPlan {
        &self.plan
    }

    /// The current plan, mutably (for queries that update the detection caches; changes made through it
    /// become part of the current node).
    pub fn plan_mut(&mut self) -> &mut PartialPlan {
        self.peeked = None;
        &mut self.plan
    }

    pub fn into_plan(self) -> PartialPlan {
        self.plan
    }

    /// Why the last resolver the search rejected was rejected (or the last flaw it found without any).
    pub fn last_rejection(&self) -> Option<&str> {
        self.last_rejection.as_deref()
    }

    /// Planning steps done.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// Backtracks done.
    pub fn backtracks(&self) -> u64 {
        self.backtracks
    }

    /// Number of choices on the current branch.
    pub fn depth(&self) -> usize {
        self.stack.len()
    }

    /// Whether the current node's plan is *executable* (Definition 5) given the running actions.
    pub fn executable(&mut self, running: &[ActionId]) -> bool {
        self.plan.executable(running)
    }

    /// Whether the next planning step is a backtrack: none of the resolvers of the flaw it will select
    /// can be applied (seed 1 §3.6: when the time limit l is reached, planning is pursued if the next step is a backtrack
    /// and it increases l). The selection is kept for that next step.
    pub fn next_is_backtrack(&mut self) -> bool {
        if self.resume && self.status == Status::Running {
            return true;
        }
        if !self.peek() {
            return false;
        }
        let Some(Some((_, rs))) = &self.peeked else {
            return false;
        };
        // A dead end shows only when each resolver is tried (the propagation of forced conflicts is part
        // of a step): try them on the trail and undo. Only those the discrepancy limit allows count.
        let allowed = if self.next_discrepancies() < self.discrepancy_limit {
            rs.len()
        } else {
            1
        };
        for r in rs.iter().take(allowed).cloned().collect::<Vec<_>>() {
            let level = self.plan.save();
            let ok = resolvers::apply(&mut self.plan, &r)
                .and_then(|()| {
                    select::propagate_forced(&mut self.plan, &self.hierarchy, self.order)
                })
                .is_ok();
            self.plan.restore(level);
            if ok {
                return false;
            }
        }
        true
    }

    /// Whether the next step only finds that the current plan has no flaw left (it returns `Solved`
    /// without planning). The selection is kept for that next step.
    pub fn next_is_solution(&mut self) -> bool {
        if self.status == Status::Solved {
            return true;
        }
        !self.resume && self.peek() && matches!(self.peeked, Some(None)) && self.solution_admitted()
    }

    /// Makes the next step's selection once (kept in `peeked`); false when the search is over or the
    /// selection failed the search.
    fn peek(&mut self) -> bool {
        if self.status != Status::Running {
            return false;
        }
        if self.peeked.is_none() {
            match self.select() {
                Ok(p) => self.peeked = Some(p),
                Err(_) => return false,
            }
        }
        true
    }

    /// Selects the next flaw; at the root, first applies its forced conflicts (later nodes propagate them
    /// when a resolver is applied). A root conflict without resolver fails the search.
    fn select(&mut self) -> Result<Option<(Flaw, Vec<Resolver>)>, FailReason> {
        if self.stack.is_empty() {
            if let Err(e) = select::propagate_forced(&mut self.plan, &self.hierarchy, self.order) {
                let r = FailReason::NoResolver {
                    flaw: e.to_string(),
                };
                self.status = Status::Failed(r.clone());
                return Err(r);
            }
        }
        Ok(select::pick(&mut self.plan, &self.hierarchy, self.order))
    }

    /// One planning step.
    pub fn step(&mut self) -> StepOutcome {
        match &self.status {
            Status::Solved => return StepOutcome::Solved,
            Status::Failed(r) => return StepOutcome::Failed(r.clone()),
            Status::Running => {}
        }
        self.steps += 1;
        if std::mem::take(&mut self.resume) {
            let out = self.advance();
            return self.no_dc_plan(out);
        }
        let picked = match self.peeked.take() {
            Some(p) => p,
            None => match self.select() {
                Ok(p) => p,
                Err(r) => return StepOutcome::Failed(r),
            },
        };
        match picked {
            None if !self.admit_solution() => {
                let out = self.advance();
                self.no_dc_plan(out)
            }
            None => {
                self.status = Status::Solved;
                tracing::debug!(steps = self.steps, "plan found");
                StepOutcome::Solved
            }
            Some((flaw, resolvers)) => {
                tracing::trace!(flaw = %self.plan.flaw_text(&flaw), resolvers = ?resolvers, "step");
                let level = self.plan.save();
                let discrepancies = self.next_discrepancies();
                self.stack.push(Choice {
                    level,
                    flaw,
                    resolvers,
                    next: 0,
                    applied_any: false,
                    discrepancies,
                });
                let out = self.advance();
                self.no_dc_plan(out)
            }
        }
    }

    /// Applies the next applicable resolver of the top choice, backtracking as needed.
    fn advance(&mut self) -> StepOutcome {
        let mut rejected = 0;
        loop {
            let Some(top) = self.stack.last_mut() else {
                let r = FailReason::Exhausted { steps: self.steps };
                self.status = Status::Failed(r.clone());
                return StepOutcome::Failed(r);
            };
            let level = top.level;
            // Any resolver but the first departs from the order: allowed within the iteration's limit.
            let within = top.next == 0 || top.discrepancies < self.discrepancy_limit;
            if top.next < top.resolvers.len() && !within {
                self.cut = true;
            }
            if top.next < top.resolvers.len() && within {
                let r = top.resolvers[top.next].clone();
                top.next += 1;
                self.plan.restore(level);
                match resolvers::apply(&mut self.plan, &r).and_then(|()| {
                    select::propagate_forced(&mut self.plan, &self.hierarchy, self.order)
                }) {
                    Ok(()) => {
                        if let Some(top) = self.stack.last_mut() {
                            top.applied_any = true;
                        }
                        return StepOutcome::Progress;
                    }
                    Err(e) => {
                        tracing::trace!(resolver = ?r, error = %e, "resolver rejected");
                        self.plan.restore(level);
                        if let Some(top) = self.stack.last() {
                            self.last_rejection = Some(format!(
                                "{} for {}: {e}",
                                r.text(&self.plan),
                                self.plan.flaw_text(&top.flaw)
                            ));
                        }
                        rejected += 1;
                        if rejected >= MAX_REJECTED_PER_STEP {
                            // The node is the top choice's, no resolver applied: the next step resumes.
                            self.resume = true;
                            return StepOutcome::Progress;
                        }
                    }
                }
            } else {
                let Some(top) = self.stack.pop() else {
                    continue;
                };
                self.plan.restore(top.level);
                self.backtracks += 1;
                if top.resolvers.is_empty() {
                    self.last_rejection = Some(format!(
                        "no resolver for {}",
                        self.plan.flaw_text(&top.flaw)
                    ));
                }
                if self.stack.is_empty() && self.cut {
                    // The limited tree is exhausted: the next iteration, from the root.
                    self.cut = false;
                    self.discrepancy_limit = self.discrepancy_limit.saturating_add(1);
                    self.peeked = None;
                    tracing::debug!(limit = self.discrepancy_limit, "discrepancy iteration");
                    return StepOutcome::Progress;
                }
                if self.stack.is_empty() && self.plan.regress.cut.replace(false) {
                    if !self.deepen_regress {
                        let r = FailReason::Bounded {
                            steps: self.steps,
                            limit: self.plan.regress.limit,
                        };
                        self.status = Status::Failed(r.clone());
                        return StepOutcome::Failed(r);
                    }
                    // Exhausted within the regression bound only: again, from the root, deeper.
                    self.plan.regress.limit = self.plan.regress.limit.saturating_mul(2);
                    self.peeked = None;
                    tracing::debug!(limit = self.plan.regress.limit, "regression bound deepened");
                    return StepOutcome::Progress;
                }
                if self.stack.is_empty() {
                    let r = if top.applied_any {
                        FailReason::Exhausted { steps: self.steps }
                    } else {
                        FailReason::NoResolver {
                            flaw: self.plan.flaw_text(&top.flaw),
                        }
                    };
                    self.status = Status::Failed(r.clone());
                    return StepOutcome::Failed(r);
                }
            }
        }
    }

    /// Steps until solved, failed, or the budget runs out (then `Failed(Deadline)`; the search can resume).
    pub fn run(&mut self, budget: Budget) -> StepOutcome {
        let start = self.steps;
        loop {
            if budget.max_steps.is_some_and(|n| self.steps - start >= n)
                || budget.deadline.is_some_and(|d| Instant::now() >= d)
            {
                return StepOutcome::Failed(FailReason::Deadline { steps: self.steps });
            }
            match self.step() {
                StepOutcome::Progress => {}
                other => return other,
            }
        }
    }
}

/// A plan found by [`solve`], with the search's figures.
#[derive(Clone, Debug)]
pub struct Planned {
    pub plan: PartialPlan,
    pub steps: u64,
    pub backtracks: u64,
    /// Why the plan is not dynamically controllable (`None`: it is; docs/stnu.md).
    pub not_controllable: Option<crate::plan::NotControllable>,
}

/// Why [`solve`] found no plan.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum PlanFailure {
    /// The root plan could not be built (e.g. a goal window outside the horizon).
    #[error("invalid problem: {0}")]
    Root(String),
    /// A goal no plan achieves, found before the search ([`reachability`]).
    #[error(transparent)]
    Unreachable(#[from] reachability::Unreachable),
    #[error(transparent)]
    Search(#[from] FailReason),
}

/// Plans `problem` from scratch within `budget`, after refusing at once a goal that cannot be achieved
/// even alone ([`reachability`]).
pub fn solve(
    domain: std::sync::Arc<crate::model::Domain>,
    problem: std::sync::Arc<crate::model::Problem>,
    budget: Budget,
) -> Result<Planned, PlanFailure> {
    solve_dc(domain, problem, budget, DcMode::default())
}

/// [`solve`] with what a solution's dynamic controllability decides ([`DcMode`]).
pub fn solve_dc(
    domain: std::sync::Arc<crate::model::Domain>,
    problem: std::sync::Arc<crate::model::Problem>,
    budget: Budget,
    dc: DcMode,
) -> Result<Planned, PlanFailure> {
    let root = checked_root(domain, problem)?;
    let mut search = Search::new(root);
    search.set_dc_mode(dc);
    finish(search.run(budget), search)
}

/// The root plan of `problem`, refused at once when a goal cannot be achieved even alone.
fn checked_root(
    domain: std::sync::Arc<crate::model::Domain>,
    problem: std::sync::Arc<crate::model::Problem>,
) -> Result<PartialPlan, PlanFailure> {
    let root = PartialPlan::new(domain, problem).map_err(|e| PlanFailure::Root(e.to_string()))?;
    match reachability::unreachable_goals(&root, reachability::STEPS_PER_GOAL)
        .into_iter()
        .next()
    {
        Some(u) => Err(u.into()),
        None => Ok(root),
    }
}

fn finish(outcome: StepOutcome, search: Search) -> Result<Planned, PlanFailure> {
    match outcome {
        StepOutcome::Solved => Ok(Planned {
            steps: search.steps(),
            backtracks: search.backtracks(),
            not_controllable: search.not_controllable().cloned(),
            plan: search.into_plan(),
        }),
        StepOutcome::Failed(r) => Err(r.into()),
        StepOutcome::Progress => Err(FailReason::Deadline {
            steps: search.steps(),
        }
        .into()),
    }
}

/// Steps the first portfolio slice gives each search; each round doubles it.
const FIRST_SLICE: u64 = 500;

/// The time [`solve_portfolio_with`]'s other search gets in the first round (then as long as the POCL
/// searches took in the previous round).
const FIRST_OTHER_SHARE: std::time::Duration = std::time::Duration::from_millis(50);

/// [`solve`] by two searches run in turn, in slices of steps that double each round: one takes the open
/// conditions by the hierarchy ([`select::Order::Hierarchy`]), the other takes the static choices last
/// ([`select::Order::StaticChoicesLast`]). Neither order wins everywhere (binding a place by the first fact
/// that fits, or by where the vehicle already is), and a search that takes the wrong one drowns in a
/// subtree the other never enters; interleaving costs at most about twice the better of the two. The
/// first plan found is returned.
pub fn solve_portfolio(
    domain: std::sync::Arc<crate::model::Domain>,
    problem: std::sync::Arc<crate::model::Problem>,
    budget: Budget,
) -> Result<Planned, PlanFailure> {
    solve_portfolio_with(domain, problem, budget, &mut |_, _| Err(0))
}

/// [`solve_portfolio`] with a third search given its slice first in each round: `other(steps, time)` runs
/// for about as long as the POCL searches took in the previous round (`time`; their steps and the other
/// search's are too different in cost to share steps), within `steps`, and returns a plan if it found
/// one, else the steps it took (the forward search of a PDDL problem, [`forward`]). Only the POCL searches, complete, can end the portfolio without a plan.
///
/// Its first slice comes before the root's reachability analysis ([`checked_root`]): a plan it finds
/// there needs none, and on wide problems (Depots: a POCL search per goal) the analysis alone takes
/// longer than the forward search's plan.
pub fn solve_portfolio_with(
    domain: std::sync::Arc<crate::model::Domain>,
    problem: std::sync::Arc<crate::model::Problem>,
    budget: Budget,
    other: &mut dyn FnMut(u64, std::time::Duration) -> Result<Planned, u64>,
) -> Result<Planned, PlanFailure> {
    let mut steps = 0u64;
    let mut share = FIRST_OTHER_SHARE;
    let mut other_slice = |steps: &mut u64, share: std::time::Duration| {
        let left = budget.max_steps.map(|m| m.saturating_sub(*steps));
        if left == Some(0) || budget.deadline.is_some_and(|d| Instant::now() >= d) {
            return None;
        }
        match other(left.unwrap_or(u64::MAX), share) {
            Ok(p) => Some(p),
            Err(used) => {
                *steps += used;
                None
            }
        }
    };
    if let Some(p) = other_slice(&mut steps, share) {
        return Ok(p);
    }
    let root = checked_root(domain, problem)?;
    let mut searches = [
        Search::with_order(root.clone(), select::Order::Hierarchy),
        Search::with_order(root, select::Order::StaticChoicesLast),
    ];
    let mut slice = FIRST_SLICE;
    loop {
        let round = Instant::now();
        for search in &mut searches {
            let left = budget.max_steps.map(|m| m.saturating_sub(steps));
            if left == Some(0) || budget.deadline.is_some_and(|d| Instant::now() >= d) {
                return Err(FailReason::Deadline { steps }.into());
            }
            let part = Budget {
                max_steps: Some(left.map_or(slice, |l| l.min(slice))),
                deadline: budget.deadline,
            };
            let before = search.steps();
            let outcome = search.run(part);
            steps += search.steps() - before;
            match outcome {
                StepOutcome::Solved => return finish(outcome, search.clone()),
                StepOutcome::Failed(FailReason::Deadline { .. }) | StepOutcome::Progress => {}
                // Exhausted or no resolver at the root: the search is complete, every order agrees.
                StepOutcome::Failed(r) => return Err(r.into()),
            }
        }
        slice = slice.saturating_mul(2);
        share = share.max(round.elapsed());
        if let Some(p) = other_slice(&mut steps, share) {
            return Ok(p);
        }
    }
}
