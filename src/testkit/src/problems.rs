//! Problems shared by the planner tests (each test binary uses some of them).

use std::path::Path;

use mavtempo_temporal::model::{Domain, Problem};

/// The shipped rover domain.
pub fn rover() -> Domain {
    mavtempo_temporal::lang::load_domain(Path::new(repo!("domains/rover/rover.ixt")))
        .expect("shipped domain")
}

/// Fig. 2 with the battery at 35 %: the plan needs recharges and the search backtracks a few times.
pub fn fig2_low_battery(d: &Domain) -> Problem {
    let text = std::fs::read_to_string(repo!("domains/rover/problems/fig2.ixt"))
        .expect("shipped problem")
        .replace(
            "resource BATTERY: level 90, capacity 100;",
            "resource BATTERY: level 35, capacity 100;",
        );
    mavtempo_temporal::lang::parse_problem("fig2-low-battery", &text, d).expect("problem parses")
}

/// Fig. 2 with g2's picture to start within `window` (e.g. `60s`) instead of 4 min.
pub fn fig2_with_g2_window(d: &Domain, window: &str) -> Problem {
    let text =
        std::fs::read_to_string(repo!("domains/rover/problems/fig2.ixt")).expect("shipped problem");
    let changed = text.replace("st in [0, 4min];", &format!("st in [0, {window}];"));
    assert_ne!(changed, text, "g2's window is in the shipped problem");
    mavtempo_temporal::lang::parse_problem("fig2-g2-window", &changed, d).expect("problem parses")
}

/// Fig. 2 with one more target `east` metres from home and a picture goal `gfar` of it, of `priority`.
pub fn fig2_with_far_target(d: &Domain, east: f64, priority: u32) -> Problem {
    let text =
        std::fs::read_to_string(repo!("domains/rover/problems/fig2.ixt")).expect("shipped problem");
    let anchor = "object p5: location at (40, 10);";
    assert!(text.contains(anchor), "p5 is in the shipped problem");
    let mut changed = text.replace(
        anchor,
        &format!("{anchor}\nobject far: location at ({east}, 0);"),
    );
    changed.push_str(&format!(
        "\ngoal gfar priority {priority} {{\n    hold(PICTURE(far): true, (st, et));\n    \
         st in [0, 30min];\n    achieve 60s;\n}}\n"
    ));
    mavtempo_temporal::lang::parse_problem("fig2-far", &changed, d).expect("problem parses")
}
