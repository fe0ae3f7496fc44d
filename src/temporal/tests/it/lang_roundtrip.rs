//! Goals printed by the model (`Problem::goal_string`) parse back to the same goal: the shipped ones and
//! random ones (random attribute instance, value, windows with open/closed bounds, priority, d_achiev).

use std::path::PathBuf;

use mavtempo_temporal::lang;
use mavtempo_temporal::model::{Bound, Domain, Goal, GoalOrigin, Problem, TimeInterval, Value};
use proptest::prelude::*;

fn load(d: &str, p: &str) -> (Domain, Problem) {
    let path = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .join(format!("domains/{d}/problems/{p}.ixt"));
    lang::load_problem_and_domain(&path).unwrap_or_else(|e| panic!("{e}"))
}

const SHIPPED: [(&str, &str); 4] = [
    ("rover", "fig2"),
    ("rover", "dala"),
    ("auv", "vents"),
    ("shopping", "day"),
];

fn shipped() -> &'static Vec<(Domain, Problem)> {
    static S: std::sync::OnceLock<Vec<(Domain, Problem)>> = std::sync::OnceLock::new();
    S.get_or_init(|| SHIPPED.iter().map(|(d, p)| load(d, p)).collect())
}

fn round_trip(d: &Domain, p: &Problem, g: &Goal) -> Result<Goal, String> {
    let mut without = p.clone();
    without.goals.retain(|x| x.name != g.name);
    let text = p.goal_string(d, g);
    lang::parse_goal("<printed>", &text, d, &without).map_err(|e| format!("{text}\n{e}"))
}

#[test]
fn shipped_goals_round_trip() {
    for (d, p) in shipped() {
        for g in &p.goals {
            assert_eq!(round_trip(d, p, g).as_ref(), Ok(g));
        }
    }
}

#[test]
fn times_print_as_clock_or_seconds() {
    let (_, vents) = load("auv", "vents");
    assert_eq!(vents.time_string(12 * 3_600_000), "20:00:00");
    assert_eq!(vents.time_string(1_500), "08:00:01.500");
    let (_, fig2) = load("rover", "fig2");
    assert_eq!(fig2.time_string(90_000), "90s");
}

fn bound(open: bool, v: i64) -> Bound<i64> {
    if open {
        Bound::Open(v)
    } else {
        Bound::Closed(v)
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 128, ..ProptestConfig::default() })]

    #[test]
    fn random_goals_round_trip(
        which in 0usize..4,
        attr_pick in any::<prop::sample::Index>(),
        arg_picks in proptest::collection::vec(any::<prop::sample::Index>(), 3),
        value_pick in any::<prop::sample::Index>(),
        (a, b) in (0i64..1_000_000, 0i64..1_000_000),
        (lo_open, hi_open) in (any::<bool>(), any::<bool>()),
        dur in proptest::option::of((0i64..600_000, 1i64..600_000, any::<bool>())),
        priority in -5i64..10,
        achieve_frac in 0i64..=100,
        internal in any::<bool>(),
    ) {
        let (d, p) = &shipped()[which];
        let attr = attr_pick.index(d.attrs.len());
        let a_def = &d.attrs[attr];
        let args: Vec<_> = a_def.params.iter().zip(&arg_picks).map(|((_, t), pick)| {
            let objs = p.objects_of(*t);
            objs[pick.index(objs.len())]
        }).collect();
        let values = p.objects_of(a_def.value_type);
        let value = Value::Obj(values[value_pick.index(values.len())]);
        // A start window inside [0, horizon] that stays non-empty on the millisecond grid.
        let scale = |x: i64| x * p.horizon / 1_000_000;
        let (lo, hi) = (scale(a.min(b)), scale(a.max(b)));
        let (lo_open, hi_open) = if hi - lo < 3 { (false, false) } else { (lo_open, hi_open) };
        let start_window = TimeInterval { lb: bound(lo_open, lo), ub: bound(hi_open, hi) };
        let duration = match dur {
            Some((x, len, open)) => TimeInterval { lb: Bound::Closed(x), ub: bound(open, x + len + 1) },
            None => TimeInterval::exactly(0),
        };
        let achieve = lo * achieve_frac / 100;
        let g = Goal {
            name: "gx".into(),
            kind: if internal { GoalOrigin::Internal } else { GoalOrigin::External },
            priority,
            attr: mavtempo_temporal::model::AttrId::from_index(attr),
            args,
            value,
            start_window,
            duration,
            achieve,
        };
        prop_assert_eq!(round_trip(d, p, &g), Ok(g));
    }
}
