//! Seed 2's scenarios, built by hand as causal graphs over an STN and run cycle by cycle with a manual clock
//! under each dispatch policy: the shopping plan of Figs 3–5 and the AUV vents plan of Figs 1–2.
//!
//! The harness is a minimal executive: every timestep it asks the policy about each action whose causal
//! and ordering predecessors have ended, with the start window read from the STN; a dispatched action runs
//! for exactly its duration.
//!
//! Kept beside the scenarios through the real executive (src/executive/tests/it/dispatch_exec_scenarios.rs) because these
//! are the papers' plans exactly: 20-minute walks, and the trailing `Go(home, ?)` whose start has no upper
//! bound, which the planner's plans (bounded by the problem's horizon) never contain.

use mavtempo_executive::dispatch::dispatcher::Dispatcher;
use mavtempo_executive::dispatch::{
    ActionId, CausalGraph, Change, Establisher, GoalId, Link, LinkId, Marking, Node, PolicyKind,
    StartWindow, SupportForm, Tick,
};
use mavtempo_temporal::model::GoalOrigin;
use mavtempo_temporal::stn::{Stn, Time, Timepoint, INF};

const MIN: Time = 60_000;
const TS: Time = MIN;

/// Clock time `h:m` relative to the 08:00 origin.
const fn hm(h: i64, m: i64) -> Time {
    ((h - 8) * 60 + m) * MIN
}

fn clock(t: Time) -> String {
    let m = t / MIN + 8 * 60;
    format!("{:02}:{:02}", m / 60, m % 60)
}

struct Act {
    name: &'static str,
    st: Timepoint,
    et: Timepoint,
    dur: Time,
    started: Option<Time>,
    removed: bool,
    /// Actions that must have ended before this one starts (causal links and threat resolutions).
    after: Vec<usize>,
}

struct Sim {
    stn: Stn,
    acts: Vec<Act>,
    marking: Marking,
    /// An independent mirror fed the same changes, read by Algorithm 2 in the search form.
    mirror: CausalGraph,
    dispatcher: Dispatcher,
    links: Vec<(LinkId, Link)>,
    next_link: u32,
    now: Time,
}

impl Sim {
    fn new(kind: PolicyKind) -> Self {
        Sim {
            stn: Stn::new(),
            acts: Vec::new(),
            marking: Marking::new(),
            mirror: CausalGraph::new(),
            dispatcher: Dispatcher::new(kind),
            links: Vec::new(),
            next_link: 0,
            now: 0,
        }
    }

    fn change(&mut self, c: Change) {
        self.marking.apply(&c).unwrap();
        self.mirror.apply(&c).unwrap();
    }

    fn action(&mut self, name: &'static str, dur: Time) -> usize {
        let st = self.stn.add_timepoint();
        let et = self.stn.add_timepoint();
        self.stn.add_constraint(st, et, dur, dur).unwrap();
        let i = self.acts.len();
        self.acts.push(Act {
            name,
            st,
            et,
            dur,
            started: None,
            removed: false,
            after: Vec::new(),
        });
        self.change(Change::ActionAdded(ActionId(i as u32)));
        i
    }

    fn goal(&mut self, g: u32, kind: GoalOrigin) {
        self.change(Change::GoalAdded(GoalId(g), kind));
    }

    /// A causal link from `from`'s effect (the initial state if `None`) to `to`; the establisher precedes
    /// the consumer.
    fn link(&mut self, from: Option<usize>, to: Node) {
        let key = LinkId(self.next_link);
        self.next_link += 1;
        let link = Link {
            from: from.map_or(Establisher::Initial, |a| {
                Establisher::Action(ActionId(a as u32))
            }),
            to,
        };
        if let (Some(a), Node::Action(b)) = (from, to) {
            self.order(a, b.0 as usize);
        }
        self.links.push((key, link));
        self.change(Change::LinkAdded(key, link));
    }

    /// `a` ends before `b` starts.
    fn order(&mut self, a: usize, b: usize) {
        let (et, st) = (self.acts[a].et, self.acts[b].st);
        self.stn.add_constraint(et, st, 0, INF).unwrap();
        self.acts[b].after.push(a);
    }

    fn deadline(&mut self, a: usize, end_by: Time) {
        let (o, et) = (self.stn.origin(), self.acts[a].et);
        self.stn.add_constraint(o, et, 0, end_by).unwrap();
    }

    fn release(&mut self, a: usize, start_from: Time) {
        let (o, st) = (self.stn.origin(), self.acts[a].st);
        self.stn.add_constraint(o, st, start_from, INF).unwrap();
    }

    /// Plan repair removes action `a`: its causal links, then itself; its constraints are relaxed.
    fn remove(&mut self, a: usize) {
        let key = ActionId(a as u32);
        let mine: Vec<LinkId> = self
            .links
            .iter()
            .filter(|(_, l)| l.to == Node::Action(key) || l.from == Establisher::Action(key))
            .map(|(k, _)| *k)
            .collect();
        for k in mine {
            self.change(Change::LinkRemoved(k));
            self.links.retain(|(x, _)| *x != k);
        }
        self.change(Change::ActionRemoved(key));
        let (st, et) = (self.acts[a].st, self.acts[a].et);
        self.stn.relax_timepoint(st);
        self.stn.relax_timepoint(et);
        self.acts[a].removed = true;
        for act in &mut self.acts {
            act.after.retain(|&p| p != a);
        }
    }

    fn supports(&mut self, a: usize) -> bool {
        self.dispatcher
            .supports(ActionId(a as u32), &self.mirror, &self.marking)
    }

    /// One cycle at `now`, then the clock moves one timestep.
    fn step(&mut self) {
        let tick = Tick::new(self.now, TS);
        for i in 0..self.acts.len() {
            let act = &self.acts[i];
            let ready = act.after.iter().all(|&p| {
                self.stn
                    .executed_at(self.acts[p].et)
                    .is_some_and(|t| t <= self.now)
            });
            if act.removed || act.started.is_some() || !ready {
                continue;
            }
            let window = StartWindow {
                lb: self.stn.lb(act.st).max(self.now),
                ub: self.stn.ub(act.st),
            };
            let key = ActionId(i as u32);
            let decision = self
                .dispatcher
                .decide(key, window, tick, &self.mirror, &self.marking);
            if let mavtempo_executive::dispatch::Decision::Dispatch { at } = decision {
                let (st, et, dur) = (act.st, act.et, act.dur);
                self.stn.execute(st, at).unwrap();
                self.stn.execute(et, at + dur).unwrap();
                self.acts[i].started = Some(at);
            }
        }
        self.now += TS;
    }

    fn run_until(&mut self, t: Time) {
        while self.now < t {
            self.step();
        }
    }

    fn started(&self, a: usize) -> Option<String> {
        self.acts[a].started.map(clock)
    }

    fn ended(&self, a: usize) -> Option<String> {
        self.stn.executed_at(self.acts[a].et).map(clock)
    }

    fn trace(&self) -> Vec<(&'static str, Option<Time>)> {
        self.acts.iter().map(|a| (a.name, a.started)).collect()
    }
}

/// A plan fragment as seed 2 draws it: the actions it first removes (plan repair), its goals, its actions
/// (each with the index it must get), causal links, threat-resolving orderings, deadlines on action ends and
/// releases of action starts. Applied in that order, so the marking sees the changes a planner would send.
struct Fragment {
    remove: &'static [usize],
    goals: &'static [(u32, GoalOrigin)],
    actions: &'static [(usize, &'static str, Time)],
    links: &'static [(Option<usize>, Node)],
    orders: &'static [(usize, usize)],
    deadlines: &'static [(usize, Time)],
    releases: &'static [(usize, Time)],
}

const NOTHING: Fragment = Fragment {
    remove: &[],
    goals: &[],
    actions: &[],
    links: &[],
    orders: &[],
    deadlines: &[],
    releases: &[],
};

const fn action_node(a: usize) -> Node {
    Node::Action(ActionId(a as u32))
}

const fn goal_node(g: u32) -> Node {
    Node::Goal(GoalId(g))
}

impl Fragment {
    fn apply(&self, s: &mut Sim) {
        for &a in self.remove {
            s.remove(a);
        }
        for &(g, kind) in self.goals {
            s.goal(g, kind);
        }
        for &(index, name, dur) in self.actions {
            assert_eq!(s.action(name, dur), index, "{name}");
        }
        for &(from, to) in self.links {
            s.link(from, to);
        }
        for &(a, b) in self.orders {
            s.order(a, b);
        }
        for &(a, end_by) in self.deadlines {
            s.deadline(a, end_by);
        }
        for &(a, start_from) in self.releases {
            s.release(a, start_from);
        }
    }

    /// A fresh plan of this fragment, dispatched under `kind`.
    fn plan(&self, kind: PolicyKind) -> Sim {
        let mut s = Sim::new(kind);
        self.apply(&mut s);
        s
    }
}

// --- Shopping (seed 2 Figs 2–5) -------------------------------------------------------------------------

const HAVE_APPLE: u32 = 0;
const AT_HOME: u32 = 1;
const HAVE_SHIRT: u32 = 2;
const GO_H_C: usize = 0;
const GO_C_G: usize = 1;
const BUY_APPLE: usize = 2;
const GO_G_H: usize = 3;
const GO_H_ANY: usize = 4;

/// Fig. 2: at home at 08:00, wants an apple before noon (external), must be home by 20:00 (internal); the
/// grocery is reached through the clothing store; the plan model makes every `At` token be followed by a
/// `Go`, hence the trailing `Go(home, ?)` after 20:00. Buy(apple) holds At(grocery), which
/// Go(grocery, home) changes: the threat is resolved by ordering.
const SHOPPING: Fragment = Fragment {
    goals: &[
        (HAVE_APPLE, GoalOrigin::External),
        (AT_HOME, GoalOrigin::Internal),
    ],
    actions: &[
        (GO_H_C, "Go(home, clothing)", 20 * MIN),
        (GO_C_G, "Go(clothing, grocery)", 10 * MIN),
        (BUY_APPLE, "Buy(apple)", 10 * MIN),
        (GO_G_H, "Go(grocery, home)", 25 * MIN),
        (GO_H_ANY, "Go(home, ?)", 20 * MIN),
    ],
    links: &[
        (None, action_node(GO_H_C)),
        (Some(GO_H_C), action_node(GO_C_G)),
        (Some(GO_C_G), action_node(BUY_APPLE)),
        (Some(GO_C_G), action_node(GO_G_H)),
        (Some(BUY_APPLE), goal_node(HAVE_APPLE)),
        (Some(GO_G_H), goal_node(AT_HOME)),
        (Some(GO_G_H), action_node(GO_H_ANY)),
    ],
    orders: &[(BUY_APPLE, GO_G_H)],
    deadlines: &[(BUY_APPLE, hm(12, 0)), (GO_G_H, hm(20, 0))],
    releases: &[(GO_H_ANY, hm(20, 0))],
    ..NOTHING
};

const GO_G_C: usize = 5;
const BUY_SHIRT: usize = 6;
const GO_C_H: usize = 7;

/// Fig. 5: the 09:00 call asking for a shirt, integrated by repair: Go(grocery, home) gives way to
/// Go(grocery, clothing), Buy(shirt), Go(clothing, home).
const SHIRT_REQUEST: Fragment = Fragment {
    remove: &[GO_G_H],
    goals: &[(HAVE_SHIRT, GoalOrigin::External)],
    actions: &[
        (GO_G_C, "Go(grocery, clothing)", 10 * MIN),
        (BUY_SHIRT, "Buy(shirt)", 10 * MIN),
        (GO_C_H, "Go(clothing, home)", 20 * MIN),
    ],
    links: &[
        (Some(GO_C_G), action_node(GO_G_C)),
        (Some(GO_G_C), action_node(BUY_SHIRT)),
        (Some(GO_G_C), action_node(GO_C_H)),
        (Some(BUY_SHIRT), goal_node(HAVE_SHIRT)),
        (Some(GO_C_H), goal_node(AT_HOME)),
        (Some(GO_C_H), action_node(GO_H_ANY)),
    ],
    orders: &[(BUY_APPLE, GO_G_C), (BUY_SHIRT, GO_C_H)],
    deadlines: &[(BUY_SHIRT, hm(12, 0)), (GO_C_H, hm(20, 0))],
    ..NOTHING
};

const FORMS: [SupportForm; 2] = [SupportForm::Search, SupportForm::Marking];

/// Fig. 3: blindly proactive, the agent is back home at 09:05 and stuck there; the trailing Go(home, ?)
/// starts at 20:00.
#[test]
fn shopping_earliest_goes_home_at_once() {
    let mut s = SHOPPING.plan(PolicyKind::Earliest);
    s.run_until(hm(23, 59));
    assert_eq!(s.started(GO_H_C).as_deref(), Some("08:00"));
    assert_eq!(s.started(GO_C_G).as_deref(), Some("08:20"));
    assert_eq!(s.started(BUY_APPLE).as_deref(), Some("08:30"));
    assert_eq!(s.started(GO_G_H).as_deref(), Some("08:40"));
    assert_eq!(s.ended(GO_G_H).as_deref(), Some("09:05"));
    assert_eq!(s.started(GO_H_ANY).as_deref(), Some("20:00"));
}

/// Fig. 4: the path to the apple is proactive (starred), Go(grocery, home) deferred to its latest start,
/// Go(home, ?) never dispatched (its start upper bound is +∞).
#[test]
fn shopping_goal_driven_buys_the_apple_at_once_and_stays_at_the_grocery() {
    for form in FORMS {
        let mut s = SHOPPING.plan(PolicyKind::GoalDriven(form));
        for a in [GO_H_C, GO_C_G, BUY_APPLE] {
            assert!(s.supports(a), "{form:?}: {} starred", s.acts[a].name);
        }
        for a in [GO_G_H, GO_H_ANY] {
            assert!(!s.supports(a), "{form:?}: {} not starred", s.acts[a].name);
        }
        assert_eq!(s.stn.ub(s.acts[GO_G_H].st), hm(19, 35));
        s.run_until(hm(23, 59));
        assert_eq!(s.started(GO_H_C).as_deref(), Some("08:00"), "{form:?}");
        assert_eq!(s.started(GO_C_G).as_deref(), Some("08:20"), "{form:?}");
        assert_eq!(s.started(BUY_APPLE).as_deref(), Some("08:30"), "{form:?}");
        // Algorithm 1 dispatches it in the tick that contains its latest start, [19:34, 19:35].
        assert_eq!(s.started(GO_G_H).as_deref(), Some("19:34"), "{form:?}");
        assert_eq!(s.started(GO_H_ANY), None, "{form:?}");
    }
}

/// Fig. 5: at 09:00, while waiting at the grocery, a call asks for a shirt. The path to the clothing store
/// becomes proactive; Go(clothing, home) starts in the tick of its latest start, 19:40 (so at 19:39 with
/// one-minute ticks); Go(home, ?) never starts.
#[test]
fn shopping_goal_driven_serves_the_shirt_request_proactively() {
    let mut traces = Vec::new();
    for form in FORMS {
        let mut s = SHOPPING.plan(PolicyKind::GoalDriven(form));
        s.run_until(hm(9, 0));
        assert_eq!(s.started(GO_G_H), None, "{form:?}: still at the grocery");
        SHIRT_REQUEST.apply(&mut s);
        for a in [GO_G_C, BUY_SHIRT] {
            assert!(s.supports(a), "{form:?}: {} starred", s.acts[a].name);
        }
        assert!(!s.supports(GO_C_H), "{form:?}");
        assert_eq!(s.stn.ub(s.acts[GO_C_H].st), hm(19, 40));
        s.run_until(hm(23, 59));
        assert_eq!(s.started(GO_G_C).as_deref(), Some("09:00"), "{form:?}");
        assert_eq!(s.started(BUY_SHIRT).as_deref(), Some("09:10"), "{form:?}");
        assert_eq!(s.started(GO_C_H).as_deref(), Some("19:39"), "{form:?}");
        assert_eq!(s.ended(GO_C_H).as_deref(), Some("19:59"));
        assert_eq!(s.started(GO_H_ANY), None, "{form:?}");
        assert_eq!(s.started(GO_G_H), None, "{form:?}");
        traces.push(s.trace());
    }
    assert_eq!(traces[0], traces[1], "both forms dispatch alike");
}

/// Deferring everything keeps the agent home until the apple's deadline forces it out, and never starts
/// the trailing Go(home, ?).
#[test]
fn shopping_latest_defers_even_the_operators_goal() {
    let mut s = SHOPPING.plan(PolicyKind::Latest);
    s.run_until(hm(23, 59));
    assert_eq!(s.started(GO_H_C).as_deref(), Some("11:19"));
    assert_eq!(s.started(BUY_APPLE).as_deref(), Some("11:49"));
    assert_eq!(s.started(GO_G_H).as_deref(), Some("19:34"));
    assert_eq!(s.started(GO_H_ANY), None);
}

// --- AUV vents (seed 2 Figs 1–2) ------------------------------------------------------------------------

const SAMPLED: u32 = 0;
const AT_SURFACE: u32 = 1;
const GO_S_V1: usize = 0;
const GO_V1_V2: usize = 1;
const SAMPLE_V2: usize = 2;
const GO_V2_S: usize = 3;

/// Fig. 1c/2: at the surface at 08:00, the scientist wants vent 2 sampled (external); the AUV must be back
/// at the surface by 20:00 (internal).
const VENTS: Fragment = Fragment {
    goals: &[
        (SAMPLED, GoalOrigin::External),
        (AT_SURFACE, GoalOrigin::Internal),
    ],
    actions: &[
        (GO_S_V1, "Go(surface, vent1)", 30 * MIN),
        (GO_V1_V2, "Go(vent1, vent2)", 5 * MIN),
        (SAMPLE_V2, "Sample(vent2)", 10 * MIN),
        (GO_V2_S, "Go(vent2, surface)", 30 * MIN),
    ],
    links: &[
        (None, action_node(GO_S_V1)),
        (Some(GO_S_V1), action_node(GO_V1_V2)),
        (Some(GO_V1_V2), action_node(SAMPLE_V2)),
        (Some(GO_V1_V2), action_node(GO_V2_S)),
        (Some(SAMPLE_V2), goal_node(SAMPLED)),
        (Some(GO_V2_S), goal_node(AT_SURFACE)),
    ],
    orders: &[(SAMPLE_V2, GO_V2_S)],
    deadlines: &[(GO_V2_S, hm(20, 0))],
    ..NOTHING
};

#[test]
fn vents_goal_driven_samples_at_once_and_surfaces_at_the_last_moment() {
    let mut traces = Vec::new();
    for form in FORMS {
        let mut s = VENTS.plan(PolicyKind::GoalDriven(form));
        assert_eq!(s.stn.ub(s.acts[GO_V2_S].st), hm(19, 30));
        s.run_until(hm(21, 0));
        assert_eq!(s.started(GO_S_V1).as_deref(), Some("08:00"), "{form:?}");
        assert_eq!(s.started(GO_V1_V2).as_deref(), Some("08:30"), "{form:?}");
        assert_eq!(s.started(SAMPLE_V2).as_deref(), Some("08:35"), "{form:?}");
        assert_eq!(s.started(GO_V2_S).as_deref(), Some("19:29"), "{form:?}");
        traces.push(s.trace());
    }
    assert_eq!(traces[0], traces[1]);
}

#[test]
fn vents_earliest_surfaces_early_and_latest_samples_late() {
    let mut s = VENTS.plan(PolicyKind::Earliest);
    s.run_until(hm(21, 0));
    assert_eq!(s.started(SAMPLE_V2).as_deref(), Some("08:35"));
    assert_eq!(s.started(GO_V2_S).as_deref(), Some("08:45"));
    let mut s = VENTS.plan(PolicyKind::Latest);
    s.run_until(hm(21, 0));
    assert_eq!(s.started(GO_S_V1).as_deref(), Some("18:44"));
    assert_eq!(s.started(GO_V2_S).as_deref(), Some("19:29"));
}
