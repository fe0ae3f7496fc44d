//! `mavtempo check` on PDDL: a domain and its problem are read as `plan` reads them (parsed, translated),
//! so a mistake gets the same `file:line:col` diagnostic from both, and a good pair is "ok" without
//! planning.

use std::path::Path;
use std::process::Command;

fn mavtempo(args: &[&str], files: &[&Path]) -> (bool, String, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_mavtempo"))
        .args(args)
        .args(files)
        .output()
        .expect("runs");
    (
        o.status.success(),
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

#[test]
fn a_good_pddl_pair_checks_ok() {
    let d = Path::new("tests/fixtures/pddl/courier.pddl");
    let p = Path::new("tests/fixtures/pddl/courier-1.pddl");
    let (ok, out, err) = mavtempo(&["check"], &[d, p]);
    assert!(ok, "{out}\n{err}");
    assert!(
        out.contains("courier.pddl: ok (PDDL domain courier"),
        "{out}"
    );
    assert!(
        out.contains("courier-1.pddl: ok (PDDL problem courier-1 for courier"),
        "{out}"
    );
}

/// An object the problem uses and never declares: `check` fails at its line and column, with the very
/// message `plan` gives.
#[test]
fn a_pddl_mistake_is_located_as_plan_locates_it() {
    let dir = tempfile::TempDir::new().expect("temp dir");
    let text = std::fs::read_to_string("tests/fixtures/pddl/courier-1.pddl").expect("fixture");
    let bad = dir.path().join("courier-bad.pddl");
    std::fs::write(&bad, text.replace("(parcel-at p1 a)", "(parcel-at p9 a)")).expect("write");
    let d = Path::new("tests/fixtures/pddl/courier.pddl");
    let (ok, out, err) = mavtempo(&["check"], &[d, &bad]);
    assert!(!ok, "{out}\n{err}");
    let first = err.lines().next().unwrap_or("");
    let at = format!("{}:6:", bad.display());
    assert!(first.starts_with(&at), "{err}");
    assert!(first.contains("p9"), "{err}");
    let (planned, _, plan_err) = mavtempo(&["plan"], &[d, &bad]);
    assert!(!planned);
    assert_eq!(plan_err.lines().next(), Some(first), "{plan_err}");
}

/// PDDL and native files are not mixed on one command line: said, not guessed.
#[test]
fn pddl_and_native_files_are_not_mixed() {
    let (ok, _, err) = mavtempo(
        &["check"],
        &[
            Path::new("tests/fixtures/pddl/courier.pddl"),
            Path::new("domains/vehicle/problems/first.ixt"),
        ],
    );
    assert!(!ok);
    assert!(err.contains("PDDL files are checked as"), "{err}");
}
