//! `mavtempo check FILE...`: validates domain and problem files. A problem is checked against the domain of
//! the same name given on the command line, else the one its `domain NAME;` header names beside it.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::Args;

use crate::lang::{self, Diagnostics, FileKind};
use crate::model::Domain;

#[derive(Args, Debug)]
pub struct CheckArgs {
    /// Domain and problem files (e.g. `domains/*/*.ixt domains/*/problems/*`).
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
}

pub fn run(args: CheckArgs) -> ExitCode {
    let mut failed = false;
    let mut kinds = Vec::new();
    for path in &args.files {
        match header(path) {
            Ok(k) => kinds.push((path, k)),
            Err(d) => {
                eprint!("{d}");
                failed = true;
            }
        }
    }
    // Domains first, so problems find them whatever the argument order.
    let mut domains: HashMap<String, Option<Domain>> = HashMap::new();
    for (path, kind) in &kinds {
        if let FileKind::Domain(name) = kind {
            match lang::load_domain(path) {
                Ok(d) => {
                    println!(
                        "{}: ok (domain {}: {} types, {} attributes, {} resources, {} tasks)",
                        path.display(),
                        d.name,
                        d.types.len(),
                        d.attrs.len(),
                        d.resources.len(),
                        d.tasks.len()
                    );
                    domains.insert(name.clone(), Some(d));
                }
                Err(e) => {
                    eprint!("{e}");
                    failed = true;
                    domains.insert(name.clone(), None);
                }
            }
        }
    }
    for (path, kind) in &kinds {
        let FileKind::Problem { domain, .. } = kind else {
            continue;
        };
        if !domains.contains_key(domain) {
            let loaded = match lang::domain_path_for(path, domain) {
                Some(dp) => lang::load_domain(&dp).map_err(|e| eprint!("{e}")).ok(),
                None => {
                    eprint!(
                        "{}",
                        Diagnostics::file_error(
                            &path.display().to_string(),
                            format!("cannot find domain `{domain}` (give its file on the command line or put it at ../{domain}.{})", lang::EXTENSION),
                        )
                    );
                    None
                }
            };
            domains.insert(domain.clone(), loaded);
        }
        let Some(Some(d)) = domains.get(domain) else {
            eprintln!(
                "{}: not checked: domain `{domain}` has errors",
                path.display()
            );
            failed = true;
            continue;
        };
        match lang::load_problem(path, d) {
            Ok(p) => println!(
                "{}: ok (problem {} for {}: {} objects, {} goals, horizon {} s)",
                path.display(),
                p.name,
                p.domain,
                p.objects.len() - d.objects.len(),
                p.goals.len(),
                p.horizon / 1000
            ),
            Err(e) => {
                eprint!("{e}");
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

fn header(path: &Path) -> Result<FileKind, Diagnostics> {
    let name = path.display().to_string();
    let bytes = std::fs::read(path)
        .map_err(|e| Diagnostics::file_error(&name, format!("cannot read: {e}")))?;
    lang::peek_header(&name, lang::decode(&name, &bytes)?)
}
