//! docs/config.md against the code: its ```toml blocks, together, are a configuration the code accepts
//! (every table rejects unknown keys, so each documented key is a real one), and table by table the keys
//! documented are the keys the code accepts — found by asking the code: a probe key added to a table is
//! refused with the list of the table's keys (serde's "unknown field `x`, expected one of ...").

use std::collections::BTreeSet;

use mavtempo_executive::exec::config::MissionConfig;

const PROBE: &str = "zz_not_a_key";

fn documented() -> toml::Table {
    let doc = std::fs::read_to_string(repo!("docs/config.md")).expect("docs/config.md");
    let mut text = String::new();
    let mut inside = false;
    for line in doc.lines() {
        match (inside, line.trim()) {
            (false, "```toml") => inside = true,
            (true, "```") => inside = false,
            (true, _) => {
                text.push_str(line);
                text.push('\n');
            }
            _ => {}
        }
    }
    if let Err(e) = MissionConfig::parse(&text, repo!("docs/config.md (its toml blocks)")) {
        panic!("the documented configuration is refused:\n{e}");
    }
    text.parse().expect("TOML")
}

/// The keys the code accepts in the table at `path` (keys; `0` for an array's first element), or `None`
/// when the table takes any key (a map such as `[exec.reserve]`).
fn accepted(doc: &toml::Table, path: &[String]) -> Option<BTreeSet<String>> {
    let mut probe = doc.clone();
    let mut at = &mut probe;
    for p in path {
        let v = at.get_mut(p).expect("documented path");
        at = match v {
            toml::Value::Array(a) => a
                .first_mut()
                .and_then(|v| v.as_table_mut())
                .expect("a table"),
            v => v.as_table_mut().expect("a table"),
        };
    }
    at.insert(PROBE.into(), toml::Value::String("x".into()));
    let text = toml::to_string(&probe).expect("serialises");
    let err = match MissionConfig::parse(&text, "probe") {
        Ok(_) => return None,
        Err(e) => e.to_string(),
    };
    // A map whose values are numbers refuses the probe's string as a value, not as a key; a map keyed by
    // the modes of [modes] refuses it as a mode.
    if err.contains("invalid type: string") || err.contains("not a mode of [modes]") {
        return None;
    }
    let unknown = format!("unknown field `{PROBE}`");
    let variant = format!("unknown variant `{PROBE}`");
    let rest = err
        .split_once(&unknown)
        .or_else(|| err.split_once(&variant))
        .map(|(_, r)| r.lines().next().unwrap_or(""))
        .unwrap_or_else(|| panic!("{}: not refused as a key:\n{err}", path.join(".")));
    if rest.contains("there are no fields") {
        return Some(BTreeSet::new());
    }
    Some(
        rest.split('`')
            .skip(1)
            .step_by(2)
            .map(str::to_string)
            .collect(),
    )
}

fn keys_of(v: &toml::Value) -> Option<&toml::Table> {
    match v {
        toml::Value::Table(t) => Some(t),
        toml::Value::Array(a) => a.first().and_then(|v| v.as_table()),
        _ => None,
    }
}

/// Compares the table at `path` and recurses into its documented sub-tables. `[actions.*]` tables are one
/// table type: their keys are compared together.
fn walk(doc: &toml::Table, table: &toml::Table, path: Vec<String>, wrong: &mut Vec<String>) {
    let name = if path.is_empty() {
        "(top level)".to_string()
    } else {
        path.join(".")
    };
    if path == ["actions"] {
        let union: BTreeSet<String> = table
            .values()
            .filter_map(keys_of)
            .flat_map(|t| t.keys().cloned())
            .collect();
        let Some((first, _)) = table.iter().next() else {
            wrong.push("no [actions.*] table documented".into());
            return;
        };
        let code = accepted(doc, &["actions".to_string(), first.clone()]).unwrap_or_default();
        compare("actions.*", &union, &code, wrong);
        for (task, t) in table.iter().filter_map(|(k, v)| Some((k, keys_of(v)?))) {
            for (k, v) in t {
                if let Some(sub) = keys_of(v) {
                    let p = vec!["actions".to_string(), task.clone(), k.clone()];
                    walk(doc, sub, p, wrong);
                }
            }
        }
        return;
    }
    let documented: BTreeSet<String> = table.keys().cloned().collect();
    match accepted(doc, &path) {
        Some(code) => compare(&name, &documented, &code, wrong),
        // A map: any key is a name of the domain's (a resource, a mode).
        None => return,
    }
    for (k, v) in table {
        if let Some(sub) = keys_of(v) {
            let mut p = path.clone();
            p.push(k.clone());
            walk(doc, sub, p, wrong);
        }
    }
}

fn compare(
    table: &str,
    documented: &BTreeSet<String>,
    code: &BTreeSet<String>,
    wrong: &mut Vec<String>,
) {
    for k in code.difference(documented) {
        wrong.push(format!(
            "[{table}] {k}: accepted by the code, not in docs/config.md"
        ));
    }
    for k in documented.difference(code) {
        wrong.push(format!(
            "[{table}] {k}: in docs/config.md, not a key of the code"
        ));
    }
}

#[test]
fn the_reference_has_every_key_the_code_accepts_and_no_other() {
    let doc = documented();
    let mut wrong = Vec::new();
    walk(&doc, &doc, Vec::new(), &mut wrong);
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

/// The walk sees a key left out, at every depth: the top level, a table, a map keyed by an enum, the
/// actions, the executive.
#[test]
fn a_key_left_out_of_the_reference_is_found() {
    let doc = documented();
    let cut = |path: &[&str]| {
        let mut d = doc.clone();
        let (last, tables) = path.split_last().expect("a path");
        let mut at = &mut d;
        for p in tables {
            at = match at.get_mut(*p).expect("documented") {
                toml::Value::Array(a) => a[0].as_table_mut().expect("table"),
                v => v.as_table_mut().expect("table"),
            };
        }
        at.remove(*last).expect("documented key");
        let mut wrong = Vec::new();
        walk(&d.clone(), &d, Vec::new(), &mut wrong);
        wrong
    };
    for (path, said) in [
        (&["autopilot"][..], "[(top level)] autopilot"),
        (&["link", "tlog"][..], "[link] tlog"),
        (
            &["mapping", "goals", "survey"][..],
            "[mapping.goals] survey",
        ),
        (&["state", "end_still"][..], "[state] end_still"),
        (
            &["actions", "download", "poll_ms"][..],
            "[actions.*] poll_ms",
        ),
        (&["exec", "dispatch"][..], "[exec] dispatch"),
    ] {
        assert_eq!(
            cut(path),
            vec![format!(
                "{said}: accepted by the code, not in docs/config.md"
            )],
            "{path:?}"
        );
    }
}
