//! `mavtempo bench plan`: planning time and search steps on the shipped problems and on generated rover
//! problems (N picture goals over a grid of targets).

use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

use serde::Serialize;

use crate::lang::{load_domain, load_problem, parse_problem};
use crate::model::Domain;
use crate::planner::{solve, Budget};

/// Figures for one problem.
#[derive(Clone, Debug, Serialize)]
pub struct PlanFigures {
    pub problem: String,
    pub solved: bool,
    pub ms: f64,
    pub steps: u64,
    pub backtracks: u64,
    pub actions: usize,
    /// Why no plan was found (step budget, exhausted search ...).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub failure: Option<String>,
}

/// Why a benchmark could not run (a domain or problem file missing or invalid).
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct PlanBenchError(String);

fn measure(
    name: &str,
    d: &Arc<Domain>,
    p: Arc<crate::model::Problem>,
    max_steps: u64,
) -> PlanFigures {
    let t0 = Instant::now();
    let r = solve(d.clone(), p, Budget::steps(max_steps));
    let ms = t0.elapsed().as_secs_f64() * 1e3;
    match r {
        Ok(planned) => PlanFigures {
            problem: name.into(),
            solved: true,
            ms,
            steps: planned.steps,
            backtracks: planned.backtracks,
            actions: planned.plan.num_actions(),
            failure: None,
        },
        Err(e) => PlanFigures {
            problem: name.into(),
            solved: false,
            ms,
            steps: match &e {
                crate::planner::PlanFailure::Search(
                    crate::planner::FailReason::Deadline { steps }
                    | crate::planner::FailReason::Exhausted { steps },
                ) => *steps,
                _ => 0,
            },
            backtracks: 0,
            actions: 0,
            failure: Some(e.to_string()),
        },
    }
}

/// The generated rover grids `bench plan` measures unless told which (`--grid N`).
pub const DEFAULT_GRIDS: [usize; 3] = [10, 20, 40];

/// Plans each shipped problem and a rover grid of each size in `grids` once (files under `domains`), with
/// at most `max_steps` steps each.
pub fn run(
    domains: &Path,
    max_steps: u64,
    grids: &[usize],
) -> Result<Vec<PlanFigures>, PlanBenchError> {
    let load_d = |name: &str| -> Result<Arc<Domain>, PlanBenchError> {
        let path = domains.join(name).join(format!("{name}.ixt"));
        load_domain(&path)
            .map(Arc::new)
            .map_err(|e| PlanBenchError(e.to_string()))
    };
    let mut out = Vec::new();
    let rover = load_d("rover")?;
    for (dom, d, prob) in [
        ("rover", rover.clone(), "fig2"),
        ("rover", rover.clone(), "dala"),
        ("auv", load_d("auv")?, "vents"),
        ("shopping", load_d("shopping")?, "day"),
    ] {
        let path = domains
            .join(dom)
            .join("problems")
            .join(format!("{prob}.ixt"));
        let p = load_problem(&path, &d).map_err(|e| PlanBenchError(e.to_string()))?;
        out.push(measure(
            &format!("{dom}/{prob}"),
            &d,
            Arc::new(p),
            max_steps,
        ));
    }
    for &n in grids {
        let text = crate::lang::generate::rover_grid_problem(n);
        let p = parse_problem(&format!("grid{n}"), &text, &rover)
            .map_err(|e| PlanBenchError(e.to_string()))?;
        out.push(measure(
            &format!("rover/grid{n}"),
            &rover,
            Arc::new(p),
            max_steps,
        ));
    }
    Ok(out)
}
