//! `mavtempo check DOMAIN.pddl [PROBLEM.pddl...]`: PDDL files checked the way `plan` reads them — parsed,
//! and each problem translated with its domain — so an error is the same `file:line:col` message `plan`
//! would give, without planning.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use crate::cli::out::outln;
use crate::pddl;

/// Checks `files` (all PDDL): the domain first, then its problems.
pub fn run(files: &[PathBuf]) -> ExitCode {
    let Some((domain_path, problems)) = files.split_first() else {
        return ExitCode::FAILURE;
    };
    let domain = pddl::read_src(domain_path).and_then(|src| {
        let d = pddl::parse_domain(&src)?;
        Ok((src, d))
    });
    let (ds, d) = match domain {
        Ok(loaded) => loaded,
        Err(e) => {
            crate::cli::out::errln!("{e}");
            return ExitCode::FAILURE;
        }
    };
    outln!(
        "{}: ok (PDDL domain {}: {} predicates, {} functions, {} actions)",
        domain_path.display(),
        d.name.name,
        d.predicates.len(),
        d.functions.len(),
        d.actions.len()
    );
    let mut failed = false;
    for path in problems {
        match check_problem(&ds, &d, path) {
            Ok(line) => outln!("{line}"),
            Err(e) => {
                crate::cli::out::errln!("{e}");
                failed = true;
            }
        }
    }
    if failed {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    }
}

/// A problem parsed and translated with its domain: its summary line, the translation's notes on stderr.
fn check_problem(
    ds: &pddl::Src,
    d: &pddl::ast::Domain,
    path: &Path,
) -> Result<String, pddl::PddlError> {
    let ps = pddl::read_src(path)?;
    let p = pddl::parse_problem(&ps)?;
    let t = pddl::translate(ds, d, &ps, &p)?;
    for n in &t.notes {
        crate::cli::out::errln!("{}: note: {n}", path.display());
    }
    Ok(format!(
        "{}: ok (PDDL problem {} for {}: {} objects, {} goals; translated to {} tasks)",
        path.display(),
        p.name.name,
        p.domain.name,
        p.objects.len(),
        p.goal.len(),
        t.domain.tasks.len()
    ))
}
