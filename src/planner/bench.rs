//! `mavtempo bench plan`: planning time and search steps on the shipped problems and on generated rover
//! problems (N picture goals over a grid of targets).

use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

use serde::Serialize;

use super::{solve, Budget};
use crate::lang::{load_domain, load_problem, parse_problem};
use crate::model::Domain;

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
pub struct BenchError(String);

/// A rover problem with `n` picture goals on a grid of targets 10 m apart around the base (storage and
/// horizon and battery large enough that only the tour, the PTU and the camera constrain the plan).
pub fn rover_grid_problem(n: usize) -> String {
    let side = (n as f64).sqrt().ceil() as usize;
    let mut s =
        format!("problem grid{n};\ndomain rover;\nhorizon 6h;\nobject base: location at (0, 0);\n");
    for i in 0..n {
        let (x, y) = ((i % side + 1) * 10, (i / side) * 10);
        s += &format!("object t{i}: location at ({x}, {y});\n");
    }
    s += "initial {\n AT_ROBOT() = base;\n ROBOT_STATUS() = STILL;\n PTU_POS() = FORWARD;\n MVT_INIT() = T;\n PTU_INIT() = T;\n PICTURE(*) = false;\n COMMUNICATED(*) = false;\n VISIBLE() = NONE;\n}\n";
    // 50 % per target covers any tour of the grid (0.5 % per metre, legs under 100 m).
    let battery = 100.max(50 * n);
    s += &format!(
        "resource STORAGE: level {n}, capacity {n};\nresource BATTERY: level {battery}, capacity {battery};\n"
    );
    for i in 0..n {
        s += &format!("goal g{i} {{ hold(PICTURE(t{i}): true, (st, et)); }}\n");
    }
    s
}

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
                super::PlanFailure::Search(
                    super::FailReason::Deadline { steps } | super::FailReason::Exhausted { steps },
                ) => *steps,
                _ => 0,
            },
            backtracks: 0,
            actions: 0,
            failure: Some(e.to_string()),
        },
    }
}

/// Plans each problem once (files under `domains`), with at most `max_steps` steps each.
pub fn run(domains: &Path, max_steps: u64) -> Result<Vec<PlanFigures>, BenchError> {
    let load_d = |name: &str| -> Result<Arc<Domain>, BenchError> {
        let path = domains.join(name).join(format!("{name}.ixt"));
        load_domain(&path)
            .map(Arc::new)
            .map_err(|e| BenchError(e.to_string()))
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
        let p = load_problem(&path, &d).map_err(|e| BenchError(e.to_string()))?;
        out.push(measure(
            &format!("{dom}/{prob}"),
            &d,
            Arc::new(p),
            max_steps,
        ));
    }
    for n in [10, 20, 40] {
        let text = rover_grid_problem(n);
        let p = parse_problem(&format!("grid{n}"), &text, &rover)
            .map_err(|e| BenchError(e.to_string()))?;
        out.push(measure(
            &format!("rover/grid{n}"),
            &rover,
            Arc::new(p),
            max_steps,
        ));
    }
    Ok(out)
}
