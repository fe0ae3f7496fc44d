//! The shipped SITL rover configuration for tests of the ground-station port.

use mavtempo_vehicle::config::VehicleConfig;

/// `config/sitl-rover.toml` listening for nothing in particular on the vehicle side (`udpin:` port 0), with
/// `extra_link` added to its `[link]` table.
pub fn config(extra_link: &str) -> VehicleConfig {
    let text = std::fs::read_to_string(repo!("config/sitl-rover.toml")).expect("config");
    let text = text.replace(
        "address = \"tcpout:127.0.0.1:5760\"",
        &format!("address = \"udpin:127.0.0.1:0\"\n{extra_link}"),
    );
    VehicleConfig::parse(&text, "sitl-rover.toml (test)").expect("parses")
}
