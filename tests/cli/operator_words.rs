//! Reasons in the operator's words (issue 30 item 6): the built-in Fig. 2 story (faults, repairs, a complete
//! replanning, uploaded goals and their STATUSTEXT verdicts) prints no Rust debug text — no `Some(…)`, no enum
//! variant names such as `OverConsumption { c: … }`, `(InBounds)`, `NoGoals` — in its trace, its summary,
//! the texts its ground station received, or the report's reasons.

use crate::support::demo_report;

/// Debug renderings that must not reach an operator.
const DEBUG_PATTERNS: [&str; 14] = [
    "Some(",
    "None)",
    "{ c:",
    "{ p:",
    "OverConsumption",
    "OverProduction",
    "InBounds",
    "TooEarly",
    "TooLate",
    "NoGoals",
    "(Finished)",
    "Consistent",
    "Confirmed",
    "LeftAsIs",
];

/// A CamelCase word followed by ` {` or `(`: a struct or tuple variant's Debug.
fn camel_debug(text: &str) -> Option<&str> {
    text.split(|c: char| c.is_whitespace() || c == '"')
        .find(|w| {
            let ident: String = w
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric())
                .collect();
            let camel = ident.len() > 3
                && ident.starts_with(|c: char| c.is_ascii_uppercase())
                && ident.chars().skip(1).any(|c| c.is_ascii_uppercase())
                && ident.chars().any(|c| c.is_ascii_lowercase());
            camel && w[ident.len()..].starts_with('(')
        })
}

fn assert_operator_words(what: &str, text: &str) {
    for p in DEBUG_PATTERNS {
        assert!(
            !text.contains(p),
            "{what} has Rust debug text `{p}`:\n{}",
            text.lines()
                .filter(|l| l.contains(p))
                .collect::<Vec<_>>()
                .join("\n")
        );
    }
    if let Some(w) = camel_debug(text) {
        panic!("{what} has Rust debug text `{w}`");
    }
}

#[test]
fn the_fig2_story_speaks_the_operator_s_words() {
    let (stdout, report) = demo_report::demo_with_report(&[]);
    // The story has what the scan is for: a level over the plan, a report out of bounds, uploaded goals.
    assert!(stdout.contains("more used than planned"), "{stdout}");
    assert!(stdout.contains("nominal (in time)"), "{stdout}");
    assert!(stdout.contains(" accepted: "), "{stdout}");
    assert_operator_words("demo stdout", &stdout);
    for g in report["goals"].as_array().expect("goals") {
        assert_operator_words("a goal's reason", g["reason"].as_str().unwrap_or(""));
    }
}
