//! `mavtempo soak --dispatch earliest,goal-driven,latest`: the same live missions under each policy, side by
//! side (seed 2's experiment on the SITL). `latest` defers the operator's goals too, so it cannot achieve
//! more than `earliest`; goal-driven and earliest see the same goals.

use std::process::Command;

#[test]
fn soak_runs_each_mission_under_each_policy() {
    let out = Command::new(env!("CARGO_BIN_EXE_mavtempo"))
        .args([
            "soak",
            "--missions",
            "2",
            "--seed",
            "5000",
            "--domain",
            "rover",
            "--dispatch",
            "earliest,goal-driven,latest",
            "--json",
        ])
        .output()
        .expect("runs mavtempo");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let rows: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON on stdout");
    let rows = rows.as_array().expect("one summary per policy");
    let policy: Vec<&str> = rows.iter().filter_map(|r| r["policy"].as_str()).collect();
    assert_eq!(policy, ["earliest", "goal-driven:marking", "latest"]);
    let n = |r: &serde_json::Value, k: &str| r[k].as_u64().unwrap_or(u64::MAX);
    for r in rows {
        assert_eq!(n(r, "missions"), 2, "{r}");
        assert_eq!(n(r, "goals"), n(&rows[0], "goals"), "{r}");
        assert!(r["distance_km"].as_f64().is_some_and(|km| km > 0.0), "{r}");
    }
    assert!(
        n(&rows[2], "achieved") <= n(&rows[0], "achieved"),
        "{rows:?}"
    );
}
