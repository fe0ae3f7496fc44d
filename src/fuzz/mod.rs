//! `mavtempo fuzz`: seeded mutation fuzzing of every input mavtempo parses (domain and problem files,
//! vehicle configurations with `[exec]`, SITL scenarios, goal files, the MAVLink goal intake) on stable
//! Rust. A panic, or an error that does not point inside the text, is a failure; each failing input is
//! saved so that it can be replayed (`--replay FILE`).

pub mod intake;
pub mod mutate;
pub mod targets;

pub use targets::Oops;

use std::cell::RefCell;
use std::collections::BTreeMap;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::Serialize;

/// What is fuzzed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, clap::ValueEnum, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Target {
    Domain,
    Problem,
    Config,
    Scenario,
    Goals,
    Intake,
}

impl Target {
    pub const ALL: [Target; 6] = [
        Target::Domain,
        Target::Problem,
        Target::Config,
        Target::Scenario,
        Target::Goals,
        Target::Intake,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Target::Domain => "domain",
            Target::Problem => "problem",
            Target::Config => "config",
            Target::Scenario => "scenario",
            Target::Goals => "goals",
            Target::Intake => "intake",
        }
    }

    fn corpus(self) -> Vec<Vec<u8>> {
        match self {
            Target::Domain => targets::domain_corpus(),
            Target::Problem => targets::problem_corpus(),
            Target::Config => targets::config_corpus(),
            Target::Scenario => targets::scenario_corpus(),
            Target::Goals => targets::goals_corpus(),
            Target::Intake => intake::corpus(),
        }
    }

    /// Runs one input: `Err` for an input handled wrongly without a panic.
    pub fn exec(self, input: &[u8]) -> Result<(), Oops> {
        match self {
            Target::Domain => targets::domain(input),
            Target::Problem => targets::problem(input),
            Target::Config => targets::config(input),
            Target::Scenario => targets::scenario(input),
            Target::Goals => targets::goals(input),
            Target::Intake => intake::run(input),
        }
    }
}

/// One kind of failure: its message (a panic's, with its place) and how often it was met.
#[derive(Debug, Clone, Serialize)]
pub struct Failure {
    pub message: String,
    pub count: u64,
    /// The saved inputs that fail this way (the first few).
    pub saved: Vec<PathBuf>,
}

/// What one target's run did.
#[derive(Debug, Clone, Serialize)]
pub struct Report {
    pub target: Target,
    pub seed: u64,
    pub execs: u64,
    pub seconds: f64,
    pub execs_per_s: f64,
    /// The slowest input, ms: a parser gone quadratic shows here.
    pub slowest_ms: f64,
    pub failures: u64,
    pub kinds: Vec<Failure>,
}

/// Inputs saved per kind of failure.
const SAVED_PER_KIND: usize = 5;

thread_local! {
    /// The last panic's message and place, kept by the silent hook.
    static LAST_PANIC: RefCell<Option<String>> = const { RefCell::new(None) };
    /// Set while this thread runs a harness: its panics are recorded, not printed.
    static FUZZING: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Runs `execs` mutated inputs of `target` from `seed`; failing inputs go to `save`.
pub fn run(target: Target, execs: u64, seed: u64, save: &Path) -> Report {
    let corpus = target.corpus();
    let stream = seed ^ (target as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15);
    let exec = |i: &[u8]| target.exec(i);
    let generate: Option<&Generator> = match target {
        Target::Intake => Some(&intake::generate),
        _ => None,
    };
    let harness = Harness {
        name: target.name(),
        corpus: &corpus,
        exec: &exec,
        generate,
    };
    let (seconds, slowest, failures, kinds) = run_fn(&harness, execs, stream, save);
    Report {
        target,
        seed,
        execs,
        seconds,
        execs_per_s: execs as f64 / seconds.max(1e-9),
        slowest_ms: slowest.as_secs_f64() * 1e3,
        failures,
        kinds,
    }
}

/// What [`run_fn`] found: seconds, the slowest input, failures and their kinds.
type Outcome = (f64, Duration, u64, Vec<Failure>);

/// Structured generation of a whole input from the random stream.
type Generator = dyn Fn(&mut ChaCha8Rng) -> Vec<u8>;

/// What [`run_fn`] fuzzes: its name (for saved files), seeds, the execution and an optional generator.
struct Harness<'a> {
    name: &'a str,
    corpus: &'a [Vec<u8>],
    exec: &'a dyn Fn(&[u8]) -> Result<(), Oops>,
    generate: Option<&'a Generator>,
}

/// The loop behind [`run`], for any harness.
fn run_fn(h: &Harness<'_>, execs: u64, seed: u64, save: &Path) -> Outcome {
    let Harness {
        name,
        corpus,
        exec,
        generate,
    } = *h;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut input = Vec::new();
    let mut kinds: BTreeMap<String, Failure> = BTreeMap::new();
    let mut failures = 0;
    let mut slowest = Duration::ZERO;
    let start = Instant::now();
    // Silenced on this thread only: a failing input is reported once, in the summary, not as a backtrace
    // per execution; a panic elsewhere (another test of the same binary) still goes to the previous hook.
    let previous = std::sync::Arc::new(std::panic::take_hook());
    let forward = previous.clone();
    FUZZING.with(|f| f.set(true));
    std::panic::set_hook(Box::new(move |info| {
        if FUZZING.with(|f| f.get()) {
            LAST_PANIC.with(|l| *l.borrow_mut() = Some(info.to_string()));
        } else {
            forward(info);
        }
    }));
    // The parsers log what they refuse; millions of inputs would flood the terminal.
    let quiet = tracing::subscriber::NoSubscriber::default();
    tracing::subscriber::with_default(quiet, || {
        for i in 0..execs {
            // Every 16th input is a seed as shipped (or a fresh random one), a quarter generated when the
            // harness has a generator, the rest mutations.
            let base = &corpus[rng.gen_range(0..corpus.len())];
            if let (Some(g), 2) = (generate, i % 4) {
                input = g(&mut rng);
            } else if i % 16 == 0 {
                input.clear();
                if rng.gen_bool(0.5) {
                    input.extend_from_slice(base);
                } else {
                    input.extend((0..rng.gen_range(0..256)).map(|_| rng.gen::<u8>()));
                }
            } else {
                mutate::mutate(&mut rng, base, corpus, &mut input);
            }
            let t = Instant::now();
            let result = catch_unwind(AssertUnwindSafe(|| exec(&input)));
            slowest = slowest.max(t.elapsed());
            let message = match result {
                Ok(Ok(())) => continue,
                Ok(Err(wrong)) => wrong.to_string(),
                Err(payload) => LAST_PANIC
                    .with(|l| l.borrow_mut().take())
                    .unwrap_or_else(|| panic_text(payload.as_ref())),
            };
            failures += 1;
            let kind = kinds.entry(signature(&message)).or_insert_with(|| Failure {
                message: message.clone(),
                count: 0,
                saved: Vec::new(),
            });
            kind.count += 1;
            if kind.saved.len() < SAVED_PER_KIND {
                let path = save.join(format!("{name}-{seed}-{i}.bin"));
                if std::fs::create_dir_all(save)
                    .and_then(|()| std::fs::write(&path, &input))
                    .is_ok()
                {
                    kind.saved.push(path);
                }
            }
        }
    });
    FUZZING.with(|f| f.set(false));
    // Back to the previous hook (the one that forwarded to it is dropped).
    std::panic::set_hook(Box::new(move |info| previous(info)));
    let kinds = kinds.into_values().collect();
    (start.elapsed().as_secs_f64(), slowest, failures, kinds)
}

/// Replays one saved input: `Err` with the failure when it still fails.
pub fn replay(target: Target, input: &[u8]) -> Result<(), Oops> {
    match catch_unwind(AssertUnwindSafe(|| target.exec(input))) {
        Ok(r) => r,
        Err(payload) => Err(Oops::Panic(panic_text(payload.as_ref()))),
    }
}

fn panic_text(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "panic with a non-text payload".into())
}

/// Failures that differ only in numbers (a line, a value) are one kind.
fn signature(message: &str) -> String {
    let first = message.lines().next().unwrap_or("");
    first.chars().filter(|c| !c.is_ascii_digit()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn panics_are_caught_counted_by_kind_and_saved() {
        let dir = std::env::temp_dir().join(format!("mavtempo-fuzz-test-{}", std::process::id()));
        let corpus = vec![b"abcdefgh".to_vec()];
        let exec = |i: &[u8]| -> Result<(), Oops> {
            if i.contains(&b'[') {
                panic!("bracket at {}", i.len());
            }
            if i.is_empty() {
                return Err(Oops::Utf8Unlocated("empty".into()));
            }
            Ok(())
        };
        let h = Harness {
            name: "t",
            corpus: &corpus,
            exec: &exec,
            generate: None,
        };
        let (_, _, failures, kinds) = run_fn(&h, 3_000, 3, &dir);
        let total: u64 = kinds.iter().map(|k| k.count).sum();
        assert!(failures > 0 && total == failures, "{failures} {kinds:?}");
        let bracket = kinds.iter().find(|k| k.message.contains("bracket at"));
        let saved = bracket.map(|k| k.saved.clone()).unwrap_or_default();
        assert!(
            !saved.is_empty() && saved.len() <= SAVED_PER_KIND,
            "{kinds:?}"
        );
        for p in &saved {
            let input = std::fs::read(p).unwrap_or_default();
            assert!(
                input.contains(&b'['),
                "{} holds the failing input",
                p.display()
            );
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
}
