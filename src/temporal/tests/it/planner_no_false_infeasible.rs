//! Never a false "no plan" (issue 32): on small seeded random PDDL problems, whatever a brute-force forward
//! search finds a plan for is never declared infeasible by the reader, the translation or the planner
//! (search exhausted, no resolver at the root, a goal unreachable alone). A plan the planner does return
//! passes the independent checker and its replay on the PDDL (`pddl::solve` checks both).
//!
//! The oracle is written here, over the ground problem, sharing nothing with the translation: it runs the
//! durative actions one after the other (start effects, then the `over all` and `at end` conditions, then
//! the end effects), a sequential plan being a valid PDDL 2.1 plan.

use std::collections::{BTreeSet, HashSet, VecDeque};
use std::fmt::Write;

use mavtempo_temporal::pddl::{self, SolveError, Src};
use mavtempo_temporal::planner::{Budget, FailReason, PlanFailure};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum When {
    Start,
    OverAll,
    End,
}

/// A predicate applied to parameters (`Param(i)`) or objects (`Obj(i)`).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Arg {
    Param(usize),
    Obj(usize),
}

#[derive(Clone, Debug)]
struct Lit {
    pred: usize,
    args: Vec<Arg>,
    positive: bool,
}

#[derive(Clone, Debug)]
struct Action {
    params: usize,
    duration: u32,
    conds: Vec<(When, Lit)>,
    /// (at end?, literal: positive = add).
    effects: Vec<(bool, Lit)>,
}

#[derive(Clone, Debug)]
struct Problem {
    objects: usize,
    /// Arities.
    preds: Vec<usize>,
    actions: Vec<Action>,
    init: BTreeSet<(usize, Vec<usize>)>,
    goal: Vec<(usize, Vec<usize>, bool)>,
}

type Atom = (usize, Vec<usize>);

fn ground(l: &Lit, binding: &[usize]) -> Atom {
    let args = l
        .args
        .iter()
        .map(|a| match *a {
            Arg::Param(i) => binding[i],
            Arg::Obj(o) => o,
        })
        .collect();
    (l.pred, args)
}

/// Applies one ground action to `s` as a whole (start, then end); `None` when it does not apply or its
/// effects at one instant both add and delete an atom (left out: not a plan the oracle relies on).
fn apply(a: &Action, binding: &[usize], s: &BTreeSet<Atom>) -> Option<BTreeSet<Atom>> {
    let holds = |s: &BTreeSet<Atom>, w: When| {
        a.conds
            .iter()
            .filter(|(cw, _)| *cw == w)
            .all(|(_, l)| s.contains(&ground(l, binding)) == l.positive)
    };
    let effects = |s: &mut BTreeSet<Atom>, at_end: bool| -> Option<()> {
        let (adds, dels): (Vec<_>, Vec<_>) = a
            .effects
            .iter()
            .filter(|(e, _)| *e == at_end)
            .map(|(_, l)| (ground(l, binding), l.positive))
            .partition(|(_, add)| *add);
        let adds: HashSet<Atom> = adds.into_iter().map(|(x, _)| x).collect();
        for (d, _) in &dels {
            if adds.contains(d) {
                return None;
            }
            s.remove(d);
        }
        s.extend(adds);
        Some(())
    };
    if !holds(s, When::Start) {
        return None;
    }
    let mut mid = s.clone();
    effects(&mut mid, false)?;
    if !holds(&mid, When::OverAll) || !holds(&mid, When::End) {
        return None;
    }
    effects(&mut mid, true)?;
    Some(mid)
}

/// Breadth-first search over sequential plans: `Some(true)` a plan exists, `Some(false)` none (the
/// reachable states exhausted), `None` beyond `max_states`.
fn oracle(p: &Problem, max_states: usize) -> Option<bool> {
    let goal = |s: &BTreeSet<Atom>| {
        p.goal
            .iter()
            .all(|(pr, args, pos)| s.contains(&(*pr, args.clone())) == *pos)
    };
    let mut seen: HashSet<BTreeSet<Atom>> = HashSet::new();
    let mut queue = VecDeque::new();
    seen.insert(p.init.clone());
    queue.push_back(p.init.clone());
    while let Some(s) = queue.pop_front() {
        if goal(&s) {
            return Some(true);
        }
        for a in &p.actions {
            for binding in bindings(a.params, p.objects) {
                if let Some(next) = apply(a, &binding, &s) {
                    if seen.insert(next.clone()) {
                        if seen.len() > max_states {
                            return None;
                        }
                        queue.push_back(next);
                    }
                }
            }
        }
    }
    Some(false)
}

fn bindings(params: usize, objects: usize) -> Vec<Vec<usize>> {
    let mut out = vec![Vec::new()];
    for _ in 0..params {
        out = out
            .into_iter()
            .flat_map(|b| {
                (0..objects).map(move |o| {
                    let mut b = b.clone();
                    b.push(o);
                    b
                })
            })
            .collect();
    }
    out
}

fn random_lit(rng: &mut ChaCha8Rng, preds: &[usize], params: usize, objects: usize) -> Lit {
    let pred = rng.gen_range(0..preds.len());
    let args = (0..preds[pred])
        .map(|_| {
            if params > 0 && rng.gen_bool(0.85) {
                Arg::Param(rng.gen_range(0..params))
            } else {
                Arg::Obj(rng.gen_range(0..objects))
            }
        })
        .collect();
    Lit {
        pred,
        args,
        positive: true,
    }
}

/// Random STRIPS-like durative actions over a few predicates of arity 0–2.
fn random_problem(seed: u64) -> Problem {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let objects = rng.gen_range(2..=3);
    let preds: Vec<usize> = (0..rng.gen_range(2..=4))
        .map(|_| rng.gen_range(0..=2))
        .collect();
    let mut actions = Vec::new();
    for _ in 0..rng.gen_range(2..=4) {
        let params = rng.gen_range(0..=2);
        let mut conds = Vec::new();
        for _ in 0..rng.gen_range(1..=3) {
            let w = [When::Start, When::Start, When::OverAll, When::End][rng.gen_range(0..4)];
            let mut l = random_lit(&mut rng, &preds, params, objects);
            l.positive = rng.gen_bool(0.8);
            conds.push((w, l));
        }
        let mut effects = Vec::new();
        for _ in 0..rng.gen_range(1..=3) {
            let mut l = random_lit(&mut rng, &preds, params, objects);
            l.positive = rng.gen_bool(0.6);
            effects.push((rng.gen_bool(0.6), l));
        }
        actions.push(Action {
            params,
            duration: rng.gen_range(1..=3),
            conds,
            effects,
        });
    }
    let mut init = BTreeSet::new();
    for (pr, &arity) in preds.iter().enumerate() {
        for args in bindings(arity, objects) {
            if rng.gen_bool(0.35) {
                init.insert((pr, args));
            }
        }
    }
    let mut goal = Vec::new();
    for _ in 0..rng.gen_range(1..=3) {
        let pr = rng.gen_range(0..preds.len());
        let args = (0..preds[pr]).map(|_| rng.gen_range(0..objects)).collect();
        goal.push((pr, args, rng.gen_bool(0.8)));
    }
    Problem {
        objects,
        preds,
        actions,
        init,
        goal,
    }
}

/// A token walking a random graph (predicate 0: `at ?x`, 1: static `link ?a ?b`): plans of several moves,
/// each move's origin established by the move before it.
fn walk_problem(seed: u64) -> Problem {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let objects = rng.gen_range(4..=7);
    let mut init = BTreeSet::new();
    // A path 0 → 1 → ... → n-1, plus random extra links.
    for i in 0..objects - 1 {
        init.insert((1, vec![i, i + 1]));
        if rng.gen_bool(0.5) {
            init.insert((1, vec![i + 1, i]));
        }
    }
    for _ in 0..rng.gen_range(0..3) {
        let (a, b) = (rng.gen_range(0..objects), rng.gen_range(0..objects));
        if a != b {
            init.insert((1, vec![a, b]));
        }
    }
    init.insert((0, vec![0]));
    let at = |p| Lit {
        pred: 0,
        args: vec![Arg::Param(p)],
        positive: true,
    };
    let mv = Action {
        params: 2,
        duration: rng.gen_range(1..=3),
        conds: vec![
            (When::Start, at(0)),
            (
                When::Start,
                Lit {
                    pred: 1,
                    args: vec![Arg::Param(0), Arg::Param(1)],
                    positive: true,
                },
            ),
        ],
        effects: vec![
            (
                false,
                Lit {
                    positive: false,
                    ..at(0)
                },
            ),
            (true, at(1)),
        ],
    };
    Problem {
        objects,
        preds: vec![1, 2],
        actions: vec![mv],
        init,
        goal: vec![(0, vec![rng.gen_range(1..objects)], true)],
    }
}

fn pddl_lit(l: &Lit) -> String {
    let args: Vec<String> = l
        .args
        .iter()
        .map(|a| match a {
            Arg::Param(i) => format!("?x{i}"),
            Arg::Obj(o) => format!("o{o}"),
        })
        .collect();
    let atom = format!("(p{} {})", l.pred, args.join(" "));
    if l.positive {
        atom
    } else {
        format!("(not {atom})")
    }
}

fn pddl_texts(p: &Problem) -> (String, String) {
    let objects: Vec<String> = (0..p.objects).map(|o| format!("o{o}")).collect();
    let mut d = String::from("(define (domain gen)\n  (:requirements :typing :durative-actions :negative-preconditions)\n  (:types thing)\n");
    let _ = writeln!(d, "  (:constants {} - thing)", objects.join(" "));
    d.push_str("  (:predicates");
    for (i, &arity) in p.preds.iter().enumerate() {
        let ps: Vec<String> = (0..arity).map(|k| format!("?a{k} - thing")).collect();
        let _ = write!(d, " (p{i} {})", ps.join(" "));
    }
    d.push_str(")\n");
    for (i, a) in p.actions.iter().enumerate() {
        let ps: Vec<String> = (0..a.params).map(|k| format!("?x{k} - thing")).collect();
        let conds: Vec<String> = a
            .conds
            .iter()
            .map(|(w, l)| {
                let w = match w {
                    When::Start => "at start",
                    When::OverAll => "over all",
                    When::End => "at end",
                };
                format!("({w} {})", pddl_lit(l))
            })
            .collect();
        let effs: Vec<String> = a
            .effects
            .iter()
            .map(|(end, l)| {
                format!(
                    "({} {})",
                    if *end { "at end" } else { "at start" },
                    pddl_lit(l)
                )
            })
            .collect();
        let _ = writeln!(
            d,
            "  (:durative-action a{i} :parameters ({}) :duration (= ?duration {})\n    :condition (and {})\n    :effect (and {}))",
            ps.join(" "),
            a.duration,
            conds.join(" "),
            effs.join(" ")
        );
    }
    d.push_str(")\n");
    let atom = |pr: usize, args: &[usize]| {
        let a: Vec<String> = args.iter().map(|o| format!("o{o}")).collect();
        format!("(p{pr} {})", a.join(" "))
    };
    let init: Vec<String> = p.init.iter().map(|(pr, args)| atom(*pr, args)).collect();
    let goal: Vec<String> = p
        .goal
        .iter()
        .map(|(pr, args, pos)| {
            if *pos {
                atom(*pr, args)
            } else {
                format!("(not {})", atom(*pr, args))
            }
        })
        .collect();
    let pr = format!(
        "(define (problem g) (:domain gen)\n  (:init {})\n  (:goal (and {})))\n",
        init.join(" "),
        goal.join(" ")
    );
    (d, pr)
}

/// Whether mavtempo declares the problem infeasible (`Some(reason)`), else `None` (a checked plan, or the
/// budget ran out). A plan that fails its checks fails the test.
fn declared_infeasible(p: &Problem, what: &str) -> Option<String> {
    let (d, pr) = pddl_texts(p);
    let (ds, ps) = (
        Src::new("gen-domain.pddl", d.clone()),
        Src::new("gen-problem.pddl", pr.clone()),
    );
    let dom = pddl::parse_domain(&ds).unwrap_or_else(|e| panic!("{what}: {e}\n{d}"));
    let prob = pddl::parse_problem(&ps).unwrap_or_else(|e| panic!("{what}: {e}\n{pr}"));
    let translated = match pddl::translate(&ds, &dom, &ps, &prob) {
        Ok(t) => t,
        Err(e) => return Some(format!("translation: {e}")),
    };
    let loaded = pddl::Loaded {
        domain: dom,
        problem: prob,
        translated,
    };
    match pddl::solve(&loaded, Budget::steps(1_500)) {
        Ok(_) => None,
        Err(SolveError::NoPlan(PlanFailure::Search(FailReason::Deadline { .. }), _)) => None,
        Err(SolveError::NoPlan(why, _)) => Some(why.to_string()),
        Err(e) => panic!("{what}: a plan that fails its checks: {e}\n{d}\n{pr}"),
    }
}

/// Whether the forward search alone ([`pddl::Hybrid`]: grounding, h_FF search, deordering, completion by
/// the POCL search, the checker and the replay) finds a plan; `Err` says why not.
fn forward_plan(p: &Problem, what: &str) -> Result<(), String> {
    let (d, pr) = pddl_texts(p);
    let (ds, ps) = (
        Src::new("gen-domain.pddl", d),
        Src::new("gen-problem.pddl", pr),
    );
    let dom = pddl::parse_domain(&ds).map_err(|e| format!("{what}: {e}"))?;
    let prob = pddl::parse_problem(&ps).map_err(|e| format!("{what}: {e}"))?;
    let translated =
        pddl::translate(&ds, &dom, &ps, &prob).map_err(|e| format!("translation: {e}"))?;
    let loaded = pddl::Loaded {
        domain: dom,
        problem: prob,
        translated,
    };
    let mut hybrid = pddl::Hybrid::new(&loaded, None);
    match hybrid.slice(1_000_000, std::time::Duration::MAX) {
        Ok(_) => Ok(()),
        Err(_) => Err(hybrid.aside.unwrap_or_else(|| "paused".into())),
    }
}

/// Each draw of the family the oracle finds a plan for, with its name; `check` panics on a failure.
fn for_each_solvable(
    name: &str,
    make: fn(u64) -> Problem,
    seeds: std::ops::Range<u64>,
    check: &dyn Fn(&Problem, &str) -> Option<String>,
) -> usize {
    let mut solvable = 0;
    for seed in seeds {
        let p = make(seed);
        if oracle(&p, 20_000) != Some(true) {
            continue;
        }
        solvable += 1;
        let what = format!("{name} seed {seed}");
        if let Some(why) = check(&p, &what) {
            let (d, pr) = pddl_texts(&p);
            panic!("{what}: the oracle finds a plan, mavtempo says: {why}\n{d}\n{pr}");
        }
    }
    solvable
}

fn check_family(name: &str, make: fn(u64) -> Problem, seeds: std::ops::Range<u64>) -> usize {
    for_each_solvable(name, make, seeds, &declared_infeasible)
}

#[test]
fn random_strips_problems_a_plan_exists_for_are_never_declared_infeasible() {
    let solvable = check_family("random", random_problem, 0..100);
    // The family must exercise the property: most draws have a plan.
    assert!(solvable >= 30, "only {solvable} solvable draws");
}

#[test]
fn walks_longer_than_the_first_regression_bound_are_never_declared_infeasible() {
    let solvable = check_family("walk", walk_problem, 0..30);
    assert!(solvable >= 20, "only {solvable} solvable draws");
}

/// The forward search is complete for sequential plans (every reachable state is expanded): whatever
/// the sequential oracle solves, it solves, and its plan, deordered and completed, passes the checks.
#[test]
fn the_forward_search_solves_what_the_oracle_solves() {
    let forward = |p: &Problem, what: &str| forward_plan(p, what).err();
    let solvable = for_each_solvable("random", random_problem, 0..100, &forward)
        + for_each_solvable("walk", walk_problem, 0..30, &forward);
    assert!(solvable >= 50, "only {solvable} solvable draws");
}

#[test]
fn the_oracle_tells_a_dead_end_from_a_plan() {
    // A walk whose goal lies against every link: no plan; with the path: a plan of n - 1 moves.
    let mut p = walk_problem(1);
    assert_eq!(oracle(&p, 20_000), Some(true));
    p.init.retain(|(pr, _)| *pr != 1);
    assert_eq!(oracle(&p, 20_000), Some(false));
}
