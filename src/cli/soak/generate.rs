//! Random missions for the soak: a problem (in the domain language) on a shipped domain, the SITL scenario
//! that agrees with it (the same windows, speeds, storage and battery), random faults injected by the SITL,
//! and goals uploaded over MAVLink during the run. Everything is drawn from one seed.

use std::fmt::Write;

use rand::seq::SliceRandom;
use rand::Rng;
use rand_chacha::ChaCha8Rng;

use crate::bench::suite::generate::{draw_auv, point_within, AuvDraw, AuvMission};

/// Which shipped domain a mission is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum SoakDomain {
    Rover,
    Auv,
    All,
    /// The shipped rover problems (fig2, dala) with their own SITL scenarios, and goals uploaded at
    /// random times, 10 to 150 m away (some need a recharge): does a new goal cost the goals held?
    Shipped,
}

/// A goal a simulated ground station uploads at `at_s` of mission time: a picture (rover) or a sample
/// (AUV) at `(east, north, up)` metres from home, to start within `[0, window_end_s]`.
#[derive(Clone, Debug)]
pub struct Upload {
    pub at_s: f64,
    pub command: u16,
    pub east: f64,
    pub north: f64,
    pub up: f64,
    pub priority: u32,
    pub window_end_s: f64,
}

/// One generated mission.
#[derive(Clone, Debug)]
pub struct Mission {
    pub seed: u64,
    pub domain: SoakDomain,
    pub problem: String,
    pub scenario: String,
    /// The kinds of fault injected (for the per-fault-class shares).
    pub faults: Vec<&'static str>,
    pub uploads: Vec<Upload>,
}

/// `MAV_CMD_IMAGE_START_CAPTURE`: a picture goal.
const PICTURE_CMD: u16 = 2000;

/// The mission of `seed` for `domain` (`All` alternates by seed).
pub fn mission(seed: u64, domain: SoakDomain) -> Mission {
    let mut rng = <ChaCha8Rng as rand::SeedableRng>::seed_from_u64(seed);
    let d = match domain {
        SoakDomain::All if seed % 3 == 2 => SoakDomain::Auv,
        SoakDomain::All => SoakDomain::Rover,
        d => d,
    };
    match d {
        SoakDomain::Auv => auv(seed, &mut rng),
        SoakDomain::Shipped => shipped(seed, &mut rng),
        _ => rover(seed, &mut rng),
    }
}

/// The shipped rover problems with their scenarios: (name, problem, scenario, horizon in s).
const SHIPPED: [(&str, &str, &str, f64); 2] = [
    (
        "fig2",
        include_str!("../../../domains/rover/problems/fig2.ixt"),
        include_str!("../../../sitl/scenarios/fig2.toml"),
        1800.0,
    ),
    (
        "dala",
        include_str!("../../../domains/rover/problems/dala.ixt"),
        include_str!("../../../sitl/scenarios/dala.toml"),
        1500.0,
    ),
];

/// A shipped rover problem (Fig. 2 for even seeds, Dala for odd ones) on its own scenario, and 1 to 3
/// picture goals uploaded during the first half of the mission, 10 to 150 m from home, priority 1 to 3.
fn shipped(seed: u64, rng: &mut ChaCha8Rng) -> Mission {
    let (name, problem, scenario, horizon_s) = SHIPPED[(seed % 2) as usize];
    let uploads = (0..rng.gen_range(1..=3))
        .map(|_| {
            let a = rng.gen_range(0.0..std::f64::consts::TAU);
            let d = rng.gen_range(10.0..150.0);
            Upload {
                at_s: rng.gen_range(20.0..horizon_s * 0.5).round(),
                command: PICTURE_CMD,
                east: (a.cos() * d).round(),
                north: (a.sin() * d).round(),
                up: 0.0,
                priority: rng.gen_range(1..=3),
                window_end_s: horizon_s - 60.0,
            }
        })
        .collect();
    Mission {
        seed,
        domain: SoakDomain::Shipped,
        problem: problem.to_string(),
        scenario: scenario.to_string(),
        faults: vec![name],
        uploads,
    }
}

/// A point at `r·[0.25, 1)` from the origin, in whole metres.
fn point(rng: &mut ChaCha8Rng, r: f64) -> (f64, f64) {
    point_within(rng, 0.25, r)
}

/// A rover mission on domains/rover/rover.ixt: 2 to 4 picture targets within 35 m, one or two visibility
/// windows (a download frees storage for a fourth picture; a communication goal in some), a battery that
/// is full or not, some deadlines.
fn rover(seed: u64, rng: &mut ChaCha8Rng) -> Mission {
    let n = rng.gen_range(2..=4);
    let horizon_s: f64 = rng.gen_range(15..=22) as f64 * 60.0;
    let targets: Vec<(f64, f64)> = (0..n).map(|_| point(rng, 35.0)).collect();
    let w1 = (rng.gen_range(60..=240) as f64, 0.0);
    let w1 = (w1.0, w1.0 + rng.gen_range(180..=360) as f64);
    let w2 = rng
        .gen_bool(0.5)
        .then(|| {
            let s = (w1.1 + rng.gen_range(60..=240) as f64).min(horizon_s - 300.0);
            (s, (s + 240.0).min(horizon_s - 60.0))
        })
        .filter(|w| w.0 > w1.1);
    let battery = if rng.gen_bool(0.7) {
        100.0
    } else {
        rng.gen_range(70..100) as f64
    };
    let mut p = crate::bench::suite::native::rover_opening(
        &format!("`mavtempo soak` (seed {seed})"),
        &format!("soak{seed}"),
        horizon_s,
        &targets,
    );
    let _ = writeln!(p, "    VISIBLE() = W1 at {}s;", w1.0);
    let _ = writeln!(p, "    VISIBLE() = NONE at {}s;", w1.1);
    if let Some(w2) = w2 {
        let _ = writeln!(p, "    VISIBLE() = W2 at {}s;", w2.0);
        let _ = writeln!(p, "    VISIBLE() = NONE at {}s;", w2.1);
    }
    let _ = writeln!(p, "}}\n");
    let _ = writeln!(p, "resource STORAGE: level 3, capacity 3;");
    let _ = writeln!(p, "resource BATTERY: level {battery}, capacity 100;\n");
    for i in 0..n {
        let prio = rng.gen_range(1..=3);
        let _ = write!(
            p,
            "goal picture_t{i} priority {prio} {{ hold(PICTURE(t{i}): true, (st, et));"
        );
        if rng.gen_bool(0.3) {
            let deadline = rng.gen_range(horizon_s * 0.5..horizon_s * 0.9).round();
            let _ = write!(p, " st in [0, {deadline}s];");
        }
        let _ = writeln!(p, " }}");
    }
    if rng.gen_bool(0.5) {
        let _ = writeln!(
            p,
            "goal comm_w1 priority 2 {{ hold(COMMUNICATED(W1): true, (st, et)); st in [0, {}s]; }}",
            w1.1
        );
    }
    let mut s = String::new();
    let _ = writeln!(s, "# Generated by `mavtempo soak` (seed {seed}).");
    let _ = writeln!(
        s,
        "[vehicle]\nspeed_mps = {:.2}\nmax_speed_mps = 0.6\naccel_mps2 = 0.5\nwp_radius_m = 1.0\n",
        rng.gen_range(0.35..0.55)
    );
    let _ = writeln!(s, "[battery]\ninitial_pct = {battery}\ndrain_pct_per_km = 500.0\ndrain_pct_per_min = 0.0\nrecharge_pct_per_min = 5.0\narm_min_pct = 5.0\n");
    let _ = writeln!(s, "[camera]\nsize_min_mib = 0.9\nsize_max_mib = 1.0\ncapture_time_s = {:.1}\nstorage_capacity_mib = 3.0\n", rng.gen_range(6.0..15.0));
    let _ = writeln!(
        s,
        "[[sunlit_zones]]\ncenter_m = [0.0, 0.0]\nradius_m = 1000.0\n"
    );
    for w in std::iter::once(w1).chain(w2) {
        let _ = writeln!(
            s,
            "[[visibility_windows]]\nstart_s = {}\nend_s = {}\nrate_mib_per_s = 0.2\n",
            w.0, w.1
        );
    }
    let mut faults = Vec::new();
    let far = targets.choose(rng).copied().unwrap_or((10.0, 0.0));
    rover_faults(rng, &mut s, &mut faults, horizon_s, far);
    let mut uploads = Vec::new();
    if rng.gen_bool(0.5) {
        for _ in 0..rng.gen_range(1..=2) {
            let (e, nn) = point(rng, 35.0);
            uploads.push(Upload {
                at_s: rng.gen_range(30.0..horizon_s * 0.5).round(),
                command: PICTURE_CMD,
                east: e,
                north: nn,
                up: 0.0,
                priority: rng.gen_range(1..=3),
                window_end_s: horizon_s - 60.0,
            });
        }
    }
    Mission {
        seed,
        domain: SoakDomain::Rover,
        problem: p,
        scenario: s,
        faults,
        uploads,
    }
}

fn fault(s: &mut String, when: &str, what: &str) {
    let _ = writeln!(s, "[[faults]]\nwhen = {{ {when} }}\nfault = {{ {what} }}\n");
}

/// Faults common to both vehicles: navigation failure, link quality and blackouts.
fn link_and_nav_faults(
    rng: &mut ChaCha8Rng,
    s: &mut String,
    faults: &mut Vec<&'static str>,
    horizon_s: f64,
) {
    if rng.gen_bool(0.2) {
        let at = rng.gen_range(20.0..horizon_s * 0.6).round();
        fault(
            s,
            &format!("at_s = {at}"),
            "kind = \"nav_fails\", duration_s = 0.0",
        );
        faults.push("nav_fails");
    }
    if rng.gen_bool(0.25) {
        let at = rng.gen_range(0.0..horizon_s * 0.6).round();
        let loss = rng.gen_range(0.02..0.15);
        fault(
            s,
            &format!("at_s = {at}"),
            &format!("kind = \"link_quality\", loss = {loss:.2}, duplicate = 0.02, reorder = 0.02, duration_s = 120.0"),
        );
        faults.push("link_quality");
    }
    if rng.gen_bool(0.2) {
        let at = rng.gen_range(10.0..horizon_s * 0.6).round();
        let d = rng.gen_range(3..=20);
        fault(
            s,
            &format!("at_s = {at}"),
            &format!("kind = \"link_blackout\", duration_s = {d}.0"),
        );
        faults.push("link_blackout");
    }
}

fn rover_faults(
    rng: &mut ChaCha8Rng,
    s: &mut String,
    faults: &mut Vec<&'static str>,
    horizon_s: f64,
    target: (f64, f64),
) {
    // One of the first three pictures fails, or hangs (in this order of draws: the seeds' missions stay).
    for (chance, kind) in [(0.3, "picture_fails"), (0.2, "picture_hangs")] {
        if rng.gen_bool(chance) {
            let k = rng.gen_range(1..=3);
            fault(
                s,
                &format!("on = \"picture_started\", occurrence = {k}"),
                &format!("kind = \"{kind}\""),
            );
            faults.push(kind);
        }
    }
    if rng.gen_bool(0.2) {
        fault(
            s,
            "at_s = 0.0",
            &format!(
                "kind = \"picture_duration\", capture_time_s = {:.1}",
                rng.gen_range(1.0..4.0)
            ),
        );
        faults.push("picture_quick");
    }
    if rng.gen_bool(0.3) {
        // On the way to a target: [north, east].
        let _ = writeln!(
            s,
            "[[slow_zones]]\ncenter_m = [{:.1}, {:.1}]\nradius_m = {:.1}\nspeed_factor = {:.2}\n",
            target.1 * 0.6,
            target.0 * 0.6,
            rng.gen_range(1.5..4.0),
            rng.gen_range(0.2..0.6)
        );
        faults.push("slow_zone");
    }
    if rng.gen_bool(0.25) {
        let at = rng.gen_range(30.0..horizon_s * 0.5).round();
        fault(
            s,
            &format!("at_s = {at}"),
            &format!(
                "kind = \"battery_drop\", percent = {}.0",
                rng.gen_range(5..=30)
            ),
        );
        faults.push("battery_drop");
    }
    link_and_nav_faults(rng, s, faults, horizon_s);
}

/// An AUV mission on domains/auv/auv.ixt: 1 to 3 vents (50 to 400 m away, 50 to 300 m deep), each to be
/// sampled, all connected to the surface and to each other; back at the surface at the horizon.
fn auv(seed: u64, rng: &mut ChaCha8Rng) -> Mission {
    let n = rng.gen_range(1..=3);
    // Generous slack.
    let how = AuvDraw {
        radius_m: 400.0,
        near: 0.25,
        slack: 1.6,
    };
    let AuvMission {
        vents,
        horizon_s,
        priorities,
        ..
    } = draw_auv(n, seed, rng, &how);
    let p = crate::bench::suite::native::auv_problem(
        &format!("`mavtempo soak` (seed {seed})"),
        &format!("soak{seed}"),
        &vents,
        horizon_s,
        &priorities,
    );
    let mut s = String::new();
    let _ = writeln!(s, "# Generated by `mavtempo soak` (seed {seed}).");
    let _ = writeln!(s, "[vehicle]\nspeed_mps = 1.2\nmax_speed_mps = 1.4\naccel_mps2 = 0.2\nturn_rate_dps = 20.0\nwp_radius_m = 3.0\nvertical_speed_mps = 1.2\n");
    let _ = writeln!(
        s,
        "[battery]\ninitial_pct = 100.0\ndrain_pct_per_km = 1.0\ndrain_pct_per_min = 0.05\n"
    );
    let mut faults = Vec::new();
    if rng.gen_bool(0.3) {
        let v = vents[0];
        let _ = writeln!(
            s,
            "[[slow_zones]]\ncenter_m = [{:.1}, {:.1}]\nradius_m = {:.1}\nspeed_factor = {:.2}\n",
            v.1 * 0.5,
            v.0 * 0.5,
            rng.gen_range(10.0..40.0),
            rng.gen_range(0.5..0.8)
        );
        faults.push("slow_zone");
    }
    link_and_nav_faults(rng, &mut s, &mut faults, horizon_s);
    let mut uploads = Vec::new();
    if n > 1 && rng.gen_bool(0.4) {
        // A second request for a vent already in the problem: recognised as that vent.
        let v = vents[rng.gen_range(0..n)];
        uploads.push(Upload {
            at_s: rng.gen_range(60.0..horizon_s * 0.3).round(),
            command: crate::vehicle::goals::SAMPLE_GOAL_CMD,
            east: v.0,
            north: v.1,
            up: v.2,
            priority: rng.gen_range(1..=3),
            window_end_s: horizon_s - 600.0,
        });
    }
    Mission {
        seed,
        domain: SoakDomain::Auv,
        problem: p,
        scenario: s,
        faults,
        uploads,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_same_seed_gives_the_same_mission() {
        for seed in [1, 2, 3] {
            let (a, b) = (
                mission(seed, SoakDomain::All),
                mission(seed, SoakDomain::All),
            );
            assert_eq!(a.problem, b.problem);
            assert_eq!(a.scenario, b.scenario);
            assert_eq!(a.faults, b.faults);
        }
        assert_ne!(
            mission(1, SoakDomain::Rover).problem,
            mission(2, SoakDomain::Rover).problem
        );
    }

    #[test]
    fn generated_problems_and_scenarios_are_valid() {
        let rover = std::sync::Arc::new(
            crate::lang::parse_domain(
                "rover.ixt",
                include_str!("../../../domains/rover/rover.ixt"),
            )
            .expect("shipped rover domain"),
        );
        let auv = std::sync::Arc::new(
            crate::lang::parse_domain("auv.ixt", include_str!("../../../domains/auv/auv.ixt"))
                .expect("shipped auv domain"),
        );
        for seed in 0..60 {
            let m = mission(seed, SoakDomain::All);
            let d = if m.domain == SoakDomain::Auv {
                &auv
            } else {
                &rover
            };
            if let Err(e) = crate::lang::parse_problem("soak.ixt", &m.problem, d) {
                panic!("seed {seed}: {e}\n{}", m.problem);
            }
            if let Err(e) = sitl::Scenario::parse(&m.scenario, "soak.toml") {
                panic!("seed {seed}: {e}\n{}", m.scenario);
            }
        }
    }
}
