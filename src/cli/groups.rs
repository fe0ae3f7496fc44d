//! `mavtempo --help` lists the subcommands in two groups: what an operator runs beside a vehicle, and what a
//! developer runs to try, measure and test. Clap lists subcommands in one block; the grouped list is built
//! from the subcommands' own one-line descriptions, so there is one text per command.

use clap::Command;

/// What an operator runs beside a vehicle.
pub const OPERATE: [&str; 6] = ["run", "sim", "plan", "check", "goal", "report"];
/// What a developer runs to try, measure and test.
pub const DEVELOP: [&str; 5] = ["demo", "bench", "soak", "fuzz", "experiment"];

/// `cmd` with its help listing the subcommands by group.
pub fn grouped(cmd: Command) -> Command {
    let width = OPERATE
        .iter()
        .chain(&DEVELOP)
        .map(|n| n.len())
        .max()
        .unwrap_or(0);
    let list = |names: &[&str]| -> String {
        names
            .iter()
            .map(|&n| {
                let about = cmd
                    .find_subcommand(n)
                    .and_then(|s| s.get_about())
                    .map(|a| a.to_string())
                    .unwrap_or_default();
                format!("  {n:<width$}  {about}\n")
            })
            .collect()
    };
    let template = format!(
        "{{about-with-newline}}\n{{usage-heading}} {{usage}}\n\nOperate a vehicle:\n{}\nTry, measure and test:\n{}\nOptions:\n{{options}}\n\n`mavtempo help COMMAND` gives a command's options.\n",
        list(&OPERATE),
        list(&DEVELOP)
    );
    cmd.help_template(template)
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::CommandFactory;

    /// Every subcommand is in exactly one group, and each group's line carries its description.
    #[test]
    fn every_subcommand_is_in_one_group() {
        let cmd = super::super::Cli::command();
        let names: Vec<String> = cmd
            .get_subcommands()
            .map(|s| s.get_name().to_string())
            .collect();
        for n in &names {
            let count = OPERATE.iter().chain(&DEVELOP).filter(|g| *g == n).count();
            assert_eq!(count, 1, "{n} is in {count} groups");
        }
        assert_eq!(names.len(), OPERATE.len() + DEVELOP.len(), "{names:?}");
        let help = grouped(super::super::Cli::command())
            .render_help()
            .to_string();
        let run = help
            .lines()
            .find(|l| l.trim_start().starts_with("run "))
            .unwrap_or("");
        assert!(run.contains("MAVLink vehicle"), "{help}");
        assert!(
            help.find("Operate a vehicle:") < help.find("Try, measure and test:"),
            "{help}"
        );
    }
}
