//! Random planning problems of a given size on the shipped domains, for `mavtempo bench suite`: nobody
//! tuned the planner on them. Everything is drawn from the seed into a plain mission struct, which
//! [`super::native`] writes in the domain language and [`super::pddl`] in PDDL, so both say the same problem.
//!
//! - rover (domains/rover/rover.ixt): `n` picture targets within 60 m of the base; 3 storage slots, so the
//!   pictures need downloads in two or three visibility windows; a battery that is full or needs about one
//!   recharge; deadlines on some pictures; communication goals in some windows.
//! - auv (domains/auv/auv.ixt): `n` vents within 500 m and 300 m deep, each to be sampled; back at the surface
//!   at the end.
//! - shopping (domains/shopping/shopping.ixt): `n` items sold at places of a random connected town, some
//!   wanted before a time; home at the end of the day.

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

/// One generated problem, before it is written in any language.
#[derive(Clone, Debug, PartialEq)]
pub enum Mission {
    Rover(RoverMission),
    Auv(AuvMission),
    Shopping(ShoppingMission),
}

impl Mission {
    pub fn domain(&self) -> SuiteDomain {
        match self {
            Mission::Rover(_) => SuiteDomain::Rover,
            Mission::Auv(_) => SuiteDomain::Auv,
            Mission::Shopping(_) => SuiteDomain::Shopping,
        }
    }

    /// (size, seed) it was drawn for.
    pub fn size_seed(&self) -> (usize, u64) {
        match self {
            Mission::Rover(m) => (m.size, m.seed),
            Mission::Auv(m) => (m.size, m.seed),
            Mission::Shopping(m) => (m.size, m.seed),
        }
    }
}

/// A rover mission: targets `t0 … t{n-1}` (east, north metres from the base at the origin).
#[derive(Clone, Debug, PartialEq)]
pub struct RoverMission {
    pub size: usize,
    pub seed: u64,
    pub horizon_s: f64,
    pub targets: Vec<(f64, f64)>,
    /// In time order; they never overlap.
    pub windows: Vec<VisibilityWindow>,
    /// Initial battery level, percent (capacity 100).
    pub battery: f64,
    /// One per target, in target order.
    pub pictures: Vec<PictureGoal>,
    pub comms: Vec<CommGoal>,
}

/// A ground-station pass: `VISIBLE() = W{station}` over `[start_s, end_s)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VisibilityWindow {
    /// 1 or 2: the domain names two stations, a third pass is station 1 again.
    pub station: u8,
    pub start_s: f64,
    pub end_s: f64,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PictureGoal {
    pub priority: u32,
    /// The picture is to be stored by then.
    pub deadline_s: Option<f64>,
}

/// `COMMUNICATED(W{station})` by `deadline_s` (the end of that station's first pass).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CommGoal {
    pub station: u8,
    pub deadline_s: f64,
}

/// An AUV mission: vents `vent0 …` (east, north, up metres from the surface point), all connected.
#[derive(Clone, Debug, PartialEq)]
pub struct AuvMission {
    pub size: usize,
    pub seed: u64,
    pub horizon_s: f64,
    pub vents: Vec<(f64, f64, f64)>,
    /// Of each vent's sampling goal.
    pub priorities: Vec<u32>,
}

/// A shopping day from 08:00 to 20:00: places `home` (0) and `shop1 …`, items `item0 …`.
#[derive(Clone, Debug, PartialEq)]
pub struct ShoppingMission {
    pub size: usize,
    pub seed: u64,
    pub places: usize,
    /// Two-way roads between place indices (smaller first).
    pub roads: Vec<(usize, usize)>,
    /// The place index selling each item.
    pub sold_at: Vec<usize>,
    /// One per item.
    pub wants: Vec<ShoppingGoal>,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShoppingGoal {
    pub priority: u32,
    /// Wanted before this hour of the day (11 … 17).
    pub by_hour: Option<u32>,
}

impl ShoppingMission {
    pub fn place_name(i: usize) -> String {
        if i == 0 {
            "home".to_string()
        } else {
            format!("shop{i}")
        }
    }
}

/// The problem text of size `n` and `seed` on `domain`, in the domain language.
pub fn problem(domain: SuiteDomain, n: usize, seed: u64) -> String {
    super::native::render(&draw(domain, n, seed))
}

/// The mission of size `n` and `seed` on `domain`.
pub fn draw(domain: SuiteDomain, n: usize, seed: u64) -> Mission {
    let mut rng = <ChaCha8Rng as rand::SeedableRng>::seed_from_u64(seed ^ ((n as u64) << 32));
    match domain {
        SuiteDomain::Rover => Mission::Rover(rover(n, seed, &mut rng)),
        SuiteDomain::Auv => Mission::Auv(auv(n, seed, &mut rng)),
        SuiteDomain::Shopping => Mission::Shopping(shopping(n, seed, &mut rng)),
    }
}

/// A point at `r·[0.2, 1)` from the origin, in whole metres.
fn point(rng: &mut ChaCha8Rng, r: f64) -> (f64, f64) {
    point_within(rng, 0.2, r)
}

/// A point at `r·[near, 1)` from the origin, in whole metres.
pub fn point_within(rng: &mut ChaCha8Rng, near: f64, r: f64) -> (f64, f64) {
    let a = rng.gen_range(0.0..std::f64::consts::TAU);
    let d = rng.gen_range(r * near..r);
    ((a.cos() * d).round(), (a.sin() * d).round())
}

// The draws below keep the order in which the problem texts used to be written, so a seed gives the same
// problem as before the split into drawing and rendering.

fn rover(n: usize, seed: u64, rng: &mut ChaCha8Rng) -> RoverMission {
    let targets: Vec<(f64, f64)> = (0..n).map(|_| point(rng, 60.0)).collect();
    // A tour at the domain's slowest speed (0.3 m/s), pictures and downloads, with slack.
    let tour: f64 = targets.iter().map(|t| t.0.hypot(t.1)).sum::<f64>() * 1.2;
    let horizon_s = ((tour / 0.3 + 120.0 * n as f64 + 600.0) / 60.0).ceil() * 60.0;
    // Windows spread over the mission: enough of them for n pictures with 3 slots.
    let count = (n.div_ceil(2)).clamp(2, 3);
    let span = horizon_s / count as f64;
    let windows: Vec<VisibilityWindow> = (0..count)
        .map(|w| {
            let start_s = (span * w as f64 + rng.gen_range(0.2..0.5) * span).round();
            let end_s = (start_s + rng.gen_range(0.3..0.45) * span).round();
            VisibilityWindow {
                station: (w % 2 + 1) as u8,
                start_s,
                end_s,
            }
        })
        .collect();
    // Moves cost 0.5 % per metre: full, or about one recharge short of the tour.
    let battery = if rng.gen_bool(0.5) {
        100.0
    } else {
        (tour * 0.5 * rng.gen_range(0.7..0.9))
            .clamp(20.0, 100.0)
            .round()
    };
    let pictures = (0..n)
        .map(|_| {
            let priority = rng.gen_range(1..=3);
            let deadline_s = rng
                .gen_bool(0.3)
                .then(|| (horizon_s * rng.gen_range(0.5..0.9)).round());
            PictureGoal {
                priority,
                deadline_s,
            }
        })
        .collect();
    // At most one goal per station, due by the end of its first pass.
    let comms = windows
        .iter()
        .take(2)
        .filter_map(|w| {
            rng.gen_bool(0.3).then_some(CommGoal {
                station: w.station,
                deadline_s: w.end_s,
            })
        })
        .collect();
    RoverMission {
        size: n,
        seed,
        horizon_s,
        targets,
        windows,
        battery,
        pictures,
        comms,
    }
}

fn auv(n: usize, seed: u64, rng: &mut ChaCha8Rng) -> AuvMission {
    let how = AuvDraw {
        radius_m: 500.0,
        near: 0.2,
        slack: 1.5,
    };
    draw_auv(n, seed, rng, &how)
}

/// How an AUV mission's vents and horizon are drawn.
pub struct AuvDraw {
    /// Vents at `radius_m·[near, 1)` from the surface point (and 50 to 300 m deep).
    pub radius_m: f64,
    pub near: f64,
    /// The horizon over the mission's least duration: legs out and back at 1 m/s, 1,500 s at each vent
    /// for its survey and sample.
    pub slack: f64,
}

/// `n` vents with a sampling goal each (priority 1 to 3), drawn as `how` says.
pub fn draw_auv(n: usize, seed: u64, rng: &mut ChaCha8Rng, how: &AuvDraw) -> AuvMission {
    let vents: Vec<(f64, f64, f64)> = (0..n)
        .map(|_| {
            let (e, nn) = point_within(rng, how.near, how.radius_m);
            (e, nn, -(rng.gen_range(50..=300) as f64))
        })
        .collect();
    let legs: f64 = vents
        .iter()
        .map(|v| v.0.hypot(v.1).hypot(v.2) * 2.0)
        .sum::<f64>();
    let horizon_s = ((legs + 1500.0 * n as f64) * how.slack / 60.0).ceil() * 60.0;
    let priorities: Vec<u32> = (0..n).map(|_| rng.gen_range(1..=3)).collect();
    AuvMission {
        size: n,
        seed,
        horizon_s,
        vents,
        priorities,
    }
}

fn shopping(n: usize, seed: u64, rng: &mut ChaCha8Rng) -> ShoppingMission {
    // A town of n/2 + 2 places: a random tree (each place joined to an earlier one), plus one shortcut.
    let places = n / 2 + 2;
    let mut roads: Vec<(usize, usize)> = (1..places).map(|i| (rng.gen_range(0..i), i)).collect();
    let (a, b) = (rng.gen_range(0..places), rng.gen_range(0..places));
    if a != b && !roads.contains(&(a.min(b), a.max(b))) {
        roads.push((a.min(b), a.max(b)));
    }
    let sold_at = (0..n).map(|_| rng.gen_range(1..places)).collect();
    let wants = (0..n)
        .map(|_| {
            let priority = rng.gen_range(1..=3);
            let by_hour = rng.gen_bool(0.3).then(|| rng.gen_range(11..=17));
            ShoppingGoal { priority, by_hour }
        })
        .collect();
    ShoppingMission {
        size: n,
        seed,
        places,
        roads,
        sold_at,
        wants,
    }
}
