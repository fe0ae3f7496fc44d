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
