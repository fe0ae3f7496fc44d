//! `mavtempo bench suite`: random problems of growing size on the shipped domains ([`generate`]), each
//! planned within a time limit and its plan checked by the independent checker; solved share and times per
//! size. `--write DIR` keeps the problems so that other planners can be run on the same ones (`--pddl`: in
//! PDDL too, [`pddl`]).

pub mod generate;
pub mod native;
pub mod pddl;

use std::path::Path;
use std::sync::Arc;
use std::time::{Duration, Instant};

use generate::{Mission, SuiteDomain};

use crate::lang::{load_domain, parse_problem};
use crate::plan::validate::validate;
use crate::planner::{solve, Budget};

/// A shipped domain that does not load.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct SuiteError(String);

/// One problem's outcome.
#[derive(Clone, Debug, serde::Serialize)]
pub struct SuiteRun {
    pub domain: SuiteDomain,
    pub size: usize,
    pub seed: u64,
    /// Solved and the plan accepted by the checker.
    pub solved: bool,
    pub ms: f64,
    pub steps: u64,
    pub actions: usize,
    /// Why not solved (the planner's reason, or the checker's).
    pub failure: Option<String>,
}

/// The figures of one size.
#[derive(Clone, Debug, serde::Serialize)]
pub struct SuiteSize {
    pub domain: SuiteDomain,
    pub size: usize,
    pub problems: usize,
    pub solved: usize,
    /// Median planning time of the solved problems, ms.
    pub median_ms: Option<f64>,
    pub max_ms: Option<f64>,
}

/// How the suite runs.
#[derive(Clone, Debug)]
pub struct SuiteOptions {
    pub seeds: u64,
    pub first_seed: u64,
    pub time_limit: Duration,
    /// Only this domain (all three otherwise).
    pub domain: Option<SuiteDomain>,
    /// Only sizes up to this one.
    pub max_size: Option<usize>,
}

/// Runs the suite; `each` sees every problem's outcome as it comes (with its mission and native text).
pub fn run(
    domains: &Path,
    opts: &SuiteOptions,
    each: &mut dyn FnMut(&SuiteRun, &Mission, &str),
) -> Result<Vec<SuiteSize>, SuiteError> {
    let mut sizes = Vec::new();
    for dom in [SuiteDomain::Rover, SuiteDomain::Auv, SuiteDomain::Shopping] {
        if opts.domain.is_some_and(|d| d != dom) {
            continue;
        }
        let path = domains.join(dom.name()).join(format!("{}.ixt", dom.name()));
        let d = Arc::new(load_domain(&path).map_err(|e| SuiteError(e.to_string()))?);
        for &n in dom.sizes() {
            if opts.max_size.is_some_and(|m| n > m) {
                continue;
            }
            let mut times = Vec::new();
            let mut solved = 0;
            for seed in opts.first_seed..opts.first_seed + opts.seeds {
                let mission = generate::draw(dom, n, seed);
                let text = native::render(&mission);
                let r = one(&d, dom, n, seed, &text, opts.time_limit);
                if r.solved {
                    solved += 1;
                    times.push(r.ms);
                }
                each(&r, &mission, &text);
            }
            times.sort_by(f64::total_cmp);
            sizes.push(SuiteSize {
                domain: dom,
                size: n,
                problems: opts.seeds as usize,
                solved,
                median_ms: (!times.is_empty()).then(|| times[times.len() / 2]),
                max_ms: times.last().copied(),
            });
        }
    }
    Ok(sizes)
}

fn one(
    d: &Arc<crate::model::Domain>,
    dom: SuiteDomain,
    n: usize,
    seed: u64,
    text: &str,
    limit: Duration,
) -> SuiteRun {
    let mut run = SuiteRun {
        domain: dom,
        size: n,
        seed,
        solved: false,
        ms: 0.0,
        steps: 0,
        actions: 0,
        failure: None,
    };
    let p = match parse_problem(&format!("{}{n}_{seed}", dom.name()), text, d) {
        Ok(p) => Arc::new(p),
        Err(e) => {
            run.failure = Some(format!("generated problem does not parse: {e}"));
            return run;
        }
    };
    let budget = Budget {
        max_steps: None,
        deadline: Some(Instant::now() + limit),
    };
    let t0 = Instant::now();
    let r = solve(d.clone(), p.clone(), budget);
    run.ms = t0.elapsed().as_secs_f64() * 1e3;
    match r {
        Ok(planned) => {
            run.steps = planned.steps;
            run.actions = planned.plan.num_actions();
            let sol = planned.plan.to_solution(&std::collections::HashMap::new());
            match validate(d, &p, &sol) {
                Ok(_) => run.solved = true,
                Err(e) => run.failure = Some(format!("checker rejects the plan: {e}")),
            }
        }
        Err(e) => run.failure = Some(e.to_string()),
    }
    run
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_generated_problem_parses_on_its_domain() {
        for dom in [SuiteDomain::Rover, SuiteDomain::Auv, SuiteDomain::Shopping] {
            let path = format!("domains/{0}/{0}.ixt", dom.name());
            let d = load_domain(Path::new(&path)).expect("shipped domain");
            for &n in dom.sizes() {
                for seed in 0..3 {
                    let text = generate::problem(dom, n, seed);
                    if let Err(e) = parse_problem("gen", &text, &d) {
                        panic!("{} n={n} seed={seed}: {e}\n{text}", dom.name());
                    }
                    assert_eq!(text, generate::problem(dom, n, seed), "deterministic");
                }
            }
        }
    }
}
