//! The classic polynomial DC check (Morris, Muscettola & Vidal 2001, in the labelled-distance-graph form
//! of Morris & Muscettola 2005): apply the tightening rules to every triangle until nothing changes,
//! failing as soon as the AllMax projection (every contingent link at its upper bound: ordinary and
//! upper-case edges) has a negative cycle. The test oracle of [`super::dc`] and its bench baseline.
//!
//! Edges are `Y − X ≤ w`, written `X −w→ Y`; a link is `(A, x, y, C)`. The rules:
//! - no-case: `A −u→ B −v→ D` gives `A −(u+v)→ D`;
//! - upper-case: `X −u→ B −C:v→ A` gives `X −C:(u+v)→ A`;
//! - lower-case: `A −c:x→ C −v→ D` with `v < 0` gives `A −(x+v)→ D`;
//! - cross-case: `A −c:x→ C −B:v→ D` with `v < 0`, `B ≠ C`, gives `A −B:(x+v)→ D`;
//! - label removal: `X −C:v→ A` with `v ≥ −x` gives `X −v→ A`.
//!
//! Without quiescence after the cutoff number of rounds the network is declared not DC, as in Morris &
//! Muscettola 2005 (a DC network quiesces much earlier: each round settles at least one more step of
//! every shortest reduced path).

use super::stnu::Stnu;
use super::{sat_add, Time, INF};

/// Whether `stnu` is dynamically controllable, by the tightening fixpoint.
pub fn is_dc(stnu: &Stnu) -> bool {
    let n = stnu.num_nodes();
    let links = stnu.links();
    let mut ord = vec![INF; n * n];
    for i in 0..n {
        ord[i * n + i] = 0;
    }
    let tighten = |m: &mut [Time], i: usize, w: Time| -> bool {
        if w < m[i] {
            m[i] = w;
            true
        } else {
            false
        }
    };
    for r in stnu.requirements() {
        if r.ub < INF {
            tighten(&mut ord, r.from * n + r.to, r.ub);
        }
        if r.lb > -INF {
            tighten(&mut ord, r.to * n + r.from, -r.lb);
        }
    }
    // upper[k][x]: the edge `x −C_k:w→ A_k`.
    let mut upper = vec![vec![INF; n]; links.len()];
    for (k, l) in links.iter().enumerate() {
        tighten(&mut ord, l.activation * n + l.contingent, l.upper);
        tighten(&mut ord, l.contingent * n + l.activation, -l.lower);
        upper[k][l.contingent] = -l.upper;
    }
    let cutoff = 4 * (n + links.len() + 2).pow(2);
    for _ in 0..cutoff {
        let mut changed = false;
        // No-case, to closure.
        changed |= close(n, &mut ord);
        for (k, l) in links.iter().enumerate() {
            // Upper-case.
            for x in 0..n {
                for b in 0..n {
                    let w = sat_add(ord[x * n + b], upper[k][b]);
                    changed |= tighten(&mut upper[k], x, w);
                }
            }
            // Lower-case.
            for d in 0..n {
                let v = ord[l.contingent * n + d];
                if v < 0 {
                    changed |= tighten(&mut ord, l.activation * n + d, l.lower + v);
                }
            }
            // Cross-case: this link's lower-case edge before another link's upper-case edge.
            for (j, up) in upper.iter_mut().enumerate() {
                let v = up[l.contingent];
                if j != k && v < 0 {
                    changed |= tighten(up, l.activation, l.lower + v);
                }
            }
        }
        // Label removal.
        for (l, up) in links.iter().zip(&upper) {
            for (x, &v) in up.iter().enumerate() {
                if v < INF && v >= -l.lower {
                    changed |= tighten(&mut ord, x * n + l.activation, v);
                }
            }
        }
        if !all_max_consistent(n, &ord, &upper, stnu) {
            return false;
        }
        if !changed {
            return true;
        }
    }
    false
}

/// The AllMax projection (ordinary edges and upper-case edges taken as ordinary) has no negative cycle.
fn all_max_consistent(n: usize, ord: &[Time], upper: &[Vec<Time>], stnu: &Stnu) -> bool {
    let mut m = ord.to_vec();
    for (l, up) in stnu.links().iter().zip(upper) {
        for (x, &v) in up.iter().enumerate() {
            let i = x * n + l.activation;
            m[i] = m[i].min(v);
        }
    }
    close(n, &mut m);
    (0..n).all(|i| m[i * n + i] >= 0)
}

/// Floyd–Warshall closure of the `n × n` matrix `m` (the no-case rule to a fixpoint); whether it changed.
fn close(n: usize, m: &mut [Time]) -> bool {
    let mut changed = false;
    for b in 0..n {
        for a in 0..n {
            let ab = m[a * n + b];
            if ab >= INF {
                continue;
            }
            for d in 0..n {
                let w = sat_add(ab, m[b * n + d]);
                if w < m[a * n + d] {
                    m[a * n + d] = w;
                    changed = true;
                }
            }
        }
    }
    changed
}
