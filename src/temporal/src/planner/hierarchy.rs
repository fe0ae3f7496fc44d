//! The abstraction hierarchy used to order flaws (Knoblock's ordered monotonicity, used by IxTeT; seed 1
//! §3.3 relies on the same main attributes for causal-link removal).
//!
//! Attribute `A` *depends on* `B` when a task that establishes `A` (a primary event on `A`) also mentions
//! `B`: resolving a flaw on `A` may insert that task and so create flaws on `B`, never the other way
//! round. Attributes in a dependency cycle share a level; an attribute's level is one more than the
//! highest level it depends on. Flaws on the higher levels are resolved first: in the rover, the tour
//! (`AT_ROBOT`) is decided before the pan-and-tilt moves (`PTU_POS`) it implies, and those before the
//! module initialisations. Without this the search commits to a `PTU_POS` link at the start of some move
//! before the order of the moves exists, and chronological backtracking cannot undo it in time.
//!
//! Two kinds of attribute sit outside the ordering: attributes no task changes (static facts, predicted
//! exogenous ones such as `VISIBLE`) come first, since their resolvers are final links that prune early;
//! attributes that tasks change only as a *secondary* effect (`ROBOT_STATUS`) come last, since their
//! establishers are side effects of actions inserted for other reasons.

use crate::model::{AttrId, Domain};

/// Level of the attributes nothing changes (resolved first).
pub const STATIC: u32 = u32::MAX;
/// Level of the attributes only changed as side effects (resolved last).
pub const SECONDARY: u32 = 0;

/// The level of every attribute of a domain, and the dependencies it is computed from.
#[derive(Clone, Debug)]
pub struct Hierarchy {
    level: Vec<u32>,
    /// For each attribute A, the attributes B it depends on (a task establishing A mentions B).
    deps: Vec<Vec<usize>>,
    /// For each resource, the highest level among the main attributes of the tasks using it (at least 1).
    resource_level: Vec<u32>,
}

impl Hierarchy {
    pub fn new(domain: &Domain) -> Self {
        let n = domain.attrs.len();
        let mut deps: Vec<Vec<usize>> = vec![Vec::new(); n];
        let mut established = vec![false; n];
        let mut changed = vec![false; n];
        for task in &domain.tasks {
            let mentioned = task.attributes();
            for e in &task.events {
                changed[e.attr.index()] = true;
            }
            for a in task.main_attributes() {
                established[a.index()] = true;
                for &b in &mentioned {
                    if b != a && !deps[a.index()].contains(&b.index()) {
                        deps[a.index()].push(b.index());
                    }
                }
            }
        }
        let comp = strongly_connected(&deps);
        let n_comp = comp.iter().copied().max().map_or(0, |m| m + 1);
        // Tarjan numbers components in reverse topological order: a component's dependencies get smaller
        // numbers, so one pass in increasing order computes the heights.
        let mut height = vec![1u32; n_comp];
        let mut members: Vec<Vec<usize>> = vec![Vec::new(); n_comp];
        for (a, &c) in comp.iter().enumerate() {
            members[c].push(a);
        }
        for c in 0..n_comp {
            let mut h = 1;
            for &a in &members[c] {
                for &b in &deps[a] {
                    if comp[b] != c && established[b] {
                        h = h.max(height[comp[b]] + 1);
                    }
                }
            }
            height[c] = h;
        }
        let level: Vec<u32> = (0..n)
            .map(|a| {
                if !changed[a] {
                    STATIC
                } else if !established[a] {
                    SECONDARY
                } else {
                    height[comp[a]]
                }
            })
            .collect();
        let resource_level = (0..domain.resources.len())
            .map(|r| {
                domain
                    .tasks
                    .iter()
                    .filter(|t| t.usages.iter().any(|u| u.resource.index() == r))
                    .flat_map(|t| t.main_attributes())
                    .map(|a| level[a.index()])
                    .filter(|&l| l != STATIC)
                    .max()
                    .unwrap_or(1)
                    .max(1)
            })
            .collect();
        Hierarchy {
            level,
            deps,
            resource_level,
        }
    }

    /// Att^i of seed 1 §3.3 "Causal links removal": from the attributes of the flaws, every attribute of a
    /// task that may be inserted to repair them (a task with a main attribute in the set), up to a fixed
    /// point: the attributes reachable from `flawed` along the dependencies. Sorted.
    pub fn closure(&self, flawed: &[AttrId]) -> Vec<AttrId> {
        let mut att: Vec<AttrId> = flawed.to_vec();
        let mut i = 0;
        while i < att.len() {
            let a = att[i].index();
            i += 1;
            for &b in self.deps.get(a).map_or(&[][..], |d| &d[..]) {
                let b = AttrId::from_index(b);
                if !att.contains(&b) {
                    att.push(b);
                }
            }
        }
        att.sort();
        att.dedup();
        att
    }

    /// The highest level of the actions that can take part in a conflict on resource `r`.
    pub fn resource_level(&self, r: crate::model::ResourceId) -> u32 {
        self.resource_level.get(r.index()).copied().unwrap_or(1)
    }

    /// The level of `attr`: higher is resolved first.
    pub fn level(&self, attr: AttrId) -> u32 {
        self.level.get(attr.index()).copied().unwrap_or(SECONDARY)
    }
}

/// Tarjan's strongly connected components; returns each node's component number (components numbered
/// in reverse topological order of the condensation: a node's successors are in components numbered no
/// higher than its own).
fn strongly_connected(succ: &[Vec<usize>]) -> Vec<usize> {
    struct State<'a> {
        succ: &'a [Vec<usize>],
        index: Vec<Option<usize>>,
        low: Vec<usize>,
        on_stack: Vec<bool>,
        stack: Vec<usize>,
        comp: Vec<usize>,
        next_index: usize,
        next_comp: usize,
    }
    fn visit(s: &mut State, v: usize) {
        s.index[v] = Some(s.next_index);
        s.low[v] = s.next_index;
        s.next_index += 1;
        s.stack.push(v);
        s.on_stack[v] = true;
        for i in 0..s.succ[v].len() {
            let w = s.succ[v][i];
            match s.index[w] {
                None => {
                    visit(s, w);
                    s.low[v] = s.low[v].min(s.low[w]);
                }
                Some(iw) if s.on_stack[w] => s.low[v] = s.low[v].min(iw),
                Some(_) => {}
            }
        }
        if Some(s.low[v]) == s.index[v] {
            while let Some(w) = s.stack.pop() {
                s.on_stack[w] = false;
                s.comp[w] = s.next_comp;
                if w == v {
                    break;
                }
            }
            s.next_comp += 1;
        }
    }
    let n = succ.len();
    let mut s = State {
        succ,
        index: vec![None; n],
        low: vec![0; n],
        on_stack: vec![false; n],
        stack: Vec::new(),
        comp: vec![0; n],
        next_index: 0,
        next_comp: 0,
    };
    for v in 0..n {
        if s.index[v].is_none() {
            visit(&mut s, v);
        }
    }
    s.comp
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn components_are_in_reverse_topological_order() {
        // 0 -> 1 <-> 2 -> 3
        let succ = vec![vec![1], vec![2], vec![1, 3], vec![]];
        let c = strongly_connected(&succ);
        assert_eq!(c[1], c[2]);
        assert!(c[3] < c[1]);
        assert!(c[1] < c[0]);
    }

    #[test]
    fn rover_levels_follow_the_task_structure() {
        let dir = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
            .join("domains/rover/rover.ixt");
        let domain = crate::lang::load_domain(&dir).expect("shipped domain loads");
        let h = Hierarchy::new(&domain);
        let lvl = |name: &str| h.level(domain.attr_id(name).expect("attribute exists"));
        assert!(lvl("PICTURE") > lvl("AT_ROBOT"));
        assert!(lvl("AT_ROBOT") > lvl("PTU_POS"));
        assert!(lvl("PTU_POS") > lvl("PTU_INIT"));
        assert!(lvl("AT_ROBOT") > lvl("MVT_INIT"));
        assert_eq!(lvl("ROBOT_STATUS"), SECONDARY);
        assert_eq!(lvl("VISIBLE"), STATIC);
        assert!(lvl("MVT_INIT") > SECONDARY);
    }
}
