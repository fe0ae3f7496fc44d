//! Morris 2014's DC check against the tightening fixpoint of Morris & Muscettola 2005 on small random
//! STNUs (seeded).

use mavtempo_temporal::stn::dc_reference::is_dc;
use mavtempo_temporal::stn::{Stnu, Time, INF};
use proptest::prelude::*;
use proptest::test_runner::RngSeed;

#[derive(Clone, Debug)]
struct Net {
    n: usize,
    links: Vec<(usize, usize, Time, Time)>,
    reqs: Vec<(usize, usize, Time, Time)>,
}

fn net() -> impl Strategy<Value = Net> {
    (3usize..=7).prop_flat_map(|n| {
        let link = (0..n, 0..n, 0i64..6, 0i64..8);
        let req = (
            0..n,
            0..n,
            -8i64..12,
            prop_oneof![0i64..12, Just(INF)],
            any::<bool>(),
        );
        (
            Just(n),
            proptest::collection::vec(link, 0..=3),
            proptest::collection::vec(req, 0..=9),
        )
            .prop_map(|(n, links, reqs)| Net {
                n,
                links: links
                    .into_iter()
                    .map(|(a, c, l, span)| (a, c, l, l + span))
                    .collect(),
                reqs: reqs
                    .into_iter()
                    .map(|(f, t, lb, span, open)| {
                        let ub = if span >= INF { INF } else { lb + span };
                        (f, t, if open { -INF } else { lb }, ub)
                    })
                    .collect(),
            })
    })
}

fn build(net: &Net) -> Stnu {
    let mut s = Stnu::new(net.n);
    for &(a, c, l, u) in &net.links {
        // Invalid ones (self links, a node contingent twice) are refused; the rest is the network.
        let _ = s.add_contingent(a, c, l, u);
    }
    for &(f, t, lb, ub) in &net.reqs {
        if f != t {
            s.add_requirement(f, t, lb, ub).expect("nodes in range");
        }
    }
    s
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 3000,
        rng_seed: RngSeed::Fixed(20260527),
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn morris_2014_agrees_with_the_tightening_fixpoint(net in net()) {
        let s = build(&net);
        let got = s.check_dc();
        prop_assert_eq!(got.is_ok(), is_dc(&s), "{:?} -> {:?}", net, got);
        if let Err(e) = got {
            prop_assert!(!e.requirements.is_empty() || !e.links.is_empty());
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 1000,
        rng_seed: RngSeed::Fixed(20260528),
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    /// On a DC network the best-effort dispatch is the check's, with no conflict.
    #[test]
    fn best_effort_is_the_check_on_dc_networks(net in net()) {
        let s = build(&net);
        let (d, conflict) = s.dispatch_best_effort();
        match s.check_dc() {
            Ok(full) => {
                prop_assert!(conflict.is_none());
                prop_assert_eq!(d.waits, full.waits);
            }
            Err(e) => prop_assert_eq!(conflict, Some(e)),
        }
    }
}
