//! Every configuration error says `file:line:col` and shows the line: a real configuration
//! (config/sitl-rover.toml) is mutated by parsing it, a bad value put at a known line, and the reported
//! place checked — type errors, unknown keys, out-of-range values and nan/inf, in the vehicle tables and in
//! `[exec]`.

use mavtempo_executive::exec::config::MissionConfig;
use toml_edit::{value, DocumentMut, Item, Table};

const SHIPPED: &str = include_str!(repo!("config/sitl-rover.toml"));

/// The shipped configuration with an `[exec]` table appended (its keys on the last lines).
fn with_exec() -> DocumentMut {
    let mut doc: DocumentMut = SHIPPED.parse().expect("shipped config parses");
    let mut exec = Table::new();
    exec["timestep_ms"] = value(1300);
    exec["repair_share"] = value(0.6);
    exec["same_failure_limit"] = value(3);
    doc["exec"] = Item::Table(exec);
    doc
}

/// Sets `path` (dotted) to `new`, or inserts it when it is not there.
fn set(doc: &mut DocumentMut, path: &str, new: Item) {
    let mut keys: Vec<&str> = path.split('.').collect();
    let last = keys.pop().expect("a key");
    let mut item = doc.as_item_mut();
    for k in keys {
        item = &mut item[k];
    }
    item[last] = new;
}

/// The 1-based line and column of the value of `key = ...` on the line of `text` that holds `marker`.
fn written_at(text: &str, marker: &str) -> (usize, usize) {
    let hits: Vec<(usize, &str)> = text
        .lines()
        .enumerate()
        .filter(|(_, l)| l.contains(marker))
        .collect();
    assert_eq!(hits.len(), 1, "marker {marker:?} once in\n{text}");
    let (i, line) = hits[0];
    let eq = line.find('=').expect("a key = value line");
    let value = eq + 1 + line[eq + 1..].find(|c: char| c != ' ').expect("a value");
    (i + 1, line[..value].chars().count() + 1)
}

/// What is tested, the key path, the new value as TOML, the mutated line's marker, the line expected (when
/// the shipped file has it), whether the error points at the key rather than the value, part of the message.
type Case = (
    &'static str,
    &'static str,
    &'static str,
    &'static str,
    Option<usize>,
    bool,
    &'static str,
);

#[test]
fn every_kind_of_error_is_reported_at_its_line_and_column() {
    let cases: &[Case] = &[
        (
            "type",
            "link.command_retries",
            "\"three\"",
            "command_retries = \"three\"",
            Some(11),
            false,
            "invalid type",
        ),
        (
            "type",
            "home.lat",
            "\"north\"",
            "lat = \"north\"",
            Some(17),
            false,
            "invalid type",
        ),
        (
            "type",
            "actions.move.speed_m_s",
            "true",
            "speed_m_s = true",
            Some(57),
            false,
            "invalid type",
        ),
        (
            "type",
            "actions.move_ptu.duration_ms",
            "-5",
            "duration_ms = -5",
            Some(77),
            false,
            "invalid value",
        ),
        (
            "type",
            "exec.timestep_ms",
            "\"fast\"",
            "timestep_ms = \"fast\"",
            None,
            false,
            "invalid type",
        ),
        (
            "type",
            "modes.on_shutdown",
            "\"land\"",
            "on_shutdown = \"land\"",
            Some(27),
            false,
            "land",
        ),
        (
            "unknown key",
            "actions.move.radius",
            "2",
            "radius = 2",
            None,
            true,
            "unknown field `radius`",
        ),
        (
            "unknown key",
            "exec.timestep_s",
            "2",
            "timestep_s = 2",
            None,
            true,
            "unknown field `timestep_s`",
        ),
        (
            "unknown key",
            "link.adress",
            "\"x\"",
            "adress = \"x\"",
            None,
            true,
            "unknown field `adress`",
        ),
        (
            "range",
            "home.lat",
            "214.0",
            "lat = 214.0",
            Some(17),
            false,
            "home.lat: must be in [-90, 90]",
        ),
        (
            "range",
            "home.lon",
            "-181.0",
            "lon = -181.0",
            Some(18),
            false,
            "home.lon",
        ),
        (
            "range",
            "actions.move.acceptance_radius_m",
            "0.0",
            "acceptance_radius_m = 0.0",
            Some(56),
            false,
            "must be > 0",
        ),
        (
            "range",
            "actions.recharge_battery.until_percent",
            "150.0",
            "until_percent = 150.0",
            Some(72),
            false,
            "[0, 100]",
        ),
        (
            "range",
            "exec.repair_share",
            "1.5",
            "repair_share = 1.5",
            None,
            false,
            "exec.repair_share must be in ]0, 1]",
        ),
        (
            "range",
            "exec.same_failure_limit",
            "0",
            "same_failure_limit = 0",
            None,
            false,
            "at least 1",
        ),
        (
            "range",
            "link.goal_sysids",
            "[0, 255]",
            "goal_sysids = [0, 255]",
            None,
            false,
            "system ids",
        ),
        (
            "range",
            "link.address",
            "\"tcpout:localhost\"",
            "address = \"tcpout:localhost\"",
            Some(8),
            false,
            "expected HOST:PORT",
        ),
        (
            "range",
            "exec.timestep_ms",
            "9223372036854775807",
            "timestep_ms = 9223372036854775807",
            None,
            false,
            "an hour",
        ),
        (
            "range",
            "actions.communicate.duration_ms",
            "604800001",
            "duration_ms = 604800001",
            Some(81),
            false,
            "at most a week",
        ),
        (
            "nan",
            "home.lon",
            "nan",
            "lon = nan",
            Some(18),
            false,
            "not a finite number",
        ),
        (
            "nan",
            "actions.move.speed_m_s",
            "-inf",
            "speed_m_s = -inf",
            Some(57),
            false,
            "not a finite number",
        ),
        (
            "nan",
            "exec.repair_share",
            "nan",
            "repair_share = nan",
            None,
            false,
            "not a finite number",
        ),
        (
            "nan",
            "actions.download_images.until_used",
            "+inf",
            "until_used = +inf",
            None,
            false,
            "not a finite number",
        ),
    ];
    for &(kind, path, new, marker, line, at_key, message) in cases {
        let mut doc = with_exec();
        let parsed: toml_edit::Value = new.parse().expect("a TOML value");
        set(&mut doc, path, Item::Value(parsed));
        let text = doc.to_string();
        let (want_line, value_col) = written_at(&text, marker);
        if let Some(l) = line {
            assert_eq!(
                want_line, l,
                "{kind} {path}: mutated where the shipped file has it"
            );
        }
        let want_col = if at_key {
            text.lines()
                .nth(want_line - 1)
                .map_or(0, |l| l.len() - l.trim_start().len())
                + 1
        } else {
            value_col
        };
        let err = MissionConfig::parse(&text, "rover.toml")
            .err()
            .unwrap_or_else(|| panic!("{kind} {path} = {new}: accepted"))
            .to_string();
        let head = err.lines().next().unwrap_or_default();
        assert!(
            head.starts_with(&format!("rover.toml:{want_line}:{want_col}: error: ")),
            "{kind} {path} = {new}: want {want_line}:{want_col}, got\n{err}"
        );
        assert!(head.contains(message), "{kind} {path}: {err}");
        assert!(
            err.lines().nth(1).is_some_and(|l| l.contains(marker)),
            "{kind} {path}: the line shown\n{err}"
        );
    }
}

#[test]
fn the_unmutated_config_with_exec_is_accepted() {
    let (cfg, text) = (with_exec(), with_exec().to_string());
    assert!(cfg.get("exec").is_some());
    let parsed = MissionConfig::parse(&text, "rover.toml").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(parsed.exec.timestep_ms, 1300);
}

#[test]
fn a_config_that_is_not_utf8_names_the_file_and_the_byte() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("bad.toml");
    let mut bytes = SHIPPED.as_bytes().to_vec();
    let at = SHIPPED.find("lon = ").expect("lon");
    bytes[at + 2] = 0xff; // line 18, column 3
    std::fs::write(&path, &bytes).expect("write");
    let err = MissionConfig::load(&path).unwrap_err().to_string();
    assert!(
        err.starts_with(&format!(
            "{}:18:3: error: invalid UTF-8 (byte 0xff)",
            path.display()
        )),
        "{err}"
    );
}

/// Every leaf value of the shipped configurations (with an `[exec]` table) given the wrong type in turn: the
/// error must be on that key's line, the one showing the new value — the reporter's sweep, where 107 of 114
/// such errors pointed elsewhere.
#[test]
fn a_wrong_type_anywhere_is_reported_on_its_own_line() {
    let mut checked = 0;
    for shipped in [
        SHIPPED,
        include_str!(repo!("config/sitl-auv.toml")),
        include_str!(repo!("config/px4-rover.toml")),
    ] {
        let mut base: DocumentMut = shipped.parse().expect("shipped config parses");
        base["exec"] = with_exec()["exec"].clone();
        for path in leaves(base.as_table(), "") {
            let mut doc = base.clone();
            let old = get(&doc, &path);
            // A number where text is expected, text where anything else is.
            let new = if old.is_some_and(|v| v.is_str()) {
                "7"
            } else {
                "\"x\""
            };
            set(&mut doc, &path, Item::Value(new.parse().expect("value")));
            let text = doc.to_string();
            let key = path.rsplit('.').next().unwrap_or_default();
            let err = MissionConfig::parse(&text, "c.toml")
                .err()
                .unwrap_or_else(|| panic!("{path} = {new}: accepted"))
                .to_string();
            let shown = err.lines().nth(1).unwrap_or_default();
            assert!(
                shown.contains(&format!("{key} = {new}")),
                "{path} = {new}: the error shows another line\n{err}"
            );
            checked += 1;
        }
    }
    assert!(checked > 100, "only {checked} keys");
}

/// The dotted paths of every scalar or array value under `table` (inline tables entered).
fn leaves(table: &dyn toml_edit::TableLike, prefix: &str) -> Vec<String> {
    let mut out = Vec::new();
    for (k, item) in table.iter() {
        let path = format!("{prefix}{k}");
        match item {
            Item::Table(t) => out.extend(leaves(t, &format!("{path}."))),
            Item::Value(toml_edit::Value::InlineTable(t)) => {
                out.extend(leaves(t, &format!("{path}.")))
            }
            Item::Value(_) => out.push(path),
            _ => {}
        }
    }
    out
}

fn get<'a>(doc: &'a DocumentMut, path: &str) -> Option<&'a toml_edit::Value> {
    let mut item = doc.as_item();
    for k in path.split('.') {
        item = item.get(k)?;
    }
    item.as_value()
}

/// Issue 30: `[authority]` and `[limits]` are checked like the rest: a value that is not one of the
/// choices, or a limit that cannot be, is reported at its line with the key.
#[test]
fn authority_and_limits_are_checked() {
    let parse = |extra: &str| {
        MissionConfig::parse(&format!("{SHIPPED}{extra}"), "sitl-rover.toml").map(|_| ())
    };
    let e = parse("\n[authority2]\n").expect_err("an unknown table");
    assert!(e.to_string().contains("authority2"), "{e}");
    let text = SHIPPED.replace("arm = \"companion\"", "arm = \"pilot\"");
    let (line, _) = written_at(&text, "arm = \"pilot\"");
    let e = MissionConfig::parse(&text, "sitl-rover.toml").expect_err("not a choice");
    assert!(e.to_string().contains("unknown variant `pilot`"), "{e}");
    assert!(
        e.to_string().contains(&format!("sitl-rover.toml:{line}:")),
        "{e}"
    );
    let e = parse("\n[limits]\nmax_range_m = -5\n").expect_err("a negative range");
    assert!(e.to_string().contains("limits.max_range_m"), "{e}");
    let e = parse("\n[limits]\npolygon = [[43.5, 1.4], [43.6, 1.4]]\n").expect_err("two corners");
    assert!(e.to_string().contains("at least 3 corners"), "{e}");
    parse("\n[limits]\nmax_range_m = 500\npolygon = [[43.5, 1.4], [43.6, 1.4], [43.6, 1.5]]\n")
        .expect("good limits");
}
