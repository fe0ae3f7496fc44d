//! Entry points: parse from strings (tests, goals built at run time) or load files (CLI, executive).

use std::path::{Path, PathBuf};

use crate::model::{Domain, Goal, Problem};

use super::diag::{decode, Diagnostics, Source, Warning};
use super::eval::Ctx;
use super::parser::Parser;
use super::{resolve_domain, resolve_problem};

/// File extension of domain and problem files.
pub const EXTENSION: &str = "ixt";

fn finish<T>(ctx: Ctx<'_>, value: T) -> Result<T, Diagnostics> {
    if ctx.diags.is_empty() {
        Ok(value)
    } else {
        Err(Diagnostics(ctx.diags))
    }
}

/// Parses and checks a domain. `file` names the source in diagnostics.
pub fn parse_domain(file: &str, text: &str) -> Result<Domain, Diagnostics> {
    let src = Source::new(file, text);
    let ast = Parser::new(src)
        .and_then(|mut p| p.domain_file())
        .map_err(|d| Diagnostics(vec![d]))?;
    let mut ctx = Ctx::new(src);
    let domain = resolve_domain::resolve(&mut ctx, &ast);
    finish(ctx, domain)
}

/// Parses and checks a problem against `domain`.
pub fn parse_problem(file: &str, text: &str, domain: &Domain) -> Result<Problem, Diagnostics> {
    parse_problem_warned(file, text, domain).map(|(p, _)| p)
}

/// [`parse_problem`], with the warnings about what is legal but most likely a mistake (a time without a
/// unit, a place by latitude and longitude without a `home`, an attribute tasks need with no initial value).
pub fn parse_problem_warned(
    file: &str,
    text: &str,
    domain: &Domain,
) -> Result<(Problem, Vec<Warning>), Diagnostics> {
    let src = Source::new(file, text);
    let ast = Parser::new(src)
        .and_then(|mut p| p.problem_file())
        .map_err(|d| Diagnostics(vec![d]))?;
    let mut ctx = Ctx::new(src);
    let problem = resolve_problem::resolve(&mut ctx, domain, &ast);
    let warnings = std::mem::take(&mut ctx.warnings)
        .into_iter()
        .map(Warning)
        .collect();
    finish(ctx, problem).map(|p| (p, warnings))
}

/// Parses one goal declaration (`goal g6 external priority 2 { hold(PICTURE(p6): true, (st, et)); ... }`)
/// against a loaded problem, e.g. a goal received from a ground station. Clock times are read relative to
/// the problem's `start`; the name must not clash with the problem's goals.
pub fn parse_goal(
    file: &str,
    text: &str,
    domain: &Domain,
    problem: &Problem,
) -> Result<Goal, Diagnostics> {
    let src = Source::new(file, text);
    let ast = Parser::new(src)
        .and_then(|mut p| p.goal_only())
        .map_err(|d| Diagnostics(vec![d]))?;
    let mut ctx = Ctx::new(src);
    if problem.goal_id(&ast.name.name).is_some() {
        ctx.err(
            ast.name.span,
            format!("goal `{}` already exists", ast.name.name),
        );
    }
    let goal = resolve_problem::goal(&mut ctx, domain, problem, &ast);
    match goal {
        Some(g) if ctx.diags.is_empty() => Ok(g),
        _ => Err(Diagnostics(ctx.diags)),
    }
}

fn read(path: &Path) -> Result<Vec<u8>, Diagnostics> {
    std::fs::read(path).map_err(|e| {
        Diagnostics::file_error(&path.display().to_string(), format!("cannot read: {e}"))
    })
}

/// Loads and checks a domain file.
pub fn load_domain(path: &Path) -> Result<Domain, Diagnostics> {
    let name = path.display().to_string();
    let bytes = read(path)?;
    parse_domain(&name, decode(&name, &bytes)?)
}

/// Loads and checks a problem file against `domain`.
pub fn load_problem(path: &Path, domain: &Domain) -> Result<Problem, Diagnostics> {
    load_problem_warned(path, domain).map(|(p, _)| p)
}

/// [`load_problem`] with its warnings ([`parse_problem_warned`]).
pub fn load_problem_warned(
    path: &Path,
    domain: &Domain,
) -> Result<(Problem, Vec<Warning>), Diagnostics> {
    let name = path.display().to_string();
    let bytes = read(path)?;
    parse_problem_warned(&name, decode(&name, &bytes)?, domain)
}

/// Loads a problem and the domain its `domain NAME;` header names, found by [`domain_path_for`].
pub fn load_problem_and_domain(path: &Path) -> Result<(Domain, Problem), Diagnostics> {
    let name = path.display().to_string();
    let bytes = read(path)?;
    let text = decode(&name, &bytes)?;
    let FileKind::Problem { domain, .. } = peek_header(&name, text)? else {
        return Err(Diagnostics::file_error(
            &name,
            "this is a domain file, not a problem",
        ));
    };
    let Some(dpath) = domain_path_for(path, &domain) else {
        return Err(Diagnostics::file_error(
            &name,
            format!("cannot find domain `{domain}`: looked for ../{domain}.{EXTENSION} and ./{domain}.{EXTENSION} beside the problem"),
        ));
    };
    let d = load_domain(&dpath)?;
    let p = parse_problem(&name, text, &d)?;
    Ok((d, p))
}

/// Where the domain named `domain` of the problem at `problem` lives: `<dir>/../<domain>.ixt` (the layout
/// `domains/<d>/problems/<p>.ixt`), else `<dir>/<domain>.ixt`.
pub fn domain_path_for(problem: &Path, domain: &str) -> Option<PathBuf> {
    let dir = problem.parent().unwrap_or(Path::new("."));
    let file = format!("{domain}.{EXTENSION}");
    [dir.join("..").join(&file), dir.join(&file)]
        .into_iter()
        .find(|p| p.is_file())
}

/// What a file declares, from its first statements.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum FileKind {
    Domain(String),
    Problem { name: String, domain: String },
}

/// Reads only the header (`domain NAME;` or `problem NAME; domain NAME;`).
pub fn peek_header(file: &str, text: &str) -> Result<FileKind, Diagnostics> {
    use super::lexer::{lex, Tok};
    let src = Source::new(file, text);
    let toks = lex(&src).map_err(|d| Diagnostics(vec![d]))?;
    let word = |i: usize| match toks.get(i).map(|t| &t.tok) {
        Some(Tok::Ident(s)) => Some(s.as_str()),
        _ => None,
    };
    let err_at = |i: usize, msg: &str| {
        let pos = toks.get(i).map_or(text.len(), |t| t.span.start);
        Diagnostics(vec![src.error_at(pos, msg)])
    };
    match word(0) {
        Some("domain") => word(1)
            .map(|n| FileKind::Domain(n.to_string()))
            .ok_or_else(|| err_at(1, "expected the domain's name")),
        Some("problem") => {
            let name = word(1).ok_or_else(|| err_at(1, "expected the problem's name"))?;
            if word(3) != Some("domain") {
                return Err(err_at(3, "expected `domain NAME;` after `problem NAME;`"));
            }
            let domain = word(4).ok_or_else(|| err_at(4, "expected the domain's name"))?;
            Ok(FileKind::Problem {
                name: name.to_string(),
                domain: domain.to_string(),
            })
        }
        _ => Err(err_at(
            0,
            "expected `domain NAME;` or `problem NAME;` at the start of the file",
        )),
    }
}
