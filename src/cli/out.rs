//! The subcommands' standard output. `println!` panics when stdout is closed (`mavtempo plan … | head`, a
//! `tee` that died): a command that only prints then stops quietly, as a reader that wanted no more lines
//! expects; a command that drives or serves a vehicle goes on without printing, since a closed terminal must
//! not end a mission (its trace still goes to the report and the log on stderr).
//! `eprintln!` panics too when stderr is closed (exit 101): [`errln!`] writes to stderr and drops what
//! cannot be written, as the log does.

use std::fmt::Arguments;
use std::io::{self, ErrorKind, Write};
use std::sync::atomic::{AtomicBool, Ordering};

/// What a closed stdout does to the running command.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OnClosed {
    /// Stop the process: exit 0 on a closed pipe, 1 on any other write error.
    Exit,
    /// Keep going; later lines are dropped.
    KeepRunning,
}

static KEEP_RUNNING: AtomicBool = AtomicBool::new(false);
static CLOSED: AtomicBool = AtomicBool::new(false);

/// Set once, before the subcommand runs.
pub fn on_closed(policy: OnClosed) {
    KEEP_RUNNING.store(policy == OnClosed::KeepRunning, Ordering::Relaxed);
}

/// Writes `args` to stdout, without a newline ([`outln!`] adds one).
pub fn write(args: Arguments<'_>) {
    if CLOSED.load(Ordering::Relaxed) {
        return;
    }
    if let Err(e) = io::stdout().lock().write_fmt(args) {
        closed(&e);
    }
}

fn closed(e: &io::Error) {
    CLOSED.store(true, Ordering::Relaxed);
    if KEEP_RUNNING.load(Ordering::Relaxed) {
        tracing::warn!("standard output: {e}; going on without printing");
        return;
    }
    if e.kind() == ErrorKind::BrokenPipe {
        std::process::exit(0);
    }
    write_err(format_args!(
        "mavtempo: cannot write to standard output: {e}\n"
    ));
    std::process::exit(1);
}

/// Writes `args` to stderr; a closed or failing stderr loses the message, never the command.
pub fn write_err(args: Arguments<'_>) {
    let _ = io::stderr().lock().write_fmt(args);
}

/// `println!` that neither panics nor loses the mission when stdout is closed (see [`crate::cli::out`]).
macro_rules! outln {
    () => {
        $crate::cli::out::write(format_args!("\n"))
    };
    ($($arg:tt)*) => {
        $crate::cli::out::write(format_args!("{}\n", format_args!($($arg)*)))
    };
}

/// `print!` that neither panics nor loses the mission when stdout is closed.
macro_rules! out {
    ($($arg:tt)*) => {
        $crate::cli::out::write(format_args!($($arg)*))
    };
}

/// `eprintln!` that does not panic when stderr is closed.
macro_rules! errln {
    () => {
        $crate::cli::out::write_err(format_args!("\n"))
    };
    ($($arg:tt)*) => {
        $crate::cli::out::write_err(format_args!("{}\n", format_args!($($arg)*)))
    };
}

/// `eprint!` that does not panic when stderr is closed.
macro_rules! err {
    ($($arg:tt)*) => {
        $crate::cli::out::write_err(format_args!($($arg)*))
    };
}

pub(crate) use {err, errln, out, outln};
