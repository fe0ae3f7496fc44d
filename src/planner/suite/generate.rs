//! Random planning problems of a given size on the shipped domains, for `mavtempo bench suite`: nobody
//! tuned the planner on them. Everything is drawn from the seed.
//!
//! - rover (domains/rover/rover.ixt): `n` picture targets within 60 m of the base; 3 storage slots, so the
//!   pictures need downloads in two or three visibility windows; a battery that is full or needs about one
//!   recharge; deadlines on some pictures; communication goals in some windows.
//! - auv (domains/auv/auv.ixt): `n` vents within 500 m and 300 m deep, each to be sampled; back at the surface
//!   at the end.
//! - shopping (domains/shopping/shopping.ixt): `n` items sold at places of a random connected town, some
//!   wanted before a time; home at the end of the day.

use std::fmt::Write;

use rand::Rng;
use rand_chacha::ChaCha8Rng;

/// A shipped domain the suite generates for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum SuiteDomain {
    Rover,
    Auv,
    Shopping,
}

impl SuiteDomain {
    pub fn name(self) -> &'static str {
        match self {
            SuiteDomain::Rover => "rover",
            SuiteDomain::Auv => "auv",
            SuiteDomain::Shopping => "shopping",
        }
    }

    /// The sizes the suite runs.
    pub fn sizes(self) -> &'static [usize] {
        match self {
            SuiteDomain::Rover => &[4, 6, 8, 10, 12, 16, 20],
            SuiteDomain::Auv => &[2, 4, 6, 8, 10, 12],
            SuiteDomain::Shopping => &[2, 4, 6, 8],
        }
    }
}

/// The problem text of size `n` and `seed` on `domain`.
pub fn problem(domain: SuiteDomain, n: usize, seed: u64) -> String {
    let mut rng = <ChaCha8Rng as rand::SeedableRng>::seed_from_u64(seed ^ ((n as u64) << 32));
    match domain {
        SuiteDomain::Rover => rover(n, seed, &mut rng),
        SuiteDomain::Auv => auv(n, seed, &mut rng),
        SuiteDomain::Shopping => shopping(n, seed, &mut rng),
    }
}

/// A point at `r·[0.2, 1)` from the origin, in whole metres.
fn point(rng: &mut ChaCha8Rng, r: f64) -> (f64, f64) {
    let a = rng.gen_range(0.0..std::f64::consts::TAU);
    let d = rng.gen_range(r * 0.2..r);
    ((a.cos() * d).round(), (a.sin() * d).round())
}

fn rover(n: usize, seed: u64, rng: &mut ChaCha8Rng) -> String {
    let targets: Vec<(f64, f64)> = (0..n).map(|_| point(rng, 60.0)).collect();
    // A tour at the domain's slowest speed (0.3 m/s), pictures and downloads, with slack.
    let tour: f64 = targets.iter().map(|t| t.0.hypot(t.1)).sum::<f64>() * 1.2;
    let horizon_s = ((tour / 0.3 + 120.0 * n as f64 + 600.0) / 60.0).ceil() * 60.0;
    // Windows spread over the mission: enough of them for n pictures with 3 slots.
    let windows = (n.div_ceil(2)).clamp(2, 3);
    let span = horizon_s / windows as f64;
    let mut p = rover_opening(
        &format!("`mavtempo bench suite` (rover, n = {n}, seed {seed})"),
        &format!("rover{n}_{seed}"),
        horizon_s,
        &targets,
    );
    let mut opened = Vec::new();
    for w in 0..windows {
        let start = (span * w as f64 + rng.gen_range(0.2..0.5) * span).round();
        let end = (start + rng.gen_range(0.3..0.45) * span).round();
        // The domain names two windows (W1, W2): a third pass is W1's ground station again.
        let _ = writeln!(p, "    VISIBLE() = W{} at {start}s;", w % 2 + 1);
        let _ = writeln!(p, "    VISIBLE() = NONE at {end}s;");
        opened.push(end);
    }
    let _ = writeln!(p, "}}\n");
    // Moves cost 0.5 % per metre: full, or about one recharge short of the tour.
    let battery = if rng.gen_bool(0.5) {
        100.0
    } else {
        (tour * 0.5 * rng.gen_range(0.7..0.9))
            .clamp(20.0, 100.0)
            .round()
    };
    let _ = writeln!(p, "resource STORAGE: level 3, capacity 3;");
    let _ = writeln!(p, "resource BATTERY: level {battery}, capacity 100;\n");
    for i in 0..n {
        let prio = rng.gen_range(1..=3);
        let _ = write!(
            p,
            "goal picture_t{i} priority {prio} {{ hold(PICTURE(t{i}): true, (st, et));"
        );
        if rng.gen_bool(0.3) {
            let deadline = (horizon_s * rng.gen_range(0.5..0.9)).round();
            let _ = write!(p, " st in [0, {deadline}s];");
        }
        let _ = writeln!(p, " }}");
    }
    for (w, end) in opened.iter().enumerate().take(2) {
        if rng.gen_bool(0.3) {
            let _ = writeln!(
                p,
                "goal comm_w{0} priority 2 {{ hold(COMMUNICATED(W{0}): true, (st, et)); st in [0, {end}s]; }}",
                w + 1
            );
        }
    }
    p
}

/// The opening of a rover problem on domains/rover/rover.ixt: header, horizon, the base and the targets
/// (east, north metres) as locations, and the `initial` block's fixed part (the robot still at the base,
/// PTU forward, modules initialised, no picture, no window open); the caller adds the windows and closes it.
pub fn rover_opening(by: &str, name: &str, horizon_s: f64, targets: &[(f64, f64)]) -> String {
    let mut p = String::new();
    let _ = writeln!(p, "// Generated by {by}.");
    let _ = writeln!(p, "problem {name};\ndomain rover;\n");
    let _ = writeln!(p, "horizon {horizon_s}s;\n");
    let _ = writeln!(p, "object base: location at (0, 0);");
    for (i, (e, nn)) in targets.iter().enumerate() {
        let _ = writeln!(p, "object t{i}: location at ({e}, {nn});");
    }
    let _ = writeln!(p, "\ninitial {{");
    for line in [
        "AT_ROBOT() = base;",
        "ROBOT_STATUS() = STILL;",
        "PTU_POS() = FORWARD;",
        "MVT_INIT() = T;",
        "PTU_INIT() = T;",
        "PICTURE(*) = false;",
        "COMMUNICATED(*) = false;",
        "VISIBLE() = NONE;",
    ] {
        let _ = writeln!(p, "    {line}");
    }
    p
}

fn auv(n: usize, seed: u64, rng: &mut ChaCha8Rng) -> String {
    let vents: Vec<(f64, f64, f64)> = (0..n)
        .map(|_| {
            let (e, nn) = point(rng, 500.0);
            (e, nn, -(rng.gen_range(50..=300) as f64))
        })
        .collect();
    let legs: f64 = vents
        .iter()
        .map(|v| v.0.hypot(v.1).hypot(v.2) * 2.0)
        .sum::<f64>();
    let horizon_s = ((legs + 1500.0 * n as f64) * 1.5 / 60.0).ceil() * 60.0;
    let priorities: Vec<u32> = (0..n).map(|_| rng.gen_range(1..=3)).collect();
    auv_problem(
        &format!("`mavtempo bench suite` (auv, n = {n}, seed {seed})"),
        &format!("auv{n}_{seed}"),
        &vents,
        horizon_s,
        &priorities,
    )
}

/// An AUV problem on domains/auv/auv.ixt: `vents` (east, north, up metres) all connected to each other and
/// to the surface, each to be sampled with its priority, back at the surface at `horizon_s`.
pub fn auv_problem(
    by: &str,
    name: &str,
    vents: &[(f64, f64, f64)],
    horizon_s: f64,
    priorities: &[u32],
) -> String {
    let mut p = String::new();
    let _ = writeln!(p, "// Generated by {by}.");
    let _ = writeln!(p, "problem {name};\ndomain auv;\n");
    let _ = writeln!(p, "horizon {horizon_s}s;\n");
    let _ = writeln!(p, "object surface: location at (0, 0, 0);");
    for (i, v) in vents.iter().enumerate() {
        let _ = writeln!(
            p,
            "object vent{i}: location at ({}, {}, {});",
            v.0, v.1, v.2
        );
    }
    let _ = writeln!(
        p,
        "\ninitial {{\n    AUV_AT() = surface;\n    CONNECTED(*, *) = false;"
    );
    let names: Vec<String> = std::iter::once("surface".to_string())
        .chain((0..vents.len()).map(|i| format!("vent{i}")))
        .collect();
    for a in &names {
        for b in &names {
            if a != b {
                let _ = writeln!(p, "    CONNECTED({a}, {b}) = true;");
            }
        }
    }
    let _ = writeln!(p, "    SURVEYED(*) = false;\n    SAMPLED(*) = false;\n}}\n");
    for (i, prio) in priorities.iter().enumerate() {
        let _ = writeln!(
            p,
            "goal sample_vent{i} external priority {prio} {{ hold(SAMPLED(vent{i}): true, (st, et)); }}"
        );
    }
    let _ = writeln!(
        p,
        "goal at_surface internal priority 1 {{ hold(AUV_AT(): surface, (st, et)); st in [{horizon_s}s, {horizon_s}s]; }}"
    );
    p
}

fn shopping(n: usize, seed: u64, rng: &mut ChaCha8Rng) -> String {
    // A town of n/2 + 2 places: a random tree (each place joined to an earlier one), plus one shortcut.
    let places = n / 2 + 2;
    let mut roads: Vec<(usize, usize)> = (1..places).map(|i| (rng.gen_range(0..i), i)).collect();
    let (a, b) = (rng.gen_range(0..places), rng.gen_range(0..places));
    if a != b && !roads.contains(&(a.min(b), a.max(b))) {
        roads.push((a.min(b), a.max(b)));
    }
    let mut p = String::new();
    let _ = writeln!(
        p,
        "// Generated by `mavtempo bench suite` (shopping, n = {n}, seed {seed})."
    );
    let _ = writeln!(p, "problem shop{n}_{seed};\ndomain shopping;\n");
    let _ = writeln!(p, "start 08:00;\nhorizon 20:00;\n");
    let names: Vec<String> = (0..places)
        .map(|i| {
            if i == 0 {
                "home".to_string()
            } else {
                format!("shop{i}")
            }
        })
        .collect();
    let _ = writeln!(p, "object {}: place;", names.join(", "));
    let items: Vec<String> = (0..n).map(|i| format!("item{i}")).collect();
    let _ = writeln!(p, "object {}: item;\n", items.join(", "));
    let _ = writeln!(
        p,
        "initial {{\n    AT() = home;\n    CONNECTED(*, *) = false;\n    SELLS(*, *) = false;\n    HAVE(*) = false;"
    );
    for &(a, b) in &roads {
        let _ = writeln!(p, "    CONNECTED({}, {}) = true;", names[a], names[b]);
        let _ = writeln!(p, "    CONNECTED({}, {}) = true;", names[b], names[a]);
    }
    for it in &items {
        let shop = rng.gen_range(1..places);
        let _ = writeln!(p, "    SELLS({}, {it}) = true;", names[shop]);
    }
    let _ = writeln!(p, "}}\n");
    for it in &items {
        let prio = rng.gen_range(1..=3);
        let _ = write!(
            p,
            "goal have_{it} external priority {prio} {{ hold(HAVE({it}): true, (st, et));"
        );
        if rng.gen_bool(0.3) {
            let h = rng.gen_range(11..=17);
            let _ = write!(p, " st in [08:00, {h}:00];");
        }
        let _ = writeln!(p, " }}");
    }
    let _ = writeln!(
        p,
        "goal at_home internal priority 1 {{ hold(AT(): home, (st, et)); st in [20:00, 20:00]; }}"
    );
    p
}
