//! Random plan-like STNUs for the DC-check bench (`benches/stnu.rs`): Morris 2014 against the tightening
//! fixpoint.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::stn::{Stnu, INF};

/// About `n` nodes (node 0 the origin, then actions as start/end pairs): every other action's duration is
/// contingent (`[d − δ, d + δ]`), the others are requirements; actions follow one of the three before them,
/// some start within a bounded gap after a predecessor's end (the constraints that make waits), and ends
/// have deadlines with slack. Dynamically controllable for most seeds ([`dc_plan_like`] picks one that is).
pub fn plan_like_stnu(n: usize, seed: u64) -> Stnu {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let actions = ((n.max(3) - 1) / 2).max(1);
    let mut s = Stnu::new(1 + 2 * actions);
    let mut horizon = 0;
    for i in 0..actions {
        let (st, et) = (2 * i + 1, 2 * i + 2);
        let d = rng.gen_range(10..100);
        let delta = rng.gen_range(0..d / 2);
        // Each node index is in range and each action's end is contingent once: no error possible.
        if i % 2 == 0 {
            s.add_contingent(st, et, d - delta, d + delta).ok();
        } else {
            s.add_requirement(st, et, d - delta, d + delta).ok();
        }
        s.add_requirement(0, st, 0, INF).ok();
        if i > 0 {
            let j = i - 1 - rng.gen_range(0..i.min(3));
            let gap = rng.gen_range(0..60);
            let bounded = if rng.gen_bool(0.3) { gap + 200 } else { INF };
            s.add_requirement(2 * j + 2, st, gap.min(5), bounded).ok();
        }
        horizon += d + delta + 60;
        s.add_requirement(0, et, 0, horizon + rng.gen_range(0..200))
            .ok();
    }
    s
}

/// The first [`plan_like_stnu`] from `seed` on that is dynamically controllable.
pub fn dc_plan_like(n: usize, seed: u64) -> Stnu {
    (seed..seed + 1_000)
        .map(|s| plan_like_stnu(n, s))
        .find(|s| s.check_dc().is_ok())
        .unwrap_or_else(|| plan_like_stnu(n, seed))
}
