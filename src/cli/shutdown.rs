//! SIGINT / SIGTERM for `run` and `demo`. The first signal asks the mission to stop: the loop ends, the
//! vehicle is made safe (`modes.on_shutdown`), the report is written with the end `interrupted`, the
//! `.tlog` is flushed, and the process exits with 128 + the signal's number (130 for SIGINT, 143 for
//! SIGTERM). A second signal exits at once with the same rule, after the hooks registered for it (the
//! `.tlog`'s flush: records reach the file whole, so it still ends on a frame boundary).

use std::process::ExitCode;
use std::sync::{Arc, Mutex};

use tokio::signal::unix::{signal, SignalKind};

use super::error::CliError;
use crate::exec::interrupt::{signal_name, Interrupt};

/// What runs before a second signal's exit: quick, and never waiting for a lock.
type Hook = Box<dyn Fn() + Send>;

/// The signals of a run: the interrupt the first one sets, and the hooks of the second one's exit.
pub struct Signals {
    pub interrupt: Interrupt,
    at_once: Arc<Mutex<Vec<Hook>>>,
}

impl Signals {
    /// Runs `hook` before exiting on a second signal.
    pub fn before_exit_at_once(&self, hook: Hook) {
        if let Ok(mut hooks) = self.at_once.lock() {
            hooks.push(hook);
        }
    }
}

/// Takes SIGINT and SIGTERM from their default (killing the process) from now on: they set the returned
/// interrupt, a second one exits. Listens on a thread of its own, whatever the caller's runtimes.
pub fn listen() -> Result<Signals, CliError> {
    let rt = tokio::runtime::Builder::new_current_thread()
        .enable_io()
        .build()
        .map_err(|source| CliError::Setup {
            what: "signal handling: tokio runtime",
            source,
        })?;
    let (mut int, mut term) = {
        // Registered here, before returning: a signal that comes right after is caught.
        let _in_runtime = rt.enter();
        let handler = |kind: SignalKind, what| {
            signal(kind).map_err(|source| CliError::Setup { what, source })
        };
        let int = handler(SignalKind::interrupt(), "SIGINT handler")?;
        let term = handler(SignalKind::terminate(), "SIGTERM handler")?;
        (int, term)
    };
    let interrupt = Interrupt::default();
    let seen = interrupt.clone();
    let at_once: Arc<Mutex<Vec<Hook>>> = Arc::default();
    let hooks = at_once.clone();
    std::thread::Builder::new()
        .name("signals".into())
        .spawn(move || {
            rt.block_on(async move {
                loop {
                    let number = tokio::select! {
                        Some(()) = int.recv() => SignalKind::interrupt().as_raw_value(),
                        Some(()) = term.recv() => SignalKind::terminate().as_raw_value(),
                        else => return,
                    };
                    let name = signal_name(number);
                    if seen.request(number) {
                        crate::cli::out::errln!(
                            "mavtempo: {name} received: stopping (vehicle made safe, report, .tlog); \
                             send it again to exit at once"
                        );
                    } else {
                        crate::cli::out::errln!("mavtempo: {name} received again: exiting at once");
                        if let Ok(hooks) = hooks.try_lock() {
                            for hook in hooks.iter() {
                                hook();
                            }
                        }
                        std::process::exit(exit_status(number));
                    }
                }
            })
        })
        .map_err(|source| CliError::Setup {
            what: "signal handling thread",
            source,
        })?;
    Ok(Signals { interrupt, at_once })
}

/// The shell's convention for a process ended by a signal: 128 + its number.
fn exit_status(signal: i32) -> i32 {
    128 + signal
}

/// The exit code of a run stopped by `interrupt`, if it was.
pub fn exit_code(interrupt: &Interrupt) -> Option<ExitCode> {
    interrupt
        .requested()
        .map(|s| ExitCode::from(u8::try_from(exit_status(s)).unwrap_or(u8::MAX)))
}
