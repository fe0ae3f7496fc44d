//! The shortest paths between every two timepoints that avoid the origin, kept up to date as constraints
//! are added (opt-in: [`Stn::maintain_paths`]), so that an ordering query costs two look-ups instead of a
//! search: `d(a, b) = min(D[a][b], ub[b] − lb[a])`, the second term being the paths through the origin,
//! which the bounds price exactly (as in [`super::distance`]).
//!
//! Leaving the origin out is what keeps the updates local: every bound change would otherwise change the
//! distances of every pair through the origin. A new (or lowered) edge u→v of weight w improves `D[x][y]`
//! only for sources x whose path to v improves through it (`D[x][u] + w < D[x][v]`) and targets y
//! whose path from u does (`w + D[v][y] < D[u][y]`): the update costs one scan of the rows of u and v
//! for the targets, a search for the sources, and the pairs actually improved (the classic incremental
//! all-pairs update; IxTeT kept its networks' all-pairs matrix, see [`super::floyd_warshall`]). The
//! sources are found backwards from u (Ausiello et al.'s observation): the first edge x→z of a shortest
//! path x→u leads to a source z whenever x is one (`D[x][u] = w(x,z) + D[z][u]` and `D[x][v] ≤ w(x,z) +
//! D[z][v]`), so every source is an in-neighbour of a source, and the search visits the few sources
//! (5 of ~700 timepoints on average at grid 100) and their in-neighbours instead of reading the whole
//! column of u, one cache line per timepoint. A tightening in the middle of a long order still improves
//! the pairs on both sides of it: that is the cost that grows with the plan.
//!
//! Each improved entry is recorded (at most once per saved level) in the matrix's undo log, whose batches
//! are marked on the network's trail, and is undone by a restore. What the update cannot
//! follow drops the matrix, and the queries go back to searches: removing or reactivating a constraint (a
//! relaxation, or undoing one), restoring a level saved before the matrix was built, growing past
//! [`MAX_TIMEPOINTS`]. A clone of the network starts without it (it is a cache).

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use super::network::Stn;
use super::trail::Entry;
use super::{sat_add, Level, Time, INF};

/// The most timepoints the matrix is kept for (`n²` entries of 8 bytes: 32 MiB at this size).
pub const MAX_TIMEPOINTS: usize = 2048;

/// "No path" in the matrix. Entries are 32-bit (the planner's plans span days at most, in ms): a
/// distance that does not fit drops the matrix.
const NONE: i32 = i32::MAX;

fn pack(t: Time) -> Option<i32> {
    if t >= INF {
        Some(NONE)
    } else {
        i32::try_from(t)
            .ok()
            .filter(|&v| v != NONE && v != i32::MIN)
    }
}

/// The matrix, row-major with stride `cap`.
#[derive(Debug)]
pub(crate) struct Paths {
    n: usize,
    cap: usize,
    d: Vec<i32>,
    /// Per entry, 1 + the trail position of the mark of its last undo record (0: none). An entry
    /// recorded since the last level handed out is not recorded again: restoring any level undoes that
    /// record, which holds the entry's value at the level (distances tighten many times in one step).
    recorded: Vec<u32>,
    /// Undo records `(entry, old value)`, in batches each marked on the network's trail
    /// ([`Entry::Paths`]): a record costs 8 bytes, not a trail entry.
    undo: Vec<(u32, i32)>,
    /// The trail length at the last [`Stn::save`] (lowered by restores).
    last_save: usize,
    /// The trail level when built: restoring below it would undo changes the matrix has no record of.
    built_at: Level,
    /// The search for an update's sources: `seen[x] == search` iff x was reached by the current one.
    seen: Vec<u32>,
    search: u32,
    sources: Vec<u32>,
}

/// The optional matrix of a network; cloned empty.
#[derive(Debug, Default)]
pub(crate) struct PathsCache(pub Option<Box<Paths>>);

impl Clone for PathsCache {
    fn clone(&self) -> Self {
        PathsCache(None)
    }
}

impl Paths {
    #[inline]
    pub fn get(&self, x: u32, y: u32) -> Time {
        unpack(self.d[x as usize * self.cap + y as usize])
    }

    fn with_capacity(cap: usize, built_at: Level) -> Self {
        Paths {
            n: 0,
            cap,
            d: vec![NONE; cap * cap],
            recorded: vec![0; cap * cap],
            undo: Vec::new(),
            last_save: 0,
            built_at,
            seen: vec![0; cap],
            search: 0,
            sources: Vec::new(),
        }
    }

    /// Appends a timepoint with no path to or from any other; false when the matrix would grow too big.
    fn push_timepoint(&mut self) -> bool {
        let t = self.n;
        if t == self.cap {
            if self.cap >= MAX_TIMEPOINTS {
                return false;
            }
            let cap = (self.cap * 2).clamp(16, MAX_TIMEPOINTS);
            let mut d = vec![NONE; cap * cap];
            let mut recorded = vec![0; cap * cap];
            for x in 0..self.n {
                let (old, new) = (
                    x * self.cap..x * self.cap + self.n,
                    x * cap..x * cap + self.n,
                );
                d[new.clone()].copy_from_slice(&self.d[old.clone()]);
                recorded[new].copy_from_slice(&self.recorded[old]);
            }
            // Records name entries by their index: re-index them.
            for r in &mut self.undo {
                let (x, y) = (r.0 as usize / self.cap, r.0 as usize % self.cap);
                r.0 = (x * cap + y) as u32;
            }
            self.d = d;
            self.recorded = recorded;
            self.seen.resize(cap, 0);
            self.cap = cap;
        }
        // The row and column may hold a removed timepoint's values.
        for y in 0..=t {
            self.d[t * self.cap + y] = NONE;
            self.d[y * self.cap + t] = NONE;
            self.recorded[t * self.cap + y] = 0;
            self.recorded[y * self.cap + t] = 0;
        }
        self.d[t * self.cap + t] = 0;
        self.n += 1;
        true
    }
}

#[inline]
fn unpack(v: i32) -> Time {
    if v == NONE {
        INF
    } else {
        Time::from(v)
    }
}

impl Stn {
    /// Keeps the all-pairs matrix of paths avoiding the origin from now on (built now, in one Dijkstra per
    /// timepoint), unless the network has more than [`MAX_TIMEPOINTS`] timepoints.
    pub fn maintain_paths(&mut self) {
        if self.paths.0.is_some() {
            return;
        }
        let n = self.lb.len();
        if n > MAX_TIMEPOINTS {
            return;
        }
        let level = self.save();
        let mut p = Paths::with_capacity(n.next_power_of_two().clamp(16, MAX_TIMEPOINTS), level);
        p.last_save = self.trail.len();
        for _ in 0..n {
            p.push_timepoint();
        }
        let mut reduced = vec![INF; n];
        let mut heap = BinaryHeap::new();
        for s in 1..n {
            self.paths_from(s as u32, &mut reduced, &mut heap);
            let row = &mut p.d[s * p.cap..s * p.cap + n];
            for (y, &r) in reduced.iter().enumerate() {
                if r < INF && y != 0 {
                    // Undo the potentials: r = d + lb[s] − lb[y].
                    let Some(v) = pack(r + self.lb[y] - self.lb[s]) else {
                        return; // a span the 32-bit entries cannot hold: no matrix
                    };
                    row[y] = v;
                }
            }
        }
        self.paths.0 = Some(Box::new(p));
    }

    /// Whether the matrix is kept (queries are look-ups).
    pub fn has_paths(&self) -> bool {
        self.paths.0.is_some()
    }

    /// Reduced distances (`w + lb[tail] − lb[head]` ≥ 0, the earliest times being a solution) from `s` to
    /// every timepoint over the edges avoiding the origin, into `reduced`.
    fn paths_from(
        &self,
        s: u32,
        reduced: &mut [Time],
        heap: &mut BinaryHeap<Reverse<(Time, u32)>>,
    ) {
        reduced.iter_mut().for_each(|r| *r = INF);
        reduced[s as usize] = 0;
        heap.clear();
        heap.push(Reverse((0, s)));
        while let Some(Reverse((dx, x))) = heap.pop() {
            if dx != reduced[x as usize] {
                continue; // stale
            }
            for &(y, w) in &self.wout[x as usize] {
                if w >= INF || y == 0 {
                    continue;
                }
                let cand = dx + w + self.lb[x as usize] - self.lb[y as usize];
                if cand < reduced[y as usize] {
                    reduced[y as usize] = cand;
                    heap.push(Reverse((cand, y)));
                }
            }
        }
    }

    /// The shortest path a→b avoiding the origin, if the matrix is kept.
    #[inline]
    pub(crate) fn path_avoiding_origin(&self, a: u32, b: u32) -> Option<Time> {
        self.paths.0.as_ref().map(|p| p.get(a, b))
    }

    /// A timepoint was added (after it is in `lb`): its row and column, or the matrix dropped.
    pub(crate) fn paths_push_timepoint(&mut self) {
        if let Some(p) = &mut self.paths.0 {
            if !p.push_timepoint() {
                self.paths.0 = None;
            }
        }
    }

    /// The newest timepoint was undone.
    pub(crate) fn paths_pop_timepoint(&mut self) {
        if let Some(p) = &mut self.paths.0 {
            p.n -= 1;
        }
    }

    /// An edge the matrix cannot follow came or went (a removal, or its undoing).
    pub(crate) fn paths_drop(&mut self) {
        self.paths.0 = None;
    }

    /// Before a restore to `level`.
    pub(crate) fn paths_restoring(&mut self, level: Level) {
        if self.paths.0.as_ref().is_some_and(|p| level < p.built_at) {
            self.paths.0 = None;
        }
    }

    /// After a restore: the levels handed out since are invalid.
    pub(crate) fn paths_restored(&mut self) {
        let len = self.trail.len();
        if let Some(p) = &mut self.paths.0 {
            p.last_save = p.last_save.min(len);
        }
    }

    /// A level was handed out ([`Stn::save`]): changes from now on are recorded again.
    pub(crate) fn paths_saved(&mut self) {
        let len = self.trail.len();
        if let Some(p) = &mut self.paths.0 {
            p.last_save = len;
        }
    }

    /// Undoes the batch of records marked at `len` (the undo log's length before it).
    pub(crate) fn paths_undo(&mut self, len: u32) {
        if let Some(p) = &mut self.paths.0 {
            while p.undo.len() > len as usize {
                if let Some((at, old)) = p.undo.pop() {
                    p.d[at as usize] = old;
                    p.recorded[at as usize] = 0;
                }
            }
        }
    }

    /// The edge u→v of weight w was added or lowered in a consistent network: every pair whose shortest
    /// path improves through it.
    pub(crate) fn paths_add_edge(&mut self, u: u32, v: u32, w: Time) {
        let Some(p) = self.paths.0.as_mut() else {
            return;
        };
        if u == 0 || v == 0 || w >= INF || p.get(u, v) <= w {
            return;
        }
        let (n, cap) = (p.n, p.cap);
        let (u, v) = (u as usize, v as usize);
        // Targets whose path from u improves, with their distance from v.
        let mut targets: Vec<(usize, Time)> = Vec::new();
        for y in 1..n {
            let dvy = unpack(p.d[v * cap + y]);
            if dvy < INF && sat_add(w, dvy) < unpack(p.d[u * cap + y]) {
                targets.push((y, dvy));
            }
        }
        // Sources whose path to v improves, searched backwards from u (see the module docs); u itself is
        // one (`D[u][v] > w`). Found before any entry changes: the tests read the matrix before the edge.
        p.search = p.search.wrapping_add(1);
        if p.search == 0 {
            p.seen.iter_mut().for_each(|s| *s = 0);
            p.search = 1;
        }
        let search = p.search;
        let mut sources = std::mem::take(&mut p.sources);
        sources.clear();
        sources.push(u as u32);
        p.seen[u] = search;
        let mut next = 0;
        while next < sources.len() {
            let z = sources[next] as usize;
            next += 1;
            for h in &self.inc[z] {
                let k = &self.cons[h.c as usize];
                let (x, _, wxz) = k.edge(h.forward);
                let x = x as usize;
                if !k.active || wxz >= INF || x == 0 || p.seen[x] == search {
                    continue;
                }
                p.seen[x] = search;
                let dxu = unpack(p.d[x * cap + u]);
                if dxu < INF && sat_add(dxu, w) < unpack(p.d[x * cap + v]) {
                    sources.push(x as u32);
                }
            }
        }
        // The trail position of this batch's mark, once one record is made.
        let mut mark: Option<usize> = None;
        let mut fits = true;
        'sources: for &x in &sources {
            let x = x as usize;
            let via = sat_add(unpack(p.d[x * cap + u]), w);
            for &(y, dvy) in &targets {
                let at = x * cap + y;
                let cand = sat_add(via, dvy);
                if cand >= unpack(p.d[at]) {
                    continue;
                }
                let Some(packed) = pack(cand) else {
                    fits = false;
                    break 'sources;
                };
                if (p.recorded[at] as usize) <= p.last_save {
                    let pos = *mark.get_or_insert_with(|| {
                        let pos = self.trail.len();
                        self.trail.push(Entry::Paths(p.undo.len() as u32));
                        pos
                    });
                    p.recorded[at] = pos as u32 + 1;
                    p.undo.push((at as u32, p.d[at]));
                }
                p.d[at] = packed;
            }
        }
        p.sources = sources;
        if !fits {
            self.paths.0 = None;
        }
    }
}
