//! The rover problems the planner's step-by-step comparisons run on: generated grids of 3, 7 and 12
//! targets, then the shipped fig2 and dala.

use std::sync::Arc;

use crate::model::{Domain, Problem};

/// The rover domain and its problems.
pub(super) fn rover_problems() -> (Arc<Domain>, Vec<Problem>) {
    let domains =
        std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).join("domains");
    let rover = Arc::new(
        crate::lang::load_domain(&domains.join("rover").join("rover.ixt")).expect("rover domain"),
    );
    let mut problems = Vec::new();
    for n in [3, 7, 12] {
        let text = crate::lang::generate::rover_grid_problem(n);
        problems.push(
            crate::lang::parse_problem(&format!("grid{n}"), &text, &rover).expect("grid problem"),
        );
    }
    for name in ["fig2", "dala"] {
        let path = domains
            .join("rover")
            .join("problems")
            .join(format!("{name}.ixt"));
        problems.push(crate::lang::load_problem(&path, &rover).expect("rover problem"));
    }
    (rover, problems)
}
