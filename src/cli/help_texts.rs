//! The command line's help, checked: every argument says what it is for, and no help text speaks the
//! papers' jargon (figure and section numbers, "seed 1"): a user reads the help without the papers.

#[cfg(test)]
mod tests {
    use clap::CommandFactory;

    /// Words of the papers' apparatus a help text must not lean on.
    const JARGON: [&str; 6] = ["Fig.", "Fig ", "seed 1", "seed 2", "§", "d_achiev"];

    fn walk(cmd: &clap::Command, path: &str, found: &mut Vec<String>) {
        let here = format!("{path} {}", cmd.get_name()).trim().to_string();
        let texts = cmd
            .get_about()
            .into_iter()
            .chain(cmd.get_long_about())
            .map(|t| t.to_string());
        for t in texts {
            if let Some(j) = JARGON.iter().find(|j| t.contains(*j)) {
                found.push(format!("{here}: `{j}` in \"{t}\""));
            }
        }
        for a in cmd.get_arguments() {
            let id = a.get_id().as_str();
            if id == "help" || id == "version" {
                continue;
            }
            match a.get_help().or(a.get_long_help()) {
                None => found.push(format!("{here} {id}: no help")),
                Some(h) => {
                    let values = a.get_possible_values();
                    let texts = std::iter::once(h.to_string()).chain(
                        values
                            .iter()
                            .filter_map(|v| v.get_help().map(|h| h.to_string())),
                    );
                    for t in texts {
                        if let Some(j) = JARGON.iter().find(|j| t.contains(*j)) {
                            found.push(format!("{here} {id}: `{j}` in \"{t}\""));
                        }
                    }
                }
            }
        }
        for s in cmd.get_subcommands() {
            walk(s, &here, found);
        }
    }

    #[test]
    fn every_argument_has_help_without_jargon() {
        let mut found = Vec::new();
        walk(&super::super::Cli::command(), "", &mut found);
        assert!(found.is_empty(), "{}", found.join("\n"));
    }
}
