//! Morris's O(n³) dynamic-controllability check (P. Morris, "Dynamic controllability and dispatchability
//! relationships", CPAIOR 2014).
//!
//! The network is first put in normal form: each contingent link `(A, l, u, C)` becomes a requirement
//! `A'' − A = l` to a helper node `A''` and a contingent link `(A'', 0, u − l, C)`. Its labelled distance
//! graph has the requirement edges, a lower-case edge `A'' −c:0→ C` and an upper-case edge
//! `C −C:−(u−l)→ A''` per link. A *negative node* has a negative incoming edge. From each negative node
//! (`DCbackprop`) a Dijkstra runs backwards over non-negative edges, starting from the node's negative
//! incoming edges: a node reached at a distance `d ≥ 0` gets a new edge of weight `d` to the source (the
//! lower-case, cross-case and no-case reductions of the path; an upper-case label is removed since
//! `d ≥ 0 ≥ −(u − l)`) and is not extended further; a negative node reached at a negative distance is
//! itself processed first (recursively), so that the paths through it use its new non-negative edges. A
//! recursion that comes back to a node it is still processing found a semi-reducible negative cycle: the
//! network is not DC. A lower-case edge is unsuitable to extend a path that starts with the upper-case edge
//! of the same link (that path is the link itself, not a constraint on it).
//!
//! A path from a node `X` to `A''` that starts (from `A''`'s side) with the upper-case edge and has a
//! negative length `d` is an upper-case reduction `X −C:d→ A''`: `X` waits until `A'' − d` unless `C` is
//! observed. These are the dispatchable network's waits; a path from `X` whose best distance comes from
//! an ordinary edge is ordinary and needs no wait.

use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashMap, HashSet};

use super::stnu::{DerivedEdge, Dispatchable, NotDc, Stnu, Wait};
use super::{sat_add, Time, INF};

#[derive(Copy, Clone, Eq, PartialEq, Debug)]
enum Kind {
    Ordinary,
    /// The lower-case edge `A'' → C` of a link.
    Lower(usize),
    /// The upper-case edge `C → A''` of a link.
    Upper(usize),
}

#[derive(Clone, Debug)]
enum Origin {
    Requirement(usize),
    Link(usize),
    /// Added by a back-propagation: the edges of the path it summarises.
    Derived(Vec<usize>),
}

#[derive(Clone, Debug)]
struct Edge {
    from: usize,
    to: usize,
    w: Time,
    kind: Kind,
    origin: Origin,
}

#[derive(Copy, Clone, Eq, PartialEq)]
enum Status {
    Fresh,
    /// Its back-propagation is on the call stack.
    Ancestor,
    Done,
}

/// A semi-reducible negative cycle being assembled while the recursion unwinds.
struct Fail {
    /// The node whose back-propagation was re-entered.
    target: usize,
    edges: Vec<usize>,
    closed: bool,
}

/// Label of a back-propagated path: does it start with the source's upper-case edge?
const ORD: usize = 0;
const UPPER: usize = 1;
const NO_EDGE: usize = usize::MAX;

struct Checker<'a> {
    stnu: &'a Stnu,
    edges: Vec<Edge>,
    /// Incoming edges of each node (original nodes, then one helper `A''` per link).
    incoming: Vec<Vec<usize>>,
    derived: HashMap<(usize, usize), usize>,
    negative: Vec<bool>,
    status: Vec<Status>,
    /// The link whose helper node each node is, if any.
    helper_link: Vec<Option<usize>>,
    waits: Vec<Wait>,
}

/// Decides dynamic controllability (see the module's documentation).
pub fn check(stnu: &Stnu) -> Result<Dispatchable, NotDc> {
    let mut c = Checker::new(stnu);
    for v in 0..c.incoming.len() {
        if c.negative[v] {
            if let Err(f) = c.backprop(v) {
                return Err(c.explain(&f.edges));
            }
        }
    }
    Ok(c.dispatchable())
}

/// The waits and edges every back-propagation that succeeds derives, going on past the ones that find a
/// semi-reducible negative cycle; with the first such conflict. On a DC network, [`check`]'s result.
pub fn best_effort(stnu: &Stnu) -> (Dispatchable, Option<NotDc>) {
    let mut c = Checker::new(stnu);
    let mut first = None;
    for v in 0..c.incoming.len() {
        if c.negative[v] {
            if let Err(f) = c.backprop(v) {
                // The failed chain was left unprocessed: later sources may retry its nodes.
                for s in c.status.iter_mut() {
                    if *s == Status::Ancestor {
                        *s = Status::Fresh;
                    }
                }
                if first.is_none() {
                    first = Some(c.explain(&f.edges));
                }
            }
        }
    }
    (c.dispatchable(), first)
}

impl<'a> Checker<'a> {
    fn new(stnu: &'a Stnu) -> Self {
        let n = stnu.num_nodes();
        let total = n + stnu.links().len();
        let mut c = Checker {
            stnu,
            edges: Vec::new(),
            incoming: vec![Vec::new(); total],
            derived: HashMap::new(),
            negative: vec![false; total],
            status: vec![Status::Fresh; total],
            helper_link: vec![None; total],
            waits: Vec::new(),
        };
        for (i, r) in stnu.requirements().iter().enumerate() {
            if r.ub < INF {
                c.add(r.from, r.to, r.ub, Kind::Ordinary, Origin::Requirement(i));
            }
            if r.lb > -INF {
                c.add(r.to, r.from, -r.lb, Kind::Ordinary, Origin::Requirement(i));
            }
        }
        for (k, l) in stnu.links().iter().enumerate() {
            let (a, cn) = (l.activation, l.contingent);
            if l.lower == l.upper {
                // No uncertainty: a plain requirement.
                c.add(a, cn, l.upper, Kind::Ordinary, Origin::Link(k));
                c.add(cn, a, -l.lower, Kind::Ordinary, Origin::Link(k));
                continue;
            }
            let h = n + k;
            c.helper_link[h] = Some(k);
            c.add(a, h, l.lower, Kind::Ordinary, Origin::Link(k));
            c.add(h, a, -l.lower, Kind::Ordinary, Origin::Link(k));
            c.add(h, cn, 0, Kind::Lower(k), Origin::Link(k));
            c.add(cn, h, l.lower - l.upper, Kind::Upper(k), Origin::Link(k));
        }
        c
    }

    fn add(&mut self, from: usize, to: usize, w: Time, kind: Kind, origin: Origin) -> usize {
        let id = self.edges.len();
        self.edges.push(Edge {
            from,
            to,
            w,
            kind,
            origin,
        });
        self.incoming[to].push(id);
        if w < 0 {
            self.negative[to] = true;
        }
        id
    }

    /// Where `node` sits relative to an original node: helper `A''` of link `(A, l, ..)` is `A + l`.
    fn as_original(&self, node: usize) -> (usize, Time) {
        match self.helper_link[node] {
            Some(k) => {
                let l = self.stnu.links()[k];
                (l.activation, l.lower)
            }
            None => (node, 0),
        }
    }

    fn is_contingent(&self, node: usize) -> bool {
        self.stnu.links().iter().any(|l| l.contingent == node)
    }

    fn backprop(&mut self, source: usize) -> Result<(), Fail> {
        match self.status[source] {
            Status::Ancestor => {
                return Err(Fail {
                    target: source,
                    edges: Vec::new(),
                    closed: false,
                })
            }
            Status::Done => return Ok(()),
            Status::Fresh => {}
        }
        self.status[source] = Status::Ancestor;
        let total = self.incoming.len();
        let own_link = self.helper_link[source];
        let mut dist = [vec![INF; total], vec![INF; total]];
        let mut pred = [vec![NO_EDGE; total], vec![NO_EDGE; total]];
        dist[ORD][source] = 0;
        let mut queue = BinaryHeap::new();
        for &e in &self.incoming[source] {
            let ed = &self.edges[e];
            if ed.w >= 0 {
                continue;
            }
            let label = if matches!(ed.kind, Kind::Upper(_)) {
                UPPER
            } else {
                ORD
            };
            let v = ed.from;
            if ed.w < dist[label][v] && ed.w < dist[ORD][v] {
                dist[label][v] = ed.w;
                pred[label][v] = e;
                queue.push(Reverse((ed.w, v, label)));
            }
        }
        while let Some(Reverse((d, u, label))) = queue.pop() {
            // Stale entry, or an upper-case path dominated by an ordinary one as short.
            if d != dist[label][u] || (label == UPPER && dist[ORD][u] <= d) {
                continue;
            }
            if d >= 0 {
                let path = path_to(&pred[label], &self.edges, u, source);
                self.add_derived(u, source, d, path);
                continue;
            }
            if self.negative[u] {
                if let Err(mut f) = self.backprop(u) {
                    if !f.closed {
                        f.edges
                            .extend(path_to(&pred[label], &self.edges, u, source));
                        f.closed = source == f.target;
                    }
                    self.status[source] = Status::Fresh;
                    return Err(f);
                }
            }
            for i in 0..self.incoming[u].len() {
                let e = self.incoming[u][i];
                let ed = &self.edges[e];
                if ed.w < 0 {
                    continue;
                }
                if label == UPPER && own_link.is_some_and(|k| ed.kind == Kind::Lower(k)) {
                    continue; // unsuitable
                }
                let v = ed.from;
                let new = sat_add(d, ed.w);
                if new < dist[ORD][v] && new < dist[label][v] {
                    dist[label][v] = new;
                    pred[label][v] = e;
                    queue.push(Reverse((new, v, label)));
                }
            }
        }
        if let Some(k) = own_link {
            self.record_waits(k, source, &dist);
        }
        self.status[source] = Status::Done;
        Ok(())
    }

    /// The upper-case reductions `X −C:d→ A''` with `d < 0` that no ordinary path dominates.
    fn record_waits(&mut self, k: usize, source: usize, dist: &[Vec<Time>; 2]) {
        let (_, at) = self.as_original(source);
        let link = self.stnu.links()[k];
        for (v, (&d, &ord)) in dist[UPPER].iter().zip(&dist[ORD]).enumerate() {
            if d >= 0 || ord <= d || v == link.contingent || v == source {
                continue;
            }
            let (node, off) = self.as_original(v);
            if self.is_contingent(node) || node == link.activation {
                continue;
            }
            // v − A'' ≥ −d, with A'' = A + at and v = node + off.
            self.waits.push(Wait {
                node,
                link: k,
                delay: at - d - off,
            });
        }
    }

    fn add_derived(&mut self, from: usize, to: usize, w: Time, path: Vec<usize>) {
        if from == to {
            return;
        }
        match self.derived.get(&(from, to)) {
            Some(&e) if self.edges[e].w <= w => {}
            Some(&e) => {
                self.edges[e].w = w;
                self.edges[e].origin = Origin::Derived(path);
            }
            None => {
                let e = self.add(from, to, w, Kind::Ordinary, Origin::Derived(path));
                self.derived.insert((from, to), e);
            }
        }
    }

    /// The links and requirements behind a cycle of (possibly derived) edges.
    fn explain(&self, cycle: &[usize]) -> NotDc {
        let mut links = Vec::new();
        let mut requirements = Vec::new();
        let mut seen = HashSet::new();
        let mut stack: Vec<usize> = cycle.to_vec();
        while let Some(e) = stack.pop() {
            if !seen.insert(e) {
                continue;
            }
            match &self.edges[e].origin {
                Origin::Requirement(i) => requirements.push(*i),
                Origin::Link(k) => links.push(*k),
                Origin::Derived(path) => stack.extend(path.iter().copied()),
            }
        }
        links.sort_unstable();
        links.dedup();
        requirements.sort_unstable();
        requirements.dedup();
        NotDc {
            links,
            requirements,
        }
    }

    fn dispatchable(&self) -> Dispatchable {
        let edges = self
            .derived
            .values()
            .filter_map(|&e| {
                let ed = &self.edges[e];
                let (from, off_from) = self.as_original(ed.from);
                let (to, off_to) = self.as_original(ed.to);
                (from != to).then_some(DerivedEdge {
                    from,
                    to,
                    weight: ed.w + off_from - off_to,
                })
            })
            .collect();
        Dispatchable {
            edges,
            waits: self.waits.clone(),
        }
    }
}

/// The edges of the back-propagated path from `u` to `source` (`pred[v]` is the first edge from `v`).
fn path_to(pred: &[usize], edges: &[Edge], u: usize, source: usize) -> Vec<usize> {
    let mut out = Vec::new();
    let mut v = u;
    // A path has at most one edge per node.
    for _ in 0..pred.len() {
        if v == source && !out.is_empty() {
            break;
        }
        let e = pred[v];
        if e == NO_EDGE {
            break;
        }
        out.push(e);
        v = edges[e].to;
        if v == source {
            break;
        }
    }
    out
}
