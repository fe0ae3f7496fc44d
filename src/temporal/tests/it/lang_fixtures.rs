//! The malformed corpus under tests/fixtures/lang: each file must fail with a diagnostic at the expected
//! line:col whose message contains the expected text. Text fixtures carry the expectation on their first
//! line (`// expect: L:C message`); binary ones in a sidecar `NAME.expect`.

use std::path::{Path, PathBuf};

use mavtempo_temporal::lang::{self, FileKind};

fn root() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

fn expectation(path: &Path) -> (usize, usize, String) {
    let sidecar = path.with_extension("expect");
    let line = if sidecar.is_file() {
        std::fs::read_to_string(&sidecar).unwrap_or_default()
    } else {
        let text = std::fs::read_to_string(path).unwrap_or_default();
        text.lines()
            .next()
            .and_then(|l| l.strip_prefix("// expect: "))
            .unwrap_or_default()
            .to_string()
    };
    let (pos, msg) = line.trim().split_once(' ').unwrap_or(("", ""));
    let (l, c) = pos.split_once(':').unwrap_or(("0", "0"));
    (
        l.parse().unwrap_or(0),
        c.parse().unwrap_or(0),
        msg.to_string(),
    )
}

/// Loads a fixture the way `mavtempo check` does: a problem against its domain from `domains/`.
fn load(path: &Path) -> Result<(), lang::Diagnostics> {
    let bytes = std::fs::read(path).unwrap_or_default();
    let name = path.display().to_string();
    let header = std::str::from_utf8(&bytes)
        .ok()
        .and_then(|t| lang::peek_header(&name, t).ok());
    match header {
        Some(FileKind::Problem { domain, .. }) => {
            let dpath = root()
                .join("domains")
                .join(&domain)
                .join(format!("{domain}.ixt"));
            let d = lang::load_domain(&dpath)?;
            lang::load_problem(path, &d).map(|_| ())
        }
        _ => lang::load_domain(path).map(|_| ()),
    }
}

#[test]
fn every_malformed_fixture_is_reported_at_the_right_place() {
    let dir = root().join("tests/fixtures/lang");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .map(|rd| rd.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    files.retain(|p| p.extension().is_some_and(|e| e == "ixt"));
    files.sort();
    assert!(files.len() >= 30, "corpus too small: {}", files.len());
    let mut failures = Vec::new();
    for f in &files {
        let (line, col, msg) = expectation(f);
        assert!(
            line > 0 && !msg.is_empty(),
            "{}: no expectation",
            f.display()
        );
        match load(f) {
            Ok(()) => failures.push(format!("{}: accepted", f.display())),
            Err(d) => {
                let hit = d
                    .iter()
                    .any(|x| x.line == line && x.col == col && x.message.contains(&msg));
                let rendered = d.to_string();
                let header = format!("{}:{line}:{col}: error: ", f.display());
                if !hit || !rendered.contains(&header) || !rendered.contains('^') {
                    failures.push(format!(
                        "{}: expected {line}:{col} {msg:?}, got:\n{rendered}",
                        f.display()
                    ));
                }
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
