//! Every shipped scenario file parses and starts a simulator.

use std::time::Duration;

#[tokio::test]
async fn shipped_scenarios_load_and_run() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios");
    let mut n = 0;
    for entry in std::fs::read_dir(&dir).expect("scenarios dir") {
        let path = entry.expect("entry").path();
        if path.extension().and_then(|e| e.to_str()) != Some("toml") {
            continue;
        }
        let scenario = sitl::Scenario::load(&path).unwrap_or_else(|e| panic!("{e}"));
        let mut cfg = sitl::SimConfig::for_tests();
        cfg.scenario = scenario;
        let sim = sitl::spawn(cfg).await.expect("spawn");
        sim.step(Duration::from_secs(1)).await.expect("step");
        assert_eq!(sim.snapshot().time_ms, 1000);
        n += 1;
    }
    assert!(n >= 3, "only {n} scenarios");
}

#[test]
fn a_missing_scenario_file_is_a_clear_error() {
    let err =
        sitl::Scenario::load(std::path::Path::new("/nonexistent/x.toml")).expect_err("missing");
    assert!(err.to_string().contains("/nonexistent/x.toml"), "{err}");
}

#[test]
fn scenario_errors_are_reported_at_line_and_column() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/fig2.toml");
    let text = std::fs::read_to_string(&path).expect("fig2.toml");
    // (line as shipped, its replacement, expected line:col, part of the message)
    let cases = [
        (
            "speed_mps = 0.45",
            "speed_mps = nan",
            "13:13",
            "not a finite number",
        ),
        (
            "speed_mps = 0.45",
            "speed_mps = \"fast\"",
            "13:13",
            "invalid type",
        ),
        (
            "accel_mps2 = 0.5",
            "accel_mps = 0.5",
            "15:1",
            "unknown field `accel_mps`",
        ),
        (
            "initial_pct = 90.0",
            "initial_pct = 150.0",
            "19:15",
            "battery.initial_pct: must be in [0, 100]",
        ),
        (
            "center_m = [0.0, 0.0]",
            "center = [214.0, 0.0]",
            "32:10",
            "sunlit_zones.0.center: [lat, lon]",
        ),
        (
            "end_s = 960.0",
            "end_s = 100.0",
            "36:1",
            "visibility_windows.0",
        ),
    ];
    for (from, to, at, message) in cases {
        let bad = text.replacen(from, to, 1);
        assert_ne!(bad, text, "{from} is in fig2.toml");
        let err = error_at(&bad, "fig2.toml", at, message);
        assert!(
            err.contains(&format!(
                "\n    {}",
                bad.lines()
                    .nth(
                        at.split(':')
                            .next()
                            .and_then(|l| l.parse::<usize>().ok())
                            .unwrap_or(1)
                            - 1
                    )
                    .unwrap_or("")
            )),
            "{err}"
        );
    }
}

/// Parses `bad` (named `origin`), which must fail at `at` (line:col) with `message`; the error.
fn error_at(bad: &str, origin: &str, at: &str, message: &str) -> String {
    let err = sitl::Scenario::parse(bad, origin)
        .expect_err(message)
        .to_string();
    assert!(
        err.starts_with(&format!("bad scenario {origin}:{at}: error: ")) && err.contains(message),
        "want {at} {message}, got\n{err}"
    );
    err
}

#[test]
fn a_scenario_that_is_not_utf8_names_the_byte() {
    let dir = std::env::temp_dir().join(format!("sitl-utf8-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let path = dir.join("bad.toml");
    std::fs::write(&path, b"[vehicle]\nspeed_mps = 1.0 # caf\xe9\n").expect("write");
    let err = sitl::Scenario::load(&path)
        .expect_err("not UTF-8")
        .to_string();
    let _ = std::fs::remove_dir_all(&dir);
    assert!(
        err.contains("bad.toml:2:22: error: invalid UTF-8 (byte 0xe9)"),
        "{err}"
    );
}

/// Every leaf value of every shipped scenario given the wrong type in turn: the error shows that key's line.
#[test]
fn a_wrong_type_anywhere_in_a_scenario_is_reported_on_its_own_line() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios");
    let mut checked = 0;
    for entry in std::fs::read_dir(&dir).expect("scenarios dir") {
        let path = entry.expect("entry").path();
        let text = std::fs::read_to_string(&path).expect("scenario");
        let base: toml_edit::DocumentMut = text.parse().expect("parses");
        for (table, key) in leaves(&base) {
            let mut doc = base.clone();
            let old = doc[table.as_str()][key.as_str()].as_value().cloned();
            let new = if old.is_some_and(|v| v.is_str()) {
                "7"
            } else {
                "\"x\""
            };
            doc[table.as_str()][key.as_str()] = toml_edit::Item::Value(new.parse().expect("value"));
            let err = sitl::Scenario::parse(&doc.to_string(), "s.toml")
                .err()
                .unwrap_or_else(|| panic!("{table}.{key} = {new}: accepted"))
                .to_string();
            assert!(
                err.lines()
                    .nth(1)
                    .is_some_and(|l| l.contains(&format!("{key} = {new}"))),
                "{}: {table}.{key} = {new}: the error shows another line\n{err}",
                path.display()
            );
            checked += 1;
        }
    }
    assert!(checked >= 20, "only {checked} keys");
}

/// (table, key) of the scalar values of the plain tables.
fn leaves(doc: &toml_edit::DocumentMut) -> Vec<(String, String)> {
    let mut out = Vec::new();
    for (t, item) in doc.as_table().iter() {
        if let toml_edit::Item::Table(table) = item {
            for (k, v) in table.iter() {
                if v.as_value()
                    .is_some_and(|v| !v.is_array() && !v.is_inline_table())
                {
                    out.push((t.to_string(), k.to_string()));
                }
            }
        }
    }
    out
}

/// `[autopilot]` and `[home]` values out of range, or unknown, are reported at their line:col.
#[test]
fn bad_autopilot_and_home_values_are_reported_at_line_and_column() {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/ardupilot-rover.toml");
    let text = std::fs::read_to_string(&path).expect("ardupilot-rover.toml");
    let line_of = |needle: &str| {
        text.lines()
            .position(|l| l.starts_with(needle))
            .map(|i| i + 1)
            .unwrap_or_else(|| panic!("{needle} is in ardupilot-rover.toml"))
    };
    let (home, profile) = (line_of("lat = "), line_of("profile = "));
    // (shipped text, replacement, expected line:col, part of the message)
    let cases = [
        (
            "profile = \"ardupilot\"",
            "profile = \"betaflight\"",
            format!("{profile}:11"),
            "unknown variant `betaflight`",
        ),
        (
            "profile = \"ardupilot\"",
            "profile = \"ardupilot\"\ncamera = \"gopro\"",
            format!("{}:10", profile + 1),
            "unknown variant `gopro`",
        ),
        (
            "profile = \"ardupilot\"",
            "profile = \"ardupilot\"\nready_after_s = -1.0",
            format!("{}:17", profile + 1),
            "autopilot.ready_after_s: must be in [0, 86400] seconds",
        ),
        (
            "profile = \"ardupilot\"",
            "profile = \"ardupilot\"\ngps_fix = 3.0",
            format!("{}:1", profile + 1),
            "unknown field `gps_fix`",
        ),
        (
            "lat = 43.5616",
            "lat = 143.5616",
            format!("{home}:7"),
            "home.lat: must be in [-90, 90]",
        ),
    ];
    for (from, to, at, message) in cases {
        let bad = text.replacen(from, to, 1);
        assert_ne!(bad, text, "{from} is in ardupilot-rover.toml");
        error_at(&bad, "ap.toml", &at, message);
    }
}
