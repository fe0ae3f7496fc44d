//! The text harnesses: bytes in, through the same UTF-8 check and parser as the file readers; a panic is a
//! failure (caught by the runner), and so is an error that does not point inside the text.

use std::sync::OnceLock;

use crate::exec::config::MissionConfig;
use crate::lang;
use crate::model::{Domain, Problem};
use crate::vehicle::config::ConfigError;
use crate::vehicle::geo::Home;
use crate::vehicle::goal_files;
use crate::vehicle::goals::{items_to_goals, KnownLocations};

/// The shipped domains with one of their problems each, parsed once.
fn domains() -> &'static [(Domain, Problem)] {
    static D: OnceLock<Vec<(Domain, Problem)>> = OnceLock::new();
    D.get_or_init(|| {
        let pairs = [
            (RO_DOMAIN, RO_FIG2),
            (AUV_DOMAIN, AUV_VENTS),
            (SHOP_DOMAIN, SHOP_DAY),
        ];
        pairs
            .iter()
            .filter_map(|(d, p)| {
                let d = lang::parse_domain("d.ixt", d).ok()?;
                let p = lang::parse_problem("p.ixt", p, &d).ok()?;
                Some((d, p))
            })
            .collect()
    })
}

const RO_DOMAIN: &str = include_str!("../../domains/rover/rover.ixt");
const RO_FIG2: &str = include_str!("../../domains/rover/problems/fig2.ixt");
const RO_DALA: &str = include_str!("../../domains/rover/problems/dala.ixt");
const AUV_DOMAIN: &str = include_str!("../../domains/auv/auv.ixt");
const AUV_VENTS: &str = include_str!("../../domains/auv/problems/vents.ixt");
const SHOP_DOMAIN: &str = include_str!("../../domains/shopping/shopping.ixt");
const SHOP_DAY: &str = include_str!("../../domains/shopping/problems/day.ixt");

pub fn domain_corpus() -> Vec<Vec<u8>> {
    [RO_DOMAIN, AUV_DOMAIN, SHOP_DOMAIN]
        .map(|s| s.as_bytes().to_vec())
        .to_vec()
}

pub fn problem_corpus() -> Vec<Vec<u8>> {
    [RO_FIG2, RO_DALA, AUV_VENTS, SHOP_DAY]
        .map(|s| s.as_bytes().to_vec())
        .to_vec()
}

pub fn config_corpus() -> Vec<Vec<u8>> {
    [
        include_str!("../../config/sitl-rover.toml"),
        include_str!("../../config/demo-rover.toml"),
        include_str!("../../config/ardupilot-rover.toml"),
        include_str!("../../config/px4-rover.toml"),
        include_str!("../../config/sitl-auv.toml"),
        include_str!("../../tests/fixtures/vehicle/bindings.toml"),
        // Every [exec] key, for the executive's table.
        "[exec]\ntimestep_ms = 1300\nrepair_share = 0.6\nreplan_slack_ms = 2000\nrepair_max_steps = 300\n\
         repair_cycle_max_steps = 20000\nrepair_episode_max_steps = 20000\nreplan_max_steps = 100000\n\
         goal_insertion_cycles = 3\ndispatch = \"goal-driven\"\nsame_failure_limit = 3\n\
         max_plan_changes_per_min = 12\n",
    ]
    .map(|s| s.as_bytes().to_vec())
    .to_vec()
}

pub fn scenario_corpus() -> Vec<Vec<u8>> {
    [
        include_str!("../../sitl/scenarios/fig2.toml"),
        include_str!("../../sitl/scenarios/dala.toml"),
        include_str!("../../sitl/scenarios/vents.toml"),
        include_str!("../../sitl/scenarios/link-faults.toml"),
        include_str!("../../sitl/scenarios/nav-failure.toml"),
    ]
    .map(|s| s.as_bytes().to_vec())
    .to_vec()
}

pub fn goals_corpus() -> Vec<Vec<u8>> {
    [
        include_str!("../../config/goals/example.plan"),
        "QGC WPL 110\n0\t1\t0\t16\t0\t0\t0\t0\t43.5615\t1.4778\t0\t1\n\
         1\t0\t3\t16\t0\t0\t0\t0\t43.5616\t1.4779\t0\t1\n\
         2\t0\t3\t2000\t0\t0\t1\t0\t43.5617\t1.4780\t0\t1\n\
         3\t0\t3\t20\t0\t0\t0\t0\t0\t0\t0\t1\n",
    ]
    .map(|s| s.as_bytes().to_vec())
    .to_vec()
}

/// Why an input failed: handled wrongly without a panic, or a panic (its message and place).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum Oops {
    #[error("UTF-8 error badly located: {0}")]
    Utf8Unlocated(String),
    #[error("{what}: error at {line}:{col} outside the text ({lines} lines)")]
    Outside {
        what: &'static str,
        line: usize,
        col: usize,
        lines: usize,
    },
    #[error("{what} error without a place: {message}")]
    NoPlace { what: &'static str, message: String },
    #[error("{0}")]
    Panic(String),
}

/// The text, or `None` when the bytes are not UTF-8 — then the reader's error must locate the bad byte.
fn text(bytes: &[u8]) -> Result<Option<&str>, Oops> {
    match srctext::decode("f", bytes) {
        Ok(t) => Ok(Some(t)),
        Err(e) => {
            let lines = bytes.iter().filter(|&&b| b == b'\n').count() + 1;
            if e.line == 0 || e.line > lines || e.col == 0 {
                return Err(Oops::Utf8Unlocated(e.to_string()));
            }
            Ok(None)
        }
    }
}

/// An error must point at a line of the text (or just past its end).
fn located(text: &str, line: usize, col: usize, what: &'static str) -> Result<(), Oops> {
    let lines = text.split('\n').count();
    if line == 0 || line > lines || col == 0 {
        return Err(Oops::Outside {
            what,
            line,
            col,
            lines,
        });
    }
    Ok(())
}

pub fn domain(bytes: &[u8]) -> Result<(), Oops> {
    let Some(t) = text(bytes)? else { return Ok(()) };
    if let Err(d) = lang::parse_domain("f", t) {
        for x in d.iter() {
            located(t, x.line, x.col, "domain")?;
        }
    }
    Ok(())
}

pub fn problem(bytes: &[u8]) -> Result<(), Oops> {
    let Some(t) = text(bytes)? else { return Ok(()) };
    for (d, _) in domains() {
        if let Err(e) = lang::parse_problem("f", t, d) {
            for x in e.iter() {
                located(t, x.line, x.col, "problem")?;
            }
        }
    }
    Ok(())
}

/// The vehicle configuration with its `[exec]`, then checked against each shipped domain and problem.
pub fn config(bytes: &[u8]) -> Result<(), Oops> {
    let Some(t) = text(bytes)? else { return Ok(()) };
    match MissionConfig::parse(t, "f") {
        Err(ConfigError::At(e)) => located(t, e.line, e.col, "config"),
        Err(e) => Err(Oops::NoPlace {
            what: "config",
            message: e.to_string(),
        }),
        Ok(cfg) => {
            for (d, p) in domains() {
                let _ = crate::config_check::check(&cfg.vehicle, d, Some(p));
            }
            Ok(())
        }
    }
}

pub fn scenario(bytes: &[u8]) -> Result<(), Oops> {
    let Some(t) = text(bytes)? else { return Ok(()) };
    match sitl::Scenario::parse(t, "f") {
        Err(sitl::SimError::ScenarioAt(e)) => located(t, e.line, e.col, "scenario"),
        Err(e) => Err(Oops::NoPlace {
            what: "scenario",
            message: e.to_string(),
        }),
        Ok(_) => Ok(()),
    }
}

/// A `.plan` or `.waypoints` goal file, then its items turned into goals as `run --goals` does.
pub fn goals(bytes: &[u8]) -> Result<(), Oops> {
    let Some(t) = text(bytes)? else { return Ok(()) };
    let file = if t.trim_start().starts_with('{') {
        goal_files::parse_plan(t, "f")
    } else {
        goal_files::parse_waypoints(t, "f")
    };
    let Ok(file) = file else { return Ok(()) };
    let mut known = KnownLocations::new(file.home.unwrap_or(Home {
        lat: 43.5615,
        lon: 1.4778,
        alt: 0.0,
    }));
    if let Some((_, p)) = domains().first() {
        known.objects = p
            .objects
            .iter()
            .filter_map(|o| {
                let (e, n, u) = o.local(p.home.as_ref())?;
                Some((o.name.clone(), crate::vehicle::Enu::new(e, n, u)))
            })
            .collect();
    }
    let _ = items_to_goals(&file.items, &known, 1);
    Ok(())
}
