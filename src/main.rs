use std::process::ExitCode;

fn main() -> ExitCode {
    mavtempo::cli::main()
}
