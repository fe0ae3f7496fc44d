//! Mutex groups (a simple monotonicity analysis in Helmert's sense): sets of fluent predicates of which at
//! most one atom per *key* (the counted arguments) is true in every reachable state. Each becomes one
//! multi-valued state variable of the model: `at ?r ?w` with key `?r` is `at(?r) = ?w` (`+oo` when the rover
//! is between waypoints); `empty ?s` / `full ?s` are one variable of `?s` with two values.
//!
//! A candidate is kept when the initial state has at most one atom per key, no timed initial literal
//! touches it, no condition or goal negates it, and every action that adds an atom of the group deletes
//! one with the same key at the same time or before, and only deletes atoms it requires (so a deletion
//! always removes the one true atom, and the model's event knows its `from` value).

use std::collections::{BTreeMap, BTreeSet, HashMap};

use super::ast::{Action, Arg, Atom, Domain, Effect, Init, Lit, Problem, When};

/// A multi-valued state variable recovered from predicates.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Group {
    /// The member predicates.
    pub preds: Vec<String>,
    /// For a single predicate: the position of its value argument (the others are the key). `None`: every
    /// argument is the key and each member predicate is one value.
    pub value_pos: Option<usize>,
}

impl Group {
    /// The key arguments and the value of an atom of a member (`None` value: the member itself).
    pub fn split<'a>(&self, atom: &'a Atom) -> (Vec<&'a Arg>, Option<&'a Arg>) {
        split_member(&atom.args, self.value_pos, None)
    }
}

/// The key arguments and the value of an atom of a group member, on any form of the arguments (as
/// written, as terms of a task, ground): with a `value_pos` its argument there, else `member` (the value
/// the member predicate stands for).
pub(super) fn split_member<T: Copy>(
    args: impl IntoIterator<Item = T>,
    value_pos: Option<usize>,
    member: Option<T>,
) -> (Vec<T>, Option<T>) {
    let mut key = Vec::new();
    let mut value = None;
    for (i, a) in args.into_iter().enumerate() {
        if Some(i) == value_pos {
            value = Some(a);
        } else {
            key.push(a);
        }
    }
    (key, if value_pos.is_some() { value } else { member })
}

/// Same variable or same constant (spans aside).
pub fn same_arg(a: &Arg, b: &Arg) -> bool {
    match (a, b) {
        (Arg::Var(x), Arg::Var(y)) | (Arg::Const(x), Arg::Const(y)) => x.name == y.name,
        _ => false,
    }
}

fn same_args(a: &[&Arg], b: &[&Arg]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| same_arg(x, y))
}

fn same_atom(a: &Atom, b: &Atom) -> bool {
    a.pred.name == b.pred.name
        && a.args.len() == b.args.len()
        && a.args.iter().zip(&b.args).all(|(x, y)| same_arg(x, y))
}

/// Finds the groups among `fluent` predicates (those some action or timed literal changes).
pub fn groups(d: &Domain, p: &Problem, fluent: &BTreeSet<String>) -> Vec<Group> {
    let negated = negated(d, p);
    let param_types: HashMap<&str, Vec<String>> = d
        .predicates
        .iter()
        .map(|(n, ps)| {
            let ts = ps
                .iter()
                .map(|t| {
                    t.types
                        .iter()
                        .map(|x| x.name.as_str())
                        .collect::<Vec<_>>()
                        .join("|")
                })
                .collect();
            (n.name.as_str(), ts)
        })
        .collect();
    let usable = |q: &str| fluent.contains(q) && !negated.contains(q);
    // Multi-predicate candidates: an action adds P(args) and deletes Q(args) with the same arguments.
    let mut parent: BTreeMap<String, String> = BTreeMap::new();
    fn find(parent: &BTreeMap<String, String>, x: &str) -> String {
        let mut x = x.to_string();
        while let Some(px) = parent.get(&x) {
            if *px == x {
                break;
            }
            x = px.clone();
        }
        x
    }
    for a in &d.actions {
        for (_, e) in &a.effects {
            let Effect::Add(add) = e else { continue };
            for (_, e2) in &a.effects {
                let Effect::Del(del) = e2 else { continue };
                let (pa, pd) = (&add.pred.name, &del.pred.name);
                if pa == pd || !usable(pa) || !usable(pd) {
                    continue;
                }
                let args_a: Vec<&Arg> = add.args.iter().collect();
                let args_d: Vec<&Arg> = del.args.iter().collect();
                if !same_args(&args_a, &args_d)
                    || param_types.get(pa.as_str()) != param_types.get(pd.as_str())
                {
                    continue;
                }
                parent.entry(pa.clone()).or_insert_with(|| pa.clone());
                parent.entry(pd.clone()).or_insert_with(|| pd.clone());
                let (ra, rd) = (find(&parent, pa), find(&parent, pd));
                if ra != rd {
                    parent.insert(ra, rd);
                }
            }
        }
    }
    let mut sets: BTreeMap<String, Vec<String>> = BTreeMap::new();
    for x in parent.keys() {
        sets.entry(find(&parent, x)).or_default().push(x.clone());
    }
    let mut out: Vec<Group> = Vec::new();
    let mut taken: BTreeSet<String> = BTreeSet::new();
    for preds in sets.into_values() {
        let g = Group {
            preds,
            value_pos: None,
        };
        if holds(&g, d, p) {
            taken.extend(g.preds.iter().cloned());
            out.push(g);
        }
    }
    for (name, params) in &d.predicates {
        if taken.contains(&name.name) || !usable(&name.name) || params.is_empty() {
            continue;
        }
        for v in (0..params.len()).rev() {
            let g = Group {
                preds: vec![name.name.clone()],
                value_pos: Some(v),
            };
            if holds(&g, d, p) {
                out.push(g);
                break;
            }
        }
    }
    out
}

/// Predicates negated in some condition or goal.
fn negated(d: &Domain, p: &Problem) -> BTreeSet<String> {
    let lits = d
        .actions
        .iter()
        .flat_map(|a| a.conditions.iter().map(|(_, l)| l))
        .chain(p.goal.iter());
    lits.filter_map(|l| match l {
        Lit::Neg(a) => Some(a.pred.name.clone()),
        _ => None,
    })
    .collect()
}

/// Whether the at-most-one invariant of `g` is proved (see the module's comment).
fn holds(g: &Group, d: &Domain, p: &Problem) -> bool {
    let member = |a: &Atom| g.preds.contains(&a.pred.name);
    let mut per_key: BTreeMap<Vec<String>, usize> = BTreeMap::new();
    for i in &p.init {
        match i {
            Init::Atom(a, None) if member(a) => {
                let (key, _) = g.split(a);
                let key: Vec<String> = key.iter().map(|x| x.name().name.clone()).collect();
                let n = per_key.entry(key).or_default();
                *n += 1;
                if *n > 1 {
                    return false;
                }
            }
            Init::Atom(a, Some(_)) | Init::NotAtom(a, _) if member(a) => return false,
            _ => {}
        }
    }
    d.actions.iter().all(|a| action_keeps(g, a))
}

fn action_keeps(g: &Group, a: &Action) -> bool {
    let member = |x: &Atom| g.preds.contains(&x.pred.name);
    let dels: Vec<(When, &Atom)> = a
        .effects
        .iter()
        .filter_map(|(w, e)| match e {
            Effect::Del(x) if member(x) => Some((*w, x)),
            _ => None,
        })
        .collect();
    // Every deletion removes an atom the action requires when it deletes it.
    for (w, del) in &dels {
        let required = a.conditions.iter().any(|(cw, l)| match l {
            Lit::Pos(c) => same_atom(c, del) && (*cw == When::Start || *w == When::End),
            _ => false,
        });
        if !required {
            return false;
        }
    }
    let mut used = vec![false; dels.len()];
    for (w, e) in &a.effects {
        let Effect::Add(add) = e else { continue };
        if !member(add) {
            continue;
        }
        let (key, _) = g.split(add);
        let matched = dels
            .iter()
            .enumerate()
            .position(|(i, (dw, del))| !used[i] && dw <= w && same_args(&g.split(del).0, &key));
        match matched {
            Some(i) => used[i] = true,
            None => return false,
        }
    }
    true
}
