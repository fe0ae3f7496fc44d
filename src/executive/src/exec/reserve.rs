//! A resource margin a declared fault would exhaust is not accepted silently (issue 31, seed 62288516: a
//! goal upload left the battery a 0.87 % margin; a 42 % drop was noticed only at "Battery exhausted").
//! When a plan is adopted — a goal inserted, a complete replanning — the lowest level it may leave each
//! resource of `[exec.reserve]` is compared with the fault size declared for it; below it, the trace (and
//! so the operator's output) says so. A warning, not a reservation: the plan is kept.

use super::executive::Executive;
use super::trace::TraceEvent;
use mavtempo_temporal::model::ResourceId;
use mavtempo_temporal::plan::{PartialPlan, UsageKind};

/// The lowest level `r` may reach over `plan` from the aggregated past level `past`: consumptions as early
/// as they may come, productions as late (the pessimistic order).
pub fn lowest_level(plan: &PartialPlan, r: ResourceId, past: f64) -> f64 {
    let mut changes: Vec<(i64, f64)> = Vec::new();
    for &u in plan.usages_of(r) {
        let us = plan.usage(u);
        if plan.action(us.action).removed {
            continue;
        }
        let (qlo, qhi) = plan.numeric().term(us.quantity);
        match us.kind {
            UsageKind::Produce { at } => changes.push((plan.latest(at), qlo)),
            UsageKind::Consume { at } => changes.push((plan.earliest(at), -qhi)),
            _ => {}
        }
    }
    changes.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
    let capacity = plan.domain().resource(r).capacity;
    let mut level = past;
    let mut lowest = past;
    for (_, d) in changes {
        level = (level + d).min(capacity);
        lowest = lowest.min(level);
    }
    lowest
}

impl Executive {
    /// Warns (in the trace) of each reserved resource the plan may bring below its declared fault size.
    pub(crate) fn check_reserves(&mut self) {
        let reserves: Vec<(String, f64)> = self
            .cfg
            .reserve
            .iter()
            .map(|(k, v)| (k.clone(), *v))
            .collect();
        for (name, reserve) in reserves {
            let Some(r) = self.resource(&name) else {
                continue;
            };
            let past = self.ledger.past(r).0;
            let lowest = lowest_level(&self.plan, r, past);
            if lowest < reserve {
                tracing::warn!(resource = %name, lowest, reserve, "plan margin below the declared fault size");
                self.trace(TraceEvent::ReserveShort {
                    resource: name,
                    lowest,
                    reserve,
                });
            }
        }
    }
}
