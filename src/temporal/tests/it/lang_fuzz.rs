//! No input makes the language panic: random bytes, random token soup, and randomly damaged copies of the
//! shipped files. Every failure is a located diagnostic inside the text.

use std::path::PathBuf;
use std::sync::OnceLock;

use mavtempo_temporal::lang::{self, Diagnostics};
use mavtempo_temporal::model::{Domain, Problem};
use proptest::prelude::*;

fn root() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

fn rover() -> &'static (Domain, Problem) {
    static R: OnceLock<(Domain, Problem)> = OnceLock::new();
    R.get_or_init(|| {
        lang::load_problem_and_domain(&root().join("domains/rover/problems/fig2.ixt"))
            .unwrap_or_else(|e| panic!("{e}"))
    })
}

fn shipped_texts() -> &'static Vec<String> {
    static T: OnceLock<Vec<String>> = OnceLock::new();
    T.get_or_init(|| {
        [
            repo!("domains/rover/rover.ixt"),
            repo!("domains/rover/problems/fig2.ixt"),
            repo!("domains/rover/problems/dala.ixt"),
            repo!("domains/auv/auv.ixt"),
            repo!("domains/auv/problems/vents.ixt"),
            repo!("domains/shopping/shopping.ixt"),
            repo!("domains/shopping/problems/day.ixt"),
        ]
        .iter()
        .map(|p| std::fs::read_to_string(root().join(p)).unwrap_or_default())
        .collect()
    })
}

/// Diagnostics must point inside the text (or just past its end) and render with a header.
fn well_formed(text: &str, d: &Diagnostics) -> bool {
    let lines = text.split('\n').count();
    !d.is_empty()
        && d.iter()
            .all(|x| x.line >= 1 && x.line <= lines && x.col >= 1)
        && d.to_string().contains(": error: ")
}

/// Feeds `bytes` to every entry point (through a file, as `mavtempo check` does, when they are not UTF-8);
/// returns false if some failure is badly located.
fn run_all(bytes: &[u8]) -> bool {
    let (d, p) = rover();
    match std::str::from_utf8(bytes) {
        Ok(text) => run_text(text, d, p),
        Err(_) => {
            let path = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("lang_fuzz_bytes.ixt");
            if std::fs::write(&path, bytes).is_err() {
                return false;
            }
            let lossy = String::from_utf8_lossy(bytes).into_owned();
            let a = lang::load_domain(&path)
                .err()
                .is_some_and(|e| well_formed(&lossy, &e));
            let b = lang::load_problem(&path, d)
                .err()
                .is_some_and(|e| well_formed(&lossy, &e));
            a && b
        }
    }
}

fn run_text(text: &str, d: &Domain, p: &Problem) -> bool {
    let mut ok = true;
    if let Err(e) = lang::parse_domain("f", text) {
        ok &= well_formed(text, &e);
    }
    if let Err(e) = lang::parse_problem("f", text, d) {
        ok &= well_formed(text, &e);
    }
    if let Err(e) = lang::parse_goal("f", text, d, p) {
        ok &= well_formed(text, &e);
    }
    let _ = lang::peek_header("f", text);
    ok
}

const VOCAB: &[&str] = &[
    "domain",
    "problem",
    "rover",
    "d",
    "type",
    "constant",
    "attribute",
    "resource",
    "task",
    "event",
    "hold",
    "use",
    "consume",
    "produce",
    "variable",
    "secondary",
    "achieve",
    "goal",
    "initial",
    "object",
    "horizon",
    "start",
    "home",
    "lat",
    "lon",
    "alt",
    "at",
    "in",
    "from",
    "level",
    "capacity",
    "unary",
    "reservoir",
    "external",
    "internal",
    "priority",
    "latePreemptive",
    "nonPreemptive",
    "st",
    "et",
    "AT_ROBOT",
    "PICTURE",
    "STORAGE",
    "CAMERA",
    "VISIBLE",
    "W1",
    "base",
    "p1",
    "location",
    "bool",
    "true",
    "false",
    "distance",
    "?x",
    "?from",
    "?to",
    "?d",
    "+oo",
    "-oo",
    "0",
    "3",
    "2.5",
    "20min",
    "08:00",
    "20:00",
    "1e9",
    "99999999999999999999999",
    "(",
    ")",
    "{",
    "}",
    "[",
    "]",
    ",",
    ";",
    ":",
    "=",
    "!=",
    "<=",
    ">=",
    "<",
    ">",
    "+",
    "-",
    "*",
    "/",
    "//",
    "/*",
    "*/",
    "\n",
    "é",
    "\0",
];

fn soup() -> impl Strategy<Value = String> {
    let prefix = prop_oneof![
        Just(String::new()),
        Just("domain d;\n".to_string()),
        Just("problem p; domain rover;\n".to_string()),
        Just("domain d; type location; type s = {A, B}; attribute AT(): location; resource R: reservoir capacity 3;\ntask t(?x: location) (st, et) {\n".to_string()),
    ];
    let words = proptest::collection::vec((proptest::sample::select(VOCAB), any::<bool>()), 0..120);
    (prefix, words).prop_map(|(p, w)| {
        let mut s = p;
        for (tok, space) in w {
            s.push_str(tok);
            if space {
                s.push(' ');
            }
        }
        s
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn random_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..1500)) {
        prop_assert!(run_all(&bytes));
    }

    #[test]
    fn token_soup_never_panics(text in soup()) {
        prop_assert!(run_all(text.as_bytes()));
    }

    #[test]
    fn damaged_shipped_files_never_panic(
        which in 0usize..7,
        cuts in proptest::collection::vec((any::<prop::sample::Index>(), 0usize..12, proptest::sample::select(VOCAB)), 1..4),
    ) {
        let mut text = shipped_texts()[which].clone();
        for (at, len, insert) in cuts {
            let mut start = at.index(text.len() + 1);
            while !text.is_char_boundary(start) { start -= 1; }
            let mut end = (start + len).min(text.len());
            while !text.is_char_boundary(end) { end -= 1; }
            text.replace_range(start..end.max(start), insert);
        }
        prop_assert!(run_all(text.as_bytes()));
    }
}
