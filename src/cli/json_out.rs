//! `--json` output shared by the subcommands: values printed as JSON, one a line or indented. A value that
//! does not serialise is reported on stderr and fails the command.

use std::process::ExitCode;

use crate::cli::out::outln;
use serde::Serialize;

/// Prints each row as one JSON line; at the first that does not serialise, says `{context}: {error}` on
/// stderr and fails.
pub fn print_json_lines<'a, T: Serialize + 'a>(
    context: &str,
    rows: impl IntoIterator<Item = &'a T>,
) -> ExitCode {
    print_with(context, rows, serde_json::to_string)
}

/// Prints `value` as indented JSON; when it does not serialise, says `{context}: {error}` on stderr and fails.
pub fn print_json_pretty<T: Serialize>(context: &str, value: &T) -> ExitCode {
    print_with(context, [value], serde_json::to_string_pretty)
}

fn print_with<'a, T: Serialize + 'a>(
    context: &str,
    rows: impl IntoIterator<Item = &'a T>,
    to_json: fn(&T) -> serde_json::Result<String>,
) -> ExitCode {
    for row in rows {
        match to_json(row) {
            Ok(text) => outln!("{text}"),
            Err(e) => {
                crate::cli::out::errln!("{context}: {e}");
                return ExitCode::FAILURE;
            }
        }
    }
    ExitCode::SUCCESS
}
