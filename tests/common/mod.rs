//! Problems shared by the planner tests.

use std::path::Path;

use mavtempo::model::{Domain, Problem};

/// The shipped rover domain.
pub fn rover() -> Domain {
    mavtempo::lang::load_domain(Path::new("domains/rover/rover.ixt")).expect("shipped domain")
}

/// Fig. 2 with the battery at 35 %: the plan needs recharges and the search backtracks a few times.
pub fn fig2_low_battery(d: &Domain) -> Problem {
    let text = std::fs::read_to_string("domains/rover/problems/fig2.ixt")
        .expect("shipped problem")
        .replace(
            "resource BATTERY: level 90, capacity 100;",
            "resource BATTERY: level 35, capacity 100;",
        );
    mavtempo::lang::parse_problem("fig2-low-battery", &text, d).expect("problem parses")
}
