//! `mavtempo check FILE...`: validates domain and problem files. A problem is checked against the domain of
//! the same name given on the command line, else the one its `domain NAME;` header names beside it.
//! `mavtempo check DOMAIN.pddl [PROBLEM.pddl...]`: PDDL, read as `plan` reads it ([`super::check_pddl`]).
//! `mavtempo check --config FILE DOMAIN [PROBLEM]`: checks a vehicle configuration against its domain (and
//! problem), printing every mismatch ([`crate::config_check`]).

use super::error::CliError;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::Args;

use crate::cli::out::outln;
use crate::config_check::{self, CheckedConfig, HomeSource};
use crate::lang::{self, Diagnostics, FileKind};
use crate::model::{Domain, Problem};
use crate::vehicle::config::VehicleConfig;

#[derive(Args, Debug)]
pub struct CheckArgs {
    /// A vehicle configuration (config/*.toml) to check against the domain and, if given, the problem:
    /// then FILES are `DOMAIN [PROBLEM]`.
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
    /// Domain and problem files (e.g. `domains/*/*.ixt domains/*/problems/*`), or a PDDL domain then its
    /// problems (`domain.pddl p1.pddl p2.pddl`).
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
}

pub fn run(args: CheckArgs) -> ExitCode {
    if let Some(config) = &args.config {
        return match check_config(config, &args.files) {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                crate::cli::out::errln!("{e}");
                ExitCode::FAILURE
            }
        };
    }
    if args.files.iter().any(|f| crate::pddl::is_pddl(f)) {
        if !args.files.iter().all(|f| crate::pddl::is_pddl(f)) {
            crate::cli::out::errln!("check: PDDL files are checked as DOMAIN.pddl [PROBLEM.pddl...], without native files");
            return ExitCode::FAILURE;
        }
        return super::check_pddl::run(&args.files);
    }
    let mut failed = false;
    let mut kinds = Vec::new();
    for path in &args.files {
        match header(path) {
            Ok(k) => kinds.push((path, k)),
            Err(d) => {
                crate::cli::out::err!("{d}");
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
                    outln!(
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
                    crate::cli::out::err!("{e}");
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
                Some(dp) => lang::load_domain(&dp)
                    .map_err(|e| crate::cli::out::err!("{e}"))
                    .ok(),
                None => {
                    crate::cli::out::err!(
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
            crate::cli::out::errln!(
                "{}: not checked: domain `{domain}` has errors",
                path.display()
            );
            failed = true;
            continue;
        };
        match lang::load_problem_warned(path, d) {
            Ok((p, warnings)) => {
                for w in &warnings {
                    crate::cli::out::errln!("{w}");
                }
                outln!(
                    "{}: ok (problem {} for {}: {} objects, {} goals, horizon {} s){}",
                    path.display(),
                    p.name,
                    p.domain,
                    p.objects.len() - d.objects.len(),
                    p.goals.len(),
                    p.horizon / 1000,
                    match warnings.len() {
                        0 => String::new(),
                        1 => ", 1 warning".to_string(),
                        n => format!(", {n} warnings"),
                    }
                )
            }
            Err(e) => {
                crate::cli::out::err!("{e}");
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

/// `check --config FILE DOMAIN [PROBLEM]`.
fn check_config(config: &Path, files: &[PathBuf]) -> Result<(), CliError> {
    let (domain_path, problem_path) = match files {
        [d] => (d, None),
        [d, p] => (d, Some(p)),
        _ => {
            return Err(CliError::CheckFiles {
                config: config.display().to_string(),
                files: files.len(),
            })
        }
    };
    let domain = lang::load_domain(domain_path)?;
    let problem = match problem_path {
        Some(p) => Some(lang::load_problem(p, &domain)?),
        None => None,
    };
    let (cfg, _) = super::run::load_config(config)?;
    let checked = checked_config(&cfg, &domain, problem.as_ref())?;
    let against = match problem_path {
        Some(p) => format!("{} and {}", domain_path.display(), p.display()),
        None => domain_path.display().to_string(),
    };
    outln!(
        "{}: ok against {against} ({} bindings; home {:.6}, {:.6} from the {})",
        config.display(),
        cfg.actions.len(),
        checked.home.lat,
        checked.home.lon,
        match checked.home_from {
            HomeSource::Problem => "problem",
            HomeSource::Config => "config",
        }
    );
    Ok(())
}

/// The configuration checked against the domain (and problem): warnings printed, every mismatch in the
/// error. What `check --config`, `run` and `demo` share.
pub fn checked_config(
    cfg: &VehicleConfig,
    domain: &Domain,
    problem: Option<&Problem>,
) -> Result<CheckedConfig, CliError> {
    match config_check::check(cfg, domain, problem) {
        Ok(c) => {
            for w in &c.warnings {
                crate::cli::out::errln!("{w}");
            }
            Ok(c)
        }
        Err(issues) => {
            let origin = cfg
                .source
                .as_ref()
                .map_or("the configuration", |s| s.origin.as_str());
            let lines: Vec<String> = issues.iter().map(|i| i.to_string()).collect();
            let errors = issues
                .iter()
                .filter(|i| i.severity == config_check::Severity::Error)
                .count();
            Err(CliError::ConfigMismatch {
                issues: lines.join("\n"),
                origin: origin.to_string(),
                domain: domain.name.clone(),
                errors,
            })
        }
    }
}
