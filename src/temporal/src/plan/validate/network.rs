//! The checker's own temporal solver: Bellman-Ford over the distance graph of the plan's network
//! (deliberately not the planner's incremental STN — a checker must not share the code it checks).

use crate::model::Time;

/// "No edge" / unbounded distance.
pub(super) const INF: Time = i64::MAX / 4;

/// A distance-graph edge `to − from ≤ w`.
#[derive(Debug, Clone, Copy)]
pub(super) struct Edge {
    pub from: usize,
    pub to: usize,
    pub w: Time,
}

/// Edges of `to − from ∈ [lb, ub]` (`None` bounds are infinite).
pub(super) fn edges_of(from: usize, to: usize, lb: Option<Time>, ub: Option<Time>) -> Vec<Edge> {
    let mut out = Vec::with_capacity(2);
    if let Some(ub) = ub {
        out.push(Edge { from, to, w: ub });
    }
    if let Some(lb) = lb {
        out.push(Edge {
            from: to,
            to: from,
            w: lb.saturating_neg(),
        });
    }
    out
}

/// Bounds of every timepoint relative to timepoint 0 (the origin).
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Bounds {
    /// Earliest times; together they form a consistent schedule.
    pub lb: Vec<Time>,
    /// Latest times (`None`: unbounded).
    pub ub: Vec<Option<Time>>,
}

/// Solves the network of `n` timepoints: `Err(cycle)` with the timepoints of a negative cycle.
/// Every timepoint is taken to be at or after the origin (as in the plan's STN).
pub(super) fn solve(n: usize, edges: &[Edge]) -> Result<Bounds, Vec<usize>> {
    let mut all: Vec<Edge> = edges.to_vec();
    all.extend((1..n).map(|x| Edge {
        from: x,
        to: 0,
        w: 0,
    }));
    // Distances *to* the origin: reversed graph from the origin. Every timepoint reaches the origin
    // (the edges above), so this run finds every negative cycle.
    let rev: Vec<Edge> = all
        .iter()
        .map(|e| Edge {
            from: e.to,
            to: e.from,
            w: e.w,
        })
        .collect();
    let to_origin = shortest(n, &rev)?;
    let from_origin = shortest(n, &all)?;
    Ok(Bounds {
        lb: to_origin.iter().map(|&d| d.saturating_neg()).collect(),
        ub: from_origin
            .iter()
            .map(|&d| if d >= INF { None } else { Some(d) })
            .collect(),
    })
}

/// Single-source (node 0) shortest distances, or a negative cycle.
fn shortest(n: usize, edges: &[Edge]) -> Result<Vec<Time>, Vec<usize>> {
    let mut dist = vec![INF; n];
    let mut pred = vec![usize::MAX; n];
    if n == 0 {
        return Ok(dist);
    }
    dist[0] = 0;
    let mut last = None;
    for _ in 0..n {
        last = None;
        for e in edges {
            if e.from >= n || e.to >= n || dist[e.from] >= INF {
                continue;
            }
            let d = dist[e.from].saturating_add(e.w);
            if d < dist[e.to] {
                dist[e.to] = d;
                pred[e.to] = e.from;
                last = Some(e.to);
            }
        }
        if last.is_none() {
            return Ok(dist);
        }
    }
    // Still relaxing after n rounds: walk back n steps to land on the cycle, then collect it.
    let mut x = last.unwrap_or(0);
    for _ in 0..n {
        x = pred[x];
        if x == usize::MAX {
            return Err(Vec::new());
        }
    }
    let mut cycle = vec![x];
    let mut y = pred[x];
    while y != x && y != usize::MAX && cycle.len() <= n {
        cycle.push(y);
        y = pred[y];
    }
    cycle.reverse();
    Err(cycle)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bounds_of_a_chain_and_a_negative_cycle() {
        // 1 in [10, 20] after 0; 2 in [5, +oo[ after 1.
        let mut e = edges_of(0, 1, Some(10), Some(20));
        e.extend(edges_of(1, 2, Some(5), None));
        let b = solve(3, &e).unwrap_or(Bounds {
            lb: vec![],
            ub: vec![],
        });
        assert_eq!(b.lb, vec![0, 10, 15]);
        assert_eq!(b.ub, vec![Some(0), Some(20), None]);
        e.extend(edges_of(0, 2, None, Some(12)));
        let cycle = solve(3, &e).err().unwrap_or_default();
        assert!(cycle.contains(&2) && cycle.contains(&1), "{cycle:?}");
    }
}
