//! `mavtempo check`: exit 0 on the shipped files; a malformed copy of any of them exits non-zero with a
//! `file:line:col` diagnostic at the place of the damage.

use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn shipped() -> (Vec<PathBuf>, Vec<PathBuf>) {
    let mut domains = Vec::new();
    let mut problems = Vec::new();
    let rd = |p: &Path| -> Vec<PathBuf> {
        std::fs::read_dir(p)
            .map(|rd| rd.filter_map(|e| e.ok().map(|e| e.path())).collect())
            .unwrap_or_default()
    };
    for d in rd(&root().join("domains"))
        .into_iter()
        .filter(|d| d.is_dir())
    {
        domains.extend(rd(&d).into_iter().filter(|p| p.is_file()));
        problems.extend(rd(&d.join("problems")));
    }
    domains.sort();
    problems.sort();
    (domains, problems)
}

fn check(files: &[PathBuf]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_mavtempo"))
        .arg("check")
        .args(files)
        .output();
    match out {
        Ok(o) => (
            o.status.success(),
            String::from_utf8_lossy(&o.stdout).into_owned(),
            String::from_utf8_lossy(&o.stderr).into_owned(),
        ),
        Err(e) => panic!("cannot run mavtempo: {e}"),
    }
}

/// 1-based line and column (in chars) of byte offset `pos`.
fn line_col(text: &str, pos: usize) -> (usize, usize) {
    let before = &text[..pos];
    let line = before.matches('\n').count() + 1;
    let col = before[before.rfind('\n').map_or(0, |i| i + 1)..]
        .chars()
        .count()
        + 1;
    (line, col)
}

/// Byte offset of the last `;` outside a `//` comment.
fn last_code_semicolon(text: &str) -> Option<usize> {
    let mut found = None;
    let mut offset = 0;
    for line in text.split_inclusive('\n') {
        let code = line.split("//").next().unwrap_or("");
        if let Some(i) = code.rfind(';') {
            found = Some(offset + i);
        }
        offset += line.len();
    }
    found
}

#[test]
fn shipped_files_check_clean() {
    let (domains, problems) = shipped();
    assert!(domains.len() >= 3 && problems.len() >= 4);
    let all: Vec<PathBuf> = domains.iter().chain(&problems).cloned().collect();
    let (ok, stdout, stderr) = check(&all);
    assert!(ok, "{stderr}");
    assert_eq!(
        stdout.lines().filter(|l| l.contains(": ok (")).count(),
        all.len(),
        "{stdout}"
    );
    // Problems alone find their domain through their `domain NAME;` header.
    let (ok, _, stderr) = check(&problems);
    assert!(ok, "{stderr}");
}

#[test]
fn malformed_copies_fail_at_the_damage() {
    let (domains, problems) = shipped();
    let tmp = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("cli_check");
    std::fs::create_dir_all(&tmp).unwrap_or_else(|e| panic!("{e}"));
    for (i, file) in domains.iter().chain(&problems).enumerate() {
        let text = std::fs::read_to_string(file).unwrap_or_default();
        let is_problem = text.trim_start().starts_with("problem") || text.contains("\nproblem ");
        // The domain of a problem copy is given on the command line (the copy lives elsewhere).
        let domain_arg: Vec<PathBuf> = if is_problem {
            let dir = file.parent().and_then(|p| p.parent());
            dir.map(|d| {
                shipped()
                    .0
                    .into_iter()
                    .filter(|f| f.starts_with(d))
                    .collect()
            })
            .unwrap_or_default()
        } else {
            Vec::new()
        };
        // 1. The last `;` removed: "expected `;`" exactly where it was.
        let semi =
            last_code_semicolon(&text).unwrap_or_else(|| panic!("{}: no `;`", file.display()));
        let broken = format!("{}{}", &text[..semi], &text[semi + 1..]);
        // 2. A misspelt name: an attribute in a domain, a value in a problem's initial state.
        let (anchor, replacement, message) = if is_problem {
            let init = text.find("initial {").unwrap_or(0);
            let eq = text[init..].find("= ").map(|k| init + k + 2).unwrap_or(0);
            (eq, "nowhere", "unknown object `nowhere`")
        } else {
            let h = text.find("hold(").map(|k| k + 5).unwrap_or(0);
            (h, "NO_SUCH_ATTR", "unknown attribute `NO_SUCH_ATTR`")
        };
        let end = anchor
            + text[anchor..]
                .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
                .unwrap_or(0);
        let renamed = format!("{}{replacement}{}", &text[..anchor], &text[end..]);
        for (k, (copy, pos, msg)) in [(broken, semi, "expected `;`"), (renamed, anchor, message)]
            .into_iter()
            .enumerate()
        {
            let path = tmp.join(format!("copy{i}_{k}.ixt"));
            std::fs::write(&path, &copy).unwrap_or_else(|e| panic!("{e}"));
            let mut args = domain_arg.clone();
            args.push(path.clone());
            let (ok, _, stderr) = check(&args);
            let (l, c) = line_col(&text, pos);
            let want = format!("{}:{l}:{c}: error: {msg}", path.display());
            assert!(!ok, "{} accepted", path.display());
            assert!(stderr.contains(&want), "want {want:?} in:\n{stderr}");
            assert!(stderr.contains('^'));
        }
    }
}

#[test]
fn unreadable_and_unknown_files_fail_cleanly() {
    let (ok, _, stderr) = check(&[root().join("domains/no_such_file.ixt")]);
    assert!(!ok);
    assert!(
        stderr.contains("no_such_file.ixt:1:1: error: cannot read"),
        "{stderr}"
    );
}

fn mavtempo(args: &[&str]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_mavtempo"))
        .current_dir(root())
        .args(args)
        .output()
        .unwrap_or_else(|e| panic!("cannot run mavtempo: {e}"));
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// The AUV config as it was shipped before the check: bindings named after no task of the AUV domain.
fn broken_auv_config() -> PathBuf {
    let text = std::fs::read_to_string(root().join("config/sitl-auv.toml"))
        .unwrap_or_else(|e| panic!("{e}"))
        .replace("[actions.go]", "[actions.move]");
    let tmp = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("cli_check_config");
    std::fs::create_dir_all(&tmp).unwrap_or_else(|e| panic!("{e}"));
    let path = tmp.join("auv.toml");
    std::fs::write(&path, text).unwrap_or_else(|e| panic!("{e}"));
    path
}

#[test]
fn check_config_passes_the_shipped_auv_config_and_names_a_mismatch() {
    let (ok, stdout, stderr) = mavtempo(&[
        "check",
        "--config",
        "config/sitl-auv.toml",
        "domains/auv/auv.ixt",
        "domains/auv/problems/vents.ixt",
    ]);
    assert!(ok, "{stderr}");
    assert!(
        stdout.contains("config/sitl-auv.toml: ok against"),
        "{stdout}"
    );
    assert!(stdout.contains("from the problem"), "{stdout}");

    let broken = broken_auv_config();
    let b = broken.display().to_string();
    let (ok, _, stderr) = mavtempo(&["check", "--config", &b, "domains/auv/auv.ixt"]);
    assert!(!ok);
    let text = std::fs::read_to_string(&broken).unwrap_or_default();
    let line = text
        .lines()
        .position(|l| l == "[actions.move]")
        .map_or(0, |i| i + 1);
    assert!(
        stderr.contains(&format!(
            "{b}:{line}: actions.move: the domain has no task `move`"
        )),
        "{stderr}"
    );
    assert!(
        stderr.contains("actions.go: task `go` has no binding") && stderr.contains("auv.ixt:15"),
        "{stderr}"
    );
    assert!(
        stderr.contains("does not match domain `auv`: 2 error(s)"),
        "{stderr}"
    );
}

#[test]
fn run_refuses_a_mismatched_config_before_planning_or_connecting() {
    let broken = broken_auv_config();
    let (ok, stdout, stderr) = mavtempo(&[
        "run",
        "--config",
        &broken.display().to_string(),
        "--link-timeout",
        "1",
        "domains/auv/auv.ixt",
        "domains/auv/problems/vents.ixt",
    ]);
    assert!(!ok);
    assert!(stderr.contains("does not match domain `auv`"), "{stderr}");
    assert!(!stdout.contains("planning"), "{stdout}");
    assert!(!stderr.contains("heartbeat"), "{stderr}");
}

/// A bad `[exec]` value and a non-UTF-8 byte in a configuration: `check --config` and `run` exit non-zero
/// with the file, line and column, and show the line.
#[test]
fn config_errors_exit_non_zero_at_their_line_and_column() {
    let dir = tempfile::tempdir().expect("temp dir");
    let text = std::fs::read_to_string(root().join("config/sitl-rover.toml")).expect("config");
    let lines = text.lines().count();
    let bad = dir.path().join("bad.toml");
    std::fs::write(
        &bad,
        format!("{text}\n[exec]\ntimestep_ms = 1300\nrepair_share = nan\n"),
    )
    .expect("write");
    let at = format!("{}:{}:16: error: ", bad.display(), lines + 4);
    let domain = root().join("domains/rover/rover.ixt");
    let problem = root().join("domains/rover/problems/fig2.ixt");
    let (d, p) = (domain.to_string_lossy(), problem.to_string_lossy());
    let cfg = bad.to_string_lossy();
    let (ok, _, err) = mavtempo(&["check", "--config", &cfg, &d]);
    assert!(
        !ok && err.contains(&at) && err.contains("repair_share = nan"),
        "{err}"
    );
    let (ok, _, err) = mavtempo(&["run", "--config", &cfg, &d, &p]);
    assert!(!ok && err.contains(&at), "{err}");
    let mut bytes = text.into_bytes();
    bytes[0] = 0xc0;
    std::fs::write(&bad, bytes).expect("write");
    let (ok, _, err) = mavtempo(&["check", "--config", &cfg, &d]);
    assert!(
        !ok && err.contains(&format!(
            "{}:1:1: error: invalid UTF-8 (byte 0xc0)",
            bad.display()
        )),
        "{err}"
    );
}
