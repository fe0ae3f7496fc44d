//! Problem texts generated in the language, for tests and benchmarks of any size.

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
