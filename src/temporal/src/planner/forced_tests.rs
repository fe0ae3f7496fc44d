//! The forced-conflict pass ([`select::propagate_forced`]) against the pass it replaced: every live
//! threat and unary conflict listed first (each verdict asked), then each one's resolvers counted and a
//! forced one applied, re-checked once something was. The new pass asks a conflict's resolvers first and
//! its verdict only when fewer than two remain; the plans they leave must be the same.

use std::sync::Arc;

use super::resolvers::resolvers_below;
use super::select::{self, apply_forced, forward_check_statics, Order};
use super::Search;
use crate::plan::{Flaw, PartialPlan, PlanError, ThreatCheck};

/// The pass before it asked resolvers first.
fn propagate_forced_reference(
    plan: &mut PartialPlan,
    h: &super::hierarchy::Hierarchy,
    order: Order,
) -> Result<(), PlanError> {
    let mut applied = false;
    for (event, link) in plan.live_threats() {
        if applied && plan.check_threat(event, link) != ThreatCheck::Threat {
            continue;
        }
        applied |= apply_listed(plan, &Flaw::Threat { event, link })?;
    }
    let mut applied = false;
    for (a, b) in plan.live_unary_conflicts() {
        if applied && plan.check_unary(a, b) != Some(true) {
            continue;
        }
        applied |= apply_listed(plan, &Flaw::UnaryConflict { a, b })?;
    }
    forward_check_statics(plan, h, order)
}

/// Applies a listed conflict's resolver if it is forced; whether it was.
fn apply_listed(plan: &mut PartialPlan, f: &Flaw) -> Result<bool, PlanError> {
    let Some(rs) = resolvers_below(plan, f, 2) else {
        return Ok(false);
    };
    let forced = matches!(rs.as_slice(), [r] if !r.inserts());
    apply_forced(plan, f, &rs).map(|()| forced)
}

/// What the pass leaves: its outcome, the network's constraints and the flaws.
fn after_pass(plan: &mut PartialPlan, outcome: Result<(), PlanError>) -> String {
    let constraints: Vec<_> = plan.stn.constraints().collect();
    format!("{outcome:?}\n{constraints:?}\n{:?}", plan.flaws())
}

/// On generated rover grids, the shipped problems and a grid with too short a horizon, at every step of the search, each resolver of the
/// selected flaw applied and followed by either pass leaves the same plan (or the same dead end).
#[test]
fn forced_pass_equals_the_listing_pass() {
    let (rover, mut problems) = super::test_problems::rover_problems();
    // A horizon too short for every tour: forced orderings that contradict each other (dead ends).
    let tight = crate::lang::generate::rover_grid_problem(6).replace("horizon 6h", "horizon 2min");
    problems.push(crate::lang::parse_problem("tight", &tight, &rover).expect("tight problem"));
    let (mut applied, mut dead_ends) = (0, 0);
    for p in problems {
        let steps = if p.name == "tight" { 300 } else { 2_000 };
        let root = PartialPlan::new(rover.clone(), Arc::new(p)).expect("root plan");
        let mut search = Search::new(root);
        for _ in 0..steps {
            if !search.stack.is_empty() {
                let h = &search.hierarchy;
                let mut probe = search.plan.clone();
                let resolvers = select::pick(&mut probe, h, Order::Hierarchy)
                    .map(|(_, rs)| rs)
                    .unwrap_or_default();
                for r in &resolvers {
                    let mut new = search.plan.clone();
                    if super::resolvers::apply(&mut new, r).is_err() {
                        continue;
                    }
                    let mut old = new.clone();
                    let before = new.stn.constraints().count();
                    let outcome = select::propagate_forced(&mut new, h, Order::Hierarchy);
                    let reference = propagate_forced_reference(&mut old, h, Order::Hierarchy);
                    match &outcome {
                        Ok(()) if new.stn.constraints().count() > before => applied += 1,
                        Err(_) => dead_ends += 1,
                        Ok(()) => {}
                    }
                    assert_eq!(
                        after_pass(&mut new, outcome),
                        after_pass(&mut old, reference)
                    );
                }
            }
            if search.step() != super::StepOutcome::Progress {
                break;
            }
        }
    }
    // The comparison saw forced orderings applied and dead ends found.
    assert!(applied > 50, "{applied} passes applied a forced resolver");
    assert!(dead_ends > 0, "{dead_ends} passes found a dead end");
}
