//! A tiny domain built as model structs: a robot goes between places (speed in [0.5, 2] m/s) and snaps
//! pictures (unary camera, a storage of 2 free slots); `calibrate` also borrows the camera.

use mavtempo_temporal::model::{
    Binding, Domain, Event, Fact, Goal, GoalOrigin, Hold, LogicalAttr, NumConstraint, NumInterval,
    NumTerm, NumVar, NumVarId, Object, Position, Preemption, Problem, ResourceAttr, ResourceKind,
    ResourceUsage, SymVar, SymVarId, Task, TemporalConstraint, Term, TimeInterval, TpId, TypeKind,
    UsageKind, Value,
};
use mavtempo_temporal::plan::solution::{Consumer, Establisher, PlanActionId, PlanTp, Solution};

use super::builder::Builder;

pub const PLACES: [&str; 3] = ["a", "b", "c"];
pub const HORIZON: i64 = 120_000;
const ST: TpId = TpId(0);
const ET: TpId = TpId(1);

fn task(name: &str, sym_vars: Vec<SymVar>, n_params: usize) -> Task {
    Task {
        name: name.into(),
        sym_vars,
        n_params,
        num_vars: vec![],
        timepoints: vec!["st".into(), "et".into()],
        start: ST,
        end: ET,
        events: vec![],
        holds: vec![],
        usages: vec![],
        temporal: vec![],
        bindings: vec![],
        numeric: vec![],
        preemption: Preemption::NonPreemptive,
        contingent: false,
        line: None,
    }
}

pub fn domain() -> Domain {
    let mut d = Domain::new("tiny");
    let loc = d.add_type("loc", TypeKind::Object);
    let at = d.add_attr(LogicalAttr {
        name: "AT".into(),
        params: vec![],
        value_type: loc,
        line: None,
    });
    let seen = d.add_attr(LogicalAttr {
        name: "SEEN".into(),
        params: vec![("l".into(), loc)],
        value_type: Domain::BOOL,
        line: None,
    });
    let cam = d.add_resource(ResourceAttr {
        name: "CAM".into(),
        kind: ResourceKind::Unary,
        capacity: 1.0,
        line: None,
    });
    let store = d.add_resource(ResourceAttr {
        name: "STORE".into(),
        kind: ResourceKind::Reservoir,
        capacity: 2.0,
        line: None,
    });
    let var = |name: &str| SymVar {
        name: name.into(),
        ty: loc,
    };
    let (from, to) = (Term::Var(SymVarId(0)), Term::Var(SymVarId(1)));
    let (speed, dist, dur) = (NumVarId(0), NumVarId(1), NumVarId(2));

    // go(?from, ?to): AT is +oo while moving; ?dist = ?speed * ?duration, ?speed in [0.5, 2].
    let mut go = task("go", vec![var("from"), var("to")], 2);
    go.events = vec![
        Event {
            attr: at,
            args: vec![],
            from,
            to: Term::Unknown,
            at: ST,
            primary: true,
        },
        Event {
            attr: at,
            args: vec![],
            from: Term::Unknown,
            to,
            at: ET,
            primary: true,
        },
    ];
    go.holds = vec![Hold {
        attr: at,
        args: vec![],
        value: Term::Unknown,
        from: ST,
        to: ET,
    }];
    go.temporal = vec![TemporalConstraint {
        from: ST,
        to: ET,
        interval: TimeInterval::closed(5_000, 20_000),
    }];
    go.bindings = vec![Binding::Ne(from, to)];
    go.num_vars = vec![
        NumVar {
            name: "speed".into(),
            domain: NumInterval::closed(0.5, 2.0),
        },
        NumVar {
            name: "dist".into(),
            domain: NumInterval::ANY,
        },
        NumVar {
            name: "duration".into(),
            domain: NumInterval::ANY,
        },
    ];
    go.numeric = vec![
        NumConstraint::Distance {
            var: dist,
            a: from,
            b: to,
        },
        NumConstraint::Duration {
            var: dur,
            from: ST,
            to: ET,
        },
        NumConstraint::Product {
            var: dist,
            a: NumTerm::Var(speed),
            b: NumTerm::Var(dur),
        },
    ];
    go.preemption = Preemption::LatePreemptive;
    d.add_task(go);

    // snap(?l): at ?l, the camera for [st, et[, one storage slot.
    let l = Term::Var(SymVarId(0));
    let mut snap = task("snap", vec![var("l")], 1);
    snap.holds = vec![Hold {
        attr: at,
        args: vec![],
        value: l,
        from: ST,
        to: ET,
    }];
    snap.events = vec![Event {
        attr: seen,
        args: vec![l],
        from: Term::Obj(Domain::FALSE),
        to: Term::Obj(Domain::TRUE),
        at: ET,
        primary: true,
    }];
    snap.usages = vec![
        ResourceUsage {
            resource: cam,
            kind: UsageKind::Use { from: ST, to: ET },
            quantity: NumTerm::Const(1.0),
            primary: false,
            saturating: false,
        },
        ResourceUsage {
            resource: store,
            kind: UsageKind::Consume { at: ST },
            quantity: NumTerm::Const(1.0),
            primary: false,
            saturating: false,
        },
    ];
    snap.temporal = vec![TemporalConstraint {
        from: ST,
        to: ET,
        interval: TimeInterval::closed(1_000, 3_000),
    }];
    d.add_task(snap);

    let mut cal = task("calibrate", vec![], 0);
    cal.usages = vec![ResourceUsage {
        resource: cam,
        kind: UsageKind::Use { from: ST, to: ET },
        quantity: NumTerm::Const(1.0),
        primary: false,
        saturating: false,
    }];
    cal.temporal = vec![TemporalConstraint {
        from: ST,
        to: ET,
        interval: TimeInterval::closed(1_000, 2_000),
    }];
    d.add_task(cal);
    d
}

/// Places a (0, 0), b (10, 0), c (0, 15); the robot at a; goal g1: SEEN(b) within `deadline` ms.
pub fn problem(d: &Domain, deadline: i64) -> Problem {
    let mut p = Problem::new("tiny1", d, HORIZON);
    let loc = d.type_id("loc").expect("loc");
    for (name, (e, n)) in PLACES.iter().zip([(0.0, 0.0), (10.0, 0.0), (0.0, 15.0)]) {
        p.add_object(Object {
            name: (*name).into(),
            ty: loc,
            position: Some(Position::Local {
                east: e,
                north: n,
                up: 0.0,
            }),
        });
    }
    let (at, seen) = (
        d.attr_id("AT").expect("AT"),
        d.attr_id("SEEN").expect("SEEN"),
    );
    let a = p.object_id("a").expect("a");
    p.initial.push(Fact {
        attr: at,
        args: vec![],
        value: Value::Obj(a),
    });
    for name in PLACES {
        let o = p.object_id(name).expect("place");
        p.initial.push(Fact {
            attr: seen,
            args: vec![o],
            value: Value::Obj(Domain::FALSE),
        });
    }
    p.goals.push(Goal {
        name: "g1".into(),
        kind: GoalOrigin::External,
        priority: 1,
        attr: seen,
        args: vec![p.object_id("b").expect("b")],
        value: Value::Obj(Domain::TRUE),
        start_window: TimeInterval::closed(0, deadline),
        duration: TimeInterval::exactly(0),
        achieve: 0,
    });
    p
}

/// One step of a sequential plan.
#[derive(Debug, Clone, Copy)]
pub enum Step {
    Go(usize),
    Snap,
}

/// The minimal duration of a move at top speed `vmax`, rounded up to the millisecond (what a planner's
/// numeric propagation adds to the network).
pub fn move_window(b: &mut Builder, id: PlanActionId, from: &str, to: &str, vmin: f64, vmax: f64) {
    let (p, q) = (
        b.p.object_id(from).expect("from"),
        b.p.object_id(to).expect("to"),
    );
    let dist = b.p.distance(p, q).expect("positions");
    let (st, et) = (b.st(id), b.et(id));
    let lo = (dist / vmax * 1000.0).ceil() as i64;
    let hi = (dist / vmin * 1000.0).floor() as i64;
    b.constrain(st, et, Some(lo), Some(hi));
}

/// Appends action `id` to a sequential plan: it starts after `prev`, and `at` (what last set the robot's
/// place) supports its use of that place, `robot_at`.
fn append(b: &mut Builder, prev: PlanTp, at: Establisher, id: PlanActionId, robot_at: Consumer) {
    let st = b.st(id);
    b.before(prev, st);
    b.link(at, robot_at);
}

/// A sequential plan with every causal link; snaps of places already seen, or beyond `max_snaps`, are
/// skipped; snapping b achieves g1.
pub fn sequential(d: &Domain, p: &Problem, steps: &[Step], max_snaps: usize) -> Solution {
    let mut b = Builder::new(d, p);
    let mut cur = 0usize;
    let mut at_est = Establisher::Initial;
    let mut prev = PlanTp::ORIGIN;
    let mut seen = [false; 3];
    let mut snaps = 0;
    for step in steps {
        match *step {
            Step::Go(t) if t != cur => {
                let id = b.action("go", &[PLACES[cur], PLACES[t]]);
                move_window(&mut b, id, PLACES[cur], PLACES[t], 0.5, 2.0);
                append(
                    &mut b,
                    prev,
                    at_est,
                    id,
                    Consumer::EventFrom {
                        action: id,
                        event: 0,
                    },
                );
                b.event_to_hold(id, 0, id, 0);
                at_est = Establisher::Event {
                    action: id,
                    event: 1,
                };
                prev = b.et(id);
                cur = t;
            }
            Step::Snap if !seen[cur] && snaps < max_snaps => {
                let id = b.action("snap", &[PLACES[cur]]);
                append(
                    &mut b,
                    prev,
                    at_est,
                    id,
                    Consumer::Hold {
                        action: id,
                        hold: 0,
                    },
                );
                b.link(
                    Establisher::Initial,
                    Consumer::EventFrom {
                        action: id,
                        event: 0,
                    },
                );
                prev = b.et(id);
                seen[cur] = true;
                snaps += 1;
                if PLACES[cur] == "b" {
                    b.achieve("g1", prev, id, 0);
                }
            }
            _ => {}
        }
    }
    b.finish()
}
