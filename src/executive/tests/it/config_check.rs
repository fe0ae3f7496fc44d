//! Vehicle configurations checked against their domain: every shipped config passes against the domain its
//! header names (and each problem of that domain), and each kind of mismatch is reported with its config key,
//! the key's line and the domain declaration's `file:line` — all mismatches at once.

use std::path::{Path, PathBuf};

use mavtempo_executive::config_check::{check, ConfigIssue, HomeSource, IssueKind, Severity};
use mavtempo_temporal::lang::{load_domain, load_problem, parse_domain};
use mavtempo_temporal::model::{Domain, Problem};
use mavtempo_vehicle::config::VehicleConfig;

fn root() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

/// The domain file a config's header comment names (`domains/<d>/<d>.ixt`).
fn header_domain(text: &str) -> Option<String> {
    let header: String = text
        .lines()
        .take_while(|l| l.starts_with('#'))
        .collect::<Vec<_>>()
        .join("\n");
    let start = header.find("domains/")?;
    let end = start + header[start..].find(".ixt")? + 4;
    Some(header[start..end].to_string())
}

#[test]
fn every_shipped_config_fits_the_domain_its_header_names() {
    let mut configs: Vec<PathBuf> = std::fs::read_dir(root().join("config"))
        .expect("config/")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    configs.sort();
    assert!(configs.len() >= 5, "{configs:?}");
    for path in configs {
        let text = std::fs::read_to_string(&path).expect("readable");
        let domain_file = header_domain(&text)
            .unwrap_or_else(|| panic!("{}: the header names no domain", path.display()));
        let domain = load_domain(&root().join(&domain_file)).unwrap_or_else(|e| panic!("{e}"));
        let cfg = VehicleConfig::load(&path).unwrap_or_else(|e| panic!("{e}"));
        let show = |issues: Vec<ConfigIssue>| {
            issues
                .iter()
                .map(|i| i.to_string())
                .collect::<Vec<_>>()
                .join("\n")
        };
        check(&cfg, &domain, None).unwrap_or_else(|i| panic!("{}", show(i)));
        let problems = root().join(Path::new(&domain_file).with_file_name("problems"));
        for p in std::fs::read_dir(&problems).expect("problems/").flatten() {
            let problem = load_problem(&p.path(), &domain).unwrap_or_else(|e| panic!("{e}"));
            let checked = check(&cfg, &domain, Some(&problem)).unwrap_or_else(|i| {
                panic!(
                    "{} with {}:\n{}",
                    path.display(),
                    p.path().display(),
                    show(i)
                )
            });
            assert!(
                checked.warnings.is_empty(),
                "{}: {:?}",
                path.display(),
                checked.warnings
            );
        }
    }
}

const AUV_CONFIG: &str = include_str!(repo!("config/sitl-auv.toml"));

fn auv() -> (Domain, Problem) {
    let d = load_domain(Path::new(repo!("domains/auv/auv.ixt"))).expect("auv");
    let p = load_problem(Path::new(repo!("domains/auv/problems/vents.ixt")), &d).expect("vents");
    (d, p)
}

/// 1-based line of the first line of `text` containing `needle`.
fn line(text: &str, needle: &str) -> usize {
    text.lines()
        .position(|l| l.contains(needle))
        .unwrap_or_else(|| panic!("{needle:?} not in the config"))
        + 1
}

/// `text` with the first `from` of each of `edits` (it must be there) replaced by its `to`.
fn edited(text: &str, edits: &[(&str, &str)]) -> String {
    let mut text = text.to_string();
    for (from, to) in edits {
        assert!(text.contains(from), "{from:?} not in the config");
        text = text.replacen(from, to, 1);
    }
    text
}

/// The issues of the AUV config edited by `edits` (from, to), checked against auv/vents.
fn issues(edits: &[(&str, &str)]) -> (String, Vec<ConfigIssue>) {
    let text = edited(AUV_CONFIG, edits);
    let cfg = VehicleConfig::parse(&text, "auv.toml").unwrap_or_else(|e| panic!("{e}"));
    let (d, p) = auv();
    let found = match check(&cfg, &d, Some(&p)) {
        Ok(c) => c.warnings,
        Err(i) => i,
    };
    (text, found)
}

/// The issues of config/demo-rover.toml edited by `edits` (from, to), checked against the rover domain,
/// which it must not match.
fn rover_issues(edits: &[(&str, &str)]) -> (String, Vec<ConfigIssue>) {
    let shipped = std::fs::read_to_string(root().join("config/demo-rover.toml")).expect("config");
    let text = edited(&shipped, edits);
    let cfg = VehicleConfig::parse(&text, "rover.toml").expect("parses");
    let rover = load_domain(Path::new(repo!("domains/rover/rover.ixt"))).expect("rover");
    let found = check(&cfg, &rover, None).expect_err("mismatch");
    (text, found)
}

fn find<'a>(found: &'a [ConfigIssue], key: &str) -> &'a ConfigIssue {
    found
        .iter()
        .find(|i| i.key == key)
        .unwrap_or_else(|| panic!("no issue at {key}: {found:?}"))
}

/// The issue at `key`: of `kind`, on the config line that holds `at`.
fn issue_at<'a>(
    found: &'a [ConfigIssue],
    text: &str,
    key: &str,
    kind: IssueKind,
    at: &str,
) -> &'a ConfigIssue {
    let issue = find(found, key);
    assert_eq!(issue.kind, kind, "{key}");
    assert_eq!(issue.line, Some(line(text, at)), "{key}");
    issue
}

#[test]
fn the_old_auv_bindings_are_all_reported_at_once() {
    // The shipped AUV config before it was fixed: `move` for the domain's `go`, `area` for survey's `?l`.
    let (text, found) = issues(&[
        ("[actions.go]", "[actions.move]"),
        ("area = \"l\"", "area = \"area\""),
        (
            "[actions.sample]",
            "[actions.recharge]\nkind = \"recharge\"\nuntil_percent = 90.0\n\n[actions.sample]",
        ),
    ]);
    let errors = found
        .iter()
        .filter(|i| i.severity == Severity::Error)
        .count();
    assert_eq!(errors, 4, "{found:#?}");

    let go = find(&found, "actions.go");
    assert_eq!(go.kind, IssueKind::MissingBinding { task: "go".into() });
    assert_eq!(
        go.domain_at.as_deref(),
        Some(repo!("domains/auv/auv.ixt:15"))
    );
    assert_eq!(go.line, None, "a missing binding is written nowhere");

    let mv = find(&found, "actions.move");
    assert!(
        matches!(&mv.kind, IssueKind::UnknownTask { task, known } if task == "move" && known == "go, survey, sample")
    );
    assert_eq!(mv.line, Some(line(&text, "[actions.move]")));
    assert_eq!(mv.file.as_deref(), Some("auv.toml"));

    let area = find(&found, "actions.survey.area");
    assert!(
        matches!(&area.kind, IssueKind::UnknownParameter { task, param, known }
        if task == "survey" && param == "area" && known == "l")
    );
    assert_eq!(area.line, Some(line(&text, "area = \"area\"")));
    assert_eq!(
        area.domain_at.as_deref(),
        Some(repo!("domains/auv/auv.ixt:28"))
    );
    assert_eq!(
        area.to_string(),
        format!(
            "auv.toml:{}: actions.survey.area: task `survey` has no parameter `area` (its parameters: l) \
             (see {})",
            line(&text, "area = \"area\""),
            repo!("domains/auv/auv.ixt:28")
        )
    );

    let recharge = find(&found, "actions.recharge");
    assert!(matches!(&recharge.kind, IssueKind::UnknownTask { task, .. } if task == "recharge"));
}

#[test]
fn a_defaulted_argument_is_reported_at_its_table() {
    // `to` left to its default ("to") on a task whose parameters are not called so.
    let d = parse_domain(
        "d.ixt",
        "domain d;\ntype place;\nattribute AT(): place;\n\ntask go(?a: place, ?b: place) (st, et) {\n    \
         event(AT(): (?a, ?b), et);\n} nonPreemptive\n",
    )
    .expect("domain");
    let text = AUV_CONFIG
        .replace("to = \"to\"\n", "")
        .replace("[actions.survey]", "[actions.ignored]")
        .replace("[actions.sample]", "[actions.ignored2]")
        .replace("location_type = \"location\"", "location_type = \"place\"")
        .replace("AUV_AT", "AT");
    let cfg = VehicleConfig::parse(&text, "d.toml").expect("parses");
    let found = check(&cfg, &d, None).expect_err("mismatch");
    let to = find(&found, "actions.go.to");
    assert!(
        matches!(&to.kind, IssueKind::UnknownParameter { param, known, .. } if param == "to" && known == "a, b")
    );
    assert_eq!(to.line, Some(line(&text, "[actions.go]")));
    assert_eq!(to.domain_at.as_deref(), Some("d.ixt:5"));
}

#[test]
fn arguments_of_the_wrong_type_are_reported() {
    // move_ptu(?from, ?to: ptu_position) bound as a move; recharge_battery() given a level argument.
    let (text, found) = rover_issues(&[
        (
            "[actions.move_ptu]\nkind = \"timed\"\nduration_ms = 3000",
            "[actions.move_ptu]\nkind = \"move\"",
        ),
        (
            "until_percent = 100.0",
            "until_percent = 100.0\nlevel_arg = \"level\"",
        ),
        (
            "[actions.take_picture]\nkind = \"take_picture\"",
            "[actions.take_picture]\nkind = \"recharge\"\nuntil_percent = 50.0\nlevel_arg = \"l\"",
        ),
        ("timeout_ms = 30000\n", ""),
    ]);
    let ptu = issue_at(
        &found,
        &text,
        "actions.move_ptu.to",
        IssueKind::WrongParameterType {
            task: "move_ptu".into(),
            param: "to".into(),
            found: "ptu_position".into(),
            expected: "a location (mapping.location_type)".into(),
        },
        "[actions.move_ptu]",
    );
    let domain_text =
        std::fs::read_to_string(repo!("domains/rover/rover.ixt")).expect("rover domain");
    let at = format!(
        "{}:{}",
        repo!("domains/rover/rover.ixt"),
        line(&domain_text, "task move_ptu(")
    );
    assert_eq!(ptu.domain_at.as_deref(), Some(at.as_str()));
    let level = find(&found, "actions.recharge_battery.level_arg");
    assert!(matches!(&level.kind, IssueKind::UnknownParameter { param, .. } if param == "level"));
    assert_eq!(level.line, Some(line(&text, "level_arg = \"level\"")));
    let at = format!(
        "{}:{}",
        repo!("domains/rover/rover.ixt"),
        line(&domain_text, "task recharge_battery(")
    );
    assert_eq!(level.domain_at.as_deref(), Some(at.as_str()));
    // Task parameters are symbolic: none can give a level.
    issue_at(
        &found,
        &text,
        "actions.take_picture.level_arg",
        IssueKind::WrongParameterType {
            task: "take_picture".into(),
            param: "l".into(),
            found: "location".into(),
            expected: "a number".into(),
        },
        "level_arg = \"l\"",
    );
    assert_eq!(found.len(), 3, "{found:#?}");
}

#[test]
fn resources_must_be_reservoirs_of_the_domain() {
    let (text, found) = rover_issues(&[
        ("battery = \"BATTERY\"", "battery = \"CAMERA\""),
        ("storage = \"STORAGE\"", "storage = \"DISK\""),
    ]);
    let battery = issue_at(
        &found,
        &text,
        "resources.battery",
        IssueKind::NotReservoir {
            name: "CAMERA".into(),
        },
        "battery = \"CAMERA\"",
    );
    assert_eq!(
        battery.domain_at.as_deref(),
        Some(repo!("domains/rover/rover.ixt:23"))
    );
    issue_at(
        &found,
        &text,
        "resources.storage",
        IssueKind::UnknownResource {
            name: "DISK".into(),
            known: "STORAGE, BATTERY".into(),
        },
        "storage = \"DISK\"",
    );
}

#[test]
fn mapping_names_are_checked_against_the_domain_and_problem() {
    let (text, found) = issues(&[
        ("position = \"AUV_AT\"", "position = \"AT_ROBOT\""),
        ("home_object = \"surface\"", "home_object = \"base\""),
        (
            "sample = { attribute = \"SAMPLED\" }",
            "sample = { attribute = \"CONNECTED\" }",
        ),
    ]);
    let pos = find(&found, "mapping.position");
    assert!(matches!(&pos.kind, IssueKind::UnknownAttribute { name, .. } if name == "AT_ROBOT"));
    assert_eq!(pos.line, Some(line(&text, "position = \"AT_ROBOT\"")));
    issue_at(
        &found,
        &text,
        "mapping.home_object",
        IssueKind::UnknownObject {
            name: "base".into(),
        },
        "home_object = \"base\"",
    );
    // The key inside an inline table has its own line too.
    let sample = find(&found, "mapping.goals.sample.attribute");
    assert!(matches!(&sample.kind, IssueKind::WrongAttribute { name, .. } if name == "CONNECTED"));
    assert_eq!(sample.line, Some(line(&text, "attribute = \"CONNECTED\"")));
    assert_eq!(
        sample.domain_at.as_deref(),
        Some(repo!("domains/auv/auv.ixt:11"))
    );
    assert_eq!(found.len(), 3, "{found:#?}");

    // A position that is a goal-shaped attribute; a location type that is no object type.
    let (_, found) = issues(&[("position = \"AUV_AT\"", "position = \"SAMPLED\"")]);
    let pos = find(&found, "mapping.position");
    assert!(matches!(&pos.kind, IssueKind::WrongAttribute { name, .. } if name == "SAMPLED"));
    assert_eq!(
        pos.domain_at.as_deref(),
        Some(repo!("domains/auv/auv.ixt:13"))
    );
    let (_, found) = issues(&[("location_type = \"location\"", "location_type = \"bool\"")]);
    let lt = find(&found, "mapping.location_type");
    assert_eq!(
        lt.kind,
        IssueKind::NotObjectType {
            name: "bool".into()
        }
    );
    let (_, found) = issues(&[("location_type = \"location\"", "location_type = \"place\"")]);
    let lt = find(&found, "mapping.location_type");
    assert!(
        matches!(&lt.kind, IssueKind::UnknownType { name, known } if name == "place" && known == "location")
    );
    // Reported once, not again at every key that needs it.
    assert_eq!(found.len(), 1, "{found:#?}");
}

#[test]
fn keys_that_others_need_are_reported_missing() {
    let (_, found) = issues(&[
        ("location_type = \"location\"\n", ""),
        ("home_object = \"surface\"", "# no home object"),
    ]);
    let missing: Vec<(&str, &IssueKind)> = found
        .iter()
        .filter(|i| matches!(i.kind, IssueKind::MissingKey { .. }))
        .map(|i| (i.key.as_str(), &i.kind))
        .collect();
    let needed_by = |key: &str| IssueKind::MissingKey {
        needed_by: key.into(),
    };
    assert!(missing.contains(&("mapping.location_type", &needed_by("actions.go.to"))));
    assert!(missing.contains(&("mapping.location_type", &needed_by("mapping.position"))));
    assert!(missing.contains(&(
        "mapping.home_object",
        &needed_by("mapping.goals.return_home")
    )));
}

#[test]
fn home_comes_from_the_problem_with_a_warning_when_the_config_disagrees() {
    // The old AUV home, off Marseille, 11,000 km from the vents problem's.
    let mut text = AUV_CONFIG.replace("lat = 45.95", "lat = 43.2965");
    text = text.replace("lon = -130.01", "lon = 5.3698");
    let cfg = VehicleConfig::parse(&text, "auv.toml").expect("parses");
    let (d, p) = auv();
    let checked = check(&cfg, &d, Some(&p)).expect("a warning only");
    assert_eq!(checked.home_from, HomeSource::Problem);
    assert_eq!((checked.home.lat, checked.home.lon), (45.95, -130.01));
    // The vehicle layer is given the same home.
    assert_eq!(checked.vehicle.home, checked.home);
    let [w] = &checked.warnings[..] else {
        panic!("{:?}", checked.warnings)
    };
    assert_eq!(w.severity, Severity::Warning);
    assert_eq!(w.key, "home");
    assert_eq!(w.line, Some(line(&text, "[home]")));
    assert!(matches!(w.kind, IssueKind::HomeDiffers { distance_m, .. } if distance_m > 1e6));
    assert!(w.to_string().contains("warning: home:"), "{w}");
    // A metre apart is the same home.
    let near = AUV_CONFIG.replace("lat = 45.95 ", "lat = 45.95001 ");
    let cfg = VehicleConfig::parse(&near, "auv.toml").expect("parses");
    let checked = check(&cfg, &d, Some(&p)).expect("ok");
    assert!(checked.warnings.is_empty(), "{:?}", checked.warnings);
    // Without a problem home, the config's.
    let checked = check(&cfg, &d, None).expect("ok");
    assert_eq!(checked.home_from, HomeSource::Config);
    assert_eq!(checked.home, cfg.home);
}

#[test]
fn domain_declarations_keep_their_lines() {
    let (d, _) = auv();
    assert_eq!(d.source.as_deref(), Some(repo!("domains/auv/auv.ixt")));
    let line_of = |name: &str| d.tasks.iter().find(|t| t.name == name).and_then(|t| t.line);
    assert_eq!(
        (line_of("go"), line_of("survey"), line_of("sample")),
        (Some(15), Some(28), Some(35))
    );
    let attr = d.attr_id("SURVEYED").map(|a| d.attr(a).line);
    assert_eq!(attr, Some(Some(12)));
    let t = d.type_id("location").map(|t| d.ty(t).line);
    assert_eq!(t, Some(Some(8)));
    let rover = load_domain(Path::new(repo!("domains/rover/rover.ixt"))).expect("rover");
    let r = rover.resource_id("BATTERY").map(|r| rover.resource(r).line);
    let text = std::fs::read_to_string(repo!("domains/rover/rover.ixt")).expect("rover domain");
    assert_eq!(r, Some(Some(line(&text, "resource BATTERY:"))));
}

#[test]
fn observed_state_names_are_checked_against_the_domain() {
    let text = include_str!(repo!("config/ardupilot-rover.toml"));
    let d = load_domain(Path::new(repo!("domains/rover/rover.ixt"))).expect("rover");
    let with = |from: &str, to: &str| {
        let text = edited(text, &[(from, to)]);
        let cfg = VehicleConfig::parse(&text, "rover.toml").unwrap_or_else(|e| panic!("{e}"));
        let found = check(&cfg, &d, None).err().unwrap_or_default();
        (text, found)
    };
    let shipped = "moving = { attribute = \"ROBOT_STATUS\", yes = \"MOVING\", no = \"STILL\" }";
    let (edited, found) = with(
        shipped,
        "moving = { attribute = \"ROBOT_STATE\", yes = \"MOVING\", no = \"STILL\" }",
    );
    let issue = find(&found, "state.moving.attribute");
    assert!(
        matches!(&issue.kind, IssueKind::UnknownAttribute { name, .. } if name == "ROBOT_STATE")
    );
    assert_eq!(issue.line, Some(line(&edited, "ROBOT_STATE")));
    // A value that is not of the attribute's type, with the values it has.
    let (_, found) = with(
        shipped,
        "moving = { attribute = \"ROBOT_STATUS\", yes = \"DRIVING\", no = \"STILL\" }",
    );
    let issue = find(&found, "state.moving");
    assert!(
        matches!(&issue.kind, IssueKind::UnknownValue { value, known, .. } if value == "DRIVING" && known == "STILL, MOVING"),
        "{issue}"
    );
    // An attribute with parameters cannot be an observed state.
    let (_, found) = with(
        shipped,
        "moving = { attribute = \"PICTURE\", yes = \"true\", no = \"false\" }",
    );
    assert!(matches!(
        &find(&found, "state.moving.attribute").kind,
        IssueKind::WrongAttribute { .. }
    ));
    // A mode that is not a key of [modes] is refused at parse time, at its line.
    let edited = text.replacen(
        shipped,
        &format!("{shipped}\nmode = {{ attribute = \"ROBOT_STATUS\", values = {{ loiter = \"STILL\" }} }}"),
        1,
    );
    let err = VehicleConfig::parse(&edited, "rover.toml")
        .expect_err("loiter is no mode of [modes]")
        .to_string();
    assert!(err.contains("state.mode.values.loiter"), "{err}");
}
