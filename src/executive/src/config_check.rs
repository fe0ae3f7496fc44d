//! A vehicle configuration checked against its domain (and problem) before anything moves: every task of the
//! domain has a binding and every binding a task; a binding's arguments (`to`, `area`, `level_arg`) name
//! parameters of the right type; the `[resources]` and `[mapping]` names exist in the domain with the right
//! shape; home comes from one place (the problem's `home` when it has one, else the config's `[home]`).
//! All problems are reported at once, each with its config key (and line) and the domain declaration
//! concerned (`file:line`).
//!
//! This is where the vehicle's vocabulary meets the model's: the result carries the executive's
//! [`DomainMapping`], resolved to ids.

use std::fmt;

use crate::mapping::{DomainMapping, GoalShape, GoalTarget};
use mavtempo_temporal::model::{AttrId, Domain, Problem, ResourceKind, TypeId, TypeKind};
use mavtempo_vehicle::config::{Binding, ConfigSource, GoalMapping, Mapping, VehicleConfig};
use mavtempo_vehicle::geo::Home;
use mavtempo_vehicle::GoalKind;

/// Homes further apart than this (horizontally) are reported: one of them is probably wrong.
pub const HOME_TOLERANCE_M: f64 = 5.0;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Severity {
    Error,
    /// Reported, but the configuration can be used.
    Warning,
}

/// What is wrong.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum IssueKind {
    #[error("task `{task}` has no binding (a task the autopilot has no counterpart for is bound as `kind = \"timed\"`)")]
    MissingBinding { task: String },
    #[error("the domain has no task `{task}` (its tasks: {known})")]
    UnknownTask { task: String, known: String },
    #[error("task `{task}` has no parameter `{param}` (its parameters: {known})")]
    UnknownParameter {
        task: String,
        param: String,
        known: String,
    },
    #[error("parameter `{param}` of task `{task}` is a {found}; {expected} is needed here")]
    WrongParameterType {
        task: String,
        param: String,
        found: String,
        expected: String,
    },
    #[error("the domain has no resource `{name}` (its resources: {known})")]
    UnknownResource { name: String, known: String },
    #[error("resource `{name}` is unary; a level is reported on a reservoir")]
    NotReservoir { name: String },
    #[error("the domain has no attribute `{name}` (its attributes: {known})")]
    UnknownAttribute { name: String, known: String },
    #[error("attribute `{name}` cannot be used here: {reason}")]
    WrongAttribute { name: String, reason: String },
    #[error("the domain has no type `{name}` (its types: {known})")]
    UnknownType { name: String, known: String },
    #[error(
        "type `{name}` is an enumeration; located objects need an object type (`type {name};`)"
    )]
    NotObjectType { name: String },
    #[error("`{value}` is not a value of attribute `{attribute}` (its values: {known})")]
    UnknownValue {
        attribute: String,
        value: String,
        known: String,
    },
    #[error("the problem has no object `{name}`")]
    UnknownObject { name: String },
    #[error("object `{name}` is a {found}, not a {expected}")]
    WrongObjectType {
        name: String,
        found: String,
        expected: String,
    },
    #[error("missing: {needed_by} needs it")]
    MissingKey { needed_by: String },
    #[error("the config's home ({config_lat}, {config_lon}) is {distance_m:.0} m from the problem's ({problem_lat}, {problem_lon}); the problem's is used")]
    HomeDiffers {
        config_lat: f64,
        config_lon: f64,
        problem_lat: f64,
        problem_lon: f64,
        distance_m: f64,
    },
}

/// One problem found: the config key concerned, where it is written, the domain declaration concerned.
#[derive(Debug, Clone, PartialEq)]
pub struct ConfigIssue {
    pub severity: Severity,
    /// Key path in the configuration: `actions.survey.area`, `mapping.position`, `home`.
    pub key: String,
    /// The configuration's file name, when known.
    pub file: Option<String>,
    /// The key's line in the configuration (or the closest written key above it), when known.
    pub line: Option<usize>,
    /// `file:line` of the domain (or problem) declaration concerned, e.g. `domains/auv/auv.ixt:28`.
    pub domain_at: Option<String>,
    pub kind: IssueKind,
}

impl fmt::Display for ConfigIssue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match (&self.file, self.line) {
            (Some(file), Some(line)) => write!(f, "{file}:{line}: ")?,
            (Some(file), None) => write!(f, "{file}: ")?,
            _ => {}
        }
        if self.severity == Severity::Warning {
            f.write_str("warning: ")?;
        }
        write!(f, "{}: {}", self.key, self.kind)?;
        if let Some(at) = &self.domain_at {
            write!(f, " (see {at})")?;
        }
        Ok(())
    }
}

impl std::error::Error for ConfigIssue {}

/// Where the effective home comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HomeSource {
    Problem,
    Config,
}

/// A configuration that matches its domain.
#[derive(Debug, Clone)]
pub struct CheckedConfig {
    /// The configuration, with `home` replaced by the effective home: what the vehicle layer is given.
    pub vehicle: VehicleConfig,
    /// The effective home: the origin of the problem's local frame and of every lat/lon conversion.
    pub home: Home,
    pub home_from: HomeSource,
    /// The executive's mapping. `home_object` is only resolved when the problem is given.
    pub mapping: DomainMapping,
    pub warnings: Vec<ConfigIssue>,
}

/// Collects issues with the config's source at hand.
struct Issues<'a> {
    source: Option<&'a ConfigSource>,
    domain: &'a Domain,
    found: Vec<ConfigIssue>,
}

impl Issues<'_> {
    fn push(
        &mut self,
        severity: Severity,
        key: String,
        domain_line: Option<usize>,
        kind: IssueKind,
    ) {
        let line = self.source.and_then(|s| s.line_of(&key));
        self.found.push(ConfigIssue {
            severity,
            file: self.source.map(|s| s.origin.clone()),
            line,
            domain_at: self.domain.location(domain_line),
            key,
            kind,
        });
    }

    fn error(&mut self, key: String, domain_line: Option<usize>, kind: IssueKind) {
        self.push(Severity::Error, key, domain_line, kind);
    }

    /// `found` when the domain declares the name; else the `unknown` error at `key` (its line is the config's:
    /// the name is not in the domain).
    fn declared<I>(
        &mut self,
        key: &str,
        found: Option<I>,
        unknown: impl FnOnce(&Domain) -> IssueKind,
    ) -> Option<I> {
        if found.is_none() {
            self.error(key.into(), None, unknown(self.domain));
        }
        found
    }

    /// The domain's attribute `name`, reported at `key` when it has none.
    fn attribute(&mut self, key: &str, name: &str) -> Option<AttrId> {
        let found = self.domain.attr_id(name);
        self.declared(key, found, |d| IssueKind::UnknownAttribute {
            name: name.into(),
            known: names(d.attrs.iter().map(|a| a.name.as_str())),
        })
    }
}

/// The names of the `items` that `keep` accepts, for a message's "(its …: a, b)".
fn names_where<'a, T>(
    items: &'a [T],
    keep: impl Fn(&T) -> bool,
    name: impl Fn(&'a T) -> &'a String,
) -> String {
    names(items.iter().filter(|i| keep(i)).map(|i| name(i).as_str()))
}

fn names<'a>(it: impl Iterator<Item = &'a str>) -> String {
    let v: Vec<&str> = it.collect();
    if v.is_empty() {
        "none".into()
    } else {
        v.join(", ")
    }
}

/// Checks `cfg` against `domain` (and `problem`, which gives the home and the objects): `Ok` with the
/// effective configuration and the executive's mapping, or every problem found. Warnings (homes that
/// disagree) are logged with `tracing` and returned either way.
pub fn check(
    cfg: &VehicleConfig,
    domain: &Domain,
    problem: Option<&Problem>,
) -> Result<CheckedConfig, Vec<ConfigIssue>> {
    let mut issues = Issues {
        source: cfg.source.as_ref(),
        domain,
        found: Vec::new(),
    };
    let location_type = location_type(&mut issues, &cfg.mapping);
    bindings(&mut issues, cfg, location_type);
    resources(&mut issues, cfg);
    observed_state(&mut issues, cfg);
    let mapping = mapping(&mut issues, &cfg.mapping, location_type, problem);
    let (home, home_from) = effective_home(&mut issues, cfg.home, problem);
    for w in issues
        .found
        .iter()
        .filter(|i| i.severity == Severity::Warning)
    {
        tracing::warn!("{w}");
    }
    if issues.found.iter().any(|i| i.severity == Severity::Error) {
        return Err(issues.found);
    }
    let mut vehicle = cfg.clone();
    vehicle.home = home;
    Ok(CheckedConfig {
        vehicle,
        home,
        home_from,
        mapping,
        warnings: issues.found,
    })
}

/// Resolves a `[mapping]` alone (for callers without a vehicle configuration, e.g. the dispatch
/// experiment's kinematic vehicle). `source` gives lines when the mapping was read from a file.
pub fn resolve_mapping(
    m: &Mapping,
    domain: &Domain,
    problem: Option<&Problem>,
    source: Option<&ConfigSource>,
) -> Result<DomainMapping, Vec<ConfigIssue>> {
    let mut issues = Issues {
        source,
        domain,
        found: Vec::new(),
    };
    let location_type = location_type(&mut issues, m);
    let mapping = mapping(&mut issues, m, location_type, problem);
    if issues.found.is_empty() {
        Ok(mapping)
    } else {
        Err(issues.found)
    }
}

/// `mapping.location_type`: an object type of the domain.
fn location_type(issues: &mut Issues, m: &Mapping) -> Option<TypeId> {
    let name = m.location_type.as_deref()?;
    let d = issues.domain;
    let found = d.type_id(name);
    let t = issues.declared("mapping.location_type", found, |d| IssueKind::UnknownType {
        name: name.into(),
        known: names_where(&d.types, |t| t.kind == TypeKind::Object, |t| &t.name),
    })?;
    if d.ty(t).kind != TypeKind::Object {
        issues.error(
            "mapping.location_type".into(),
            d.ty(t).line,
            IssueKind::NotObjectType { name: name.into() },
        );
        return None;
    }
    Some(t)
}

/// Every task bound, every binding a task, binding arguments naming parameters of the right type.
fn bindings(issues: &mut Issues, cfg: &VehicleConfig, location_type: Option<TypeId>) {
    let d = issues.domain;
    for t in &d.tasks {
        if !cfg.actions.contains_key(&t.name) {
            issues.error(
                format!("actions.{}", t.name),
                t.line,
                IssueKind::MissingBinding {
                    task: t.name.clone(),
                },
            );
        }
    }
    for (name, b) in &cfg.actions {
        let found = d.task_id(name);
        let unknown = |d: &Domain| IssueKind::UnknownTask {
            task: name.clone(),
            known: names(d.tasks.iter().map(|t| t.name.as_str())),
        };
        let Some(tid) = issues.declared(&format!("actions.{name}"), found, unknown) else {
            continue;
        };
        let task = d.task(tid);
        // (key, parameter named, whether a location is needed (else a number)).
        let args: Vec<(&str, &str, bool)> = match b {
            Binding::Move { to, .. } => vec![("to", to, true)],
            Binding::Survey { area, .. } => vec![("area", area, true)],
            Binding::Flight(f) => f
                .location_param()
                .map(|to| vec![("to", to, true)])
                .unwrap_or_default(),
            Binding::Recharge {
                level_arg: Some(level),
                ..
            } => vec![("level_arg", level, false)],
            _ => Vec::new(),
        };
        for (key, param, location) in args {
            let key = format!("actions.{name}.{key}");
            let Some(p) = task.params().iter().find(|p| p.name == param) else {
                issues.error(
                    key,
                    task.line,
                    IssueKind::UnknownParameter {
                        task: name.clone(),
                        param: param.into(),
                        known: names(task.params().iter().map(|p| p.name.as_str())),
                    },
                );
                continue;
            };
            // Task parameters are symbolic: none carries a number in this language.
            let expected = match location_type {
                _ if !location => Some("a number".to_string()),
                Some(lt) if lt == p.ty => None,
                Some(lt) => Some(format!("a {} (mapping.location_type)", d.ty(lt).name)),
                // An unknown location type is reported once, at mapping.location_type.
                None if cfg.mapping.location_type.is_some() => None,
                None => {
                    issues.error(
                        "mapping.location_type".into(),
                        None,
                        IssueKind::MissingKey { needed_by: key },
                    );
                    continue;
                }
            };
            if let Some(expected) = expected {
                issues.error(
                    key,
                    task.line,
                    IssueKind::WrongParameterType {
                        task: name.clone(),
                        param: param.into(),
                        found: d.ty(p.ty).name.clone(),
                        expected,
                    },
                );
            }
        }
    }
}

/// `[resources]`: reservoirs of the domain.
fn resources(issues: &mut Issues, cfg: &VehicleConfig) {
    let d = issues.domain;
    let named = [
        ("resources.battery", &cfg.resources.battery),
        ("resources.storage", &cfg.resources.storage),
    ];
    for (key, name) in named {
        let Some(name) = name else { continue };
        let found = d.resource_id(name);
        let reservoirs = |d: &Domain| IssueKind::UnknownResource {
            name: name.clone(),
            known: names_where(
                &d.resources,
                |r| r.kind == ResourceKind::Reservoir,
                |r| &r.name,
            ),
        };
        let Some(r) = issues.declared(key, found, reservoirs) else {
            continue;
        };
        if d.resource(r).kind != ResourceKind::Reservoir {
            issues.error(
                key.into(),
                d.resource(r).line,
                IssueKind::NotReservoir { name: name.clone() },
            );
        }
    }
}

/// `[state]`: each observation sets an attribute without parameters, to constants of its value type.
fn observed_state(issues: &mut Issues, cfg: &VehicleConfig) {
    let d = issues.domain;
    for (key, attribute, values) in cfg.state.named() {
        let Some(attr) = issues.attribute(&format!("{key}.attribute"), attribute) else {
            continue;
        };
        let a = d.attr(attr);
        if !a.params.is_empty() {
            issues.error(
                format!("{key}.attribute"),
                a.line,
                IssueKind::WrongAttribute {
                    name: attribute.into(),
                    reason: "an observed state is an attribute without parameters".into(),
                },
            );
            continue;
        }
        let ty = d.ty(a.value_type);
        for value in values {
            let fits = d.object_id(value).is_some_and(|o| ty.members.contains(&o));
            if !fits {
                issues.error(
                    key.clone(),
                    a.line,
                    IssueKind::UnknownValue {
                        attribute: attribute.into(),
                        value: value.into(),
                        known: names(
                            ty.members
                                .iter()
                                .map(|&o| d.objects[o.index()].name.as_str()),
                        ),
                    },
                );
            }
        }
    }
}

/// `[mapping]`: the position attribute, goal attributes and the home object, resolved.
fn mapping(
    issues: &mut Issues,
    m: &Mapping,
    location_type: Option<TypeId>,
    problem: Option<&Problem>,
) -> DomainMapping {
    let d = issues.domain;
    let mut out = DomainMapping {
        location_type,
        ..DomainMapping::default()
    };
    let type_declared = m.location_type.is_some();
    if let Some(name) = &m.position {
        let key = "mapping.position".to_string();
        match goal_shape(issues, &key, name, location_type, type_declared) {
            Some((attr, GoalShape::ValueIsLocation)) => out.position = Some(attr),
            Some((attr, GoalShape::LocationIsTrue)) => issues.error(
                key,
                d.attr(attr).line,
                IssueKind::WrongAttribute {
                    name: name.clone(),
                    reason: "a position needs no parameters and a value of the location type"
                        .into(),
                },
            ),
            None => {}
        }
    }
    for (kind, GoalMapping { attribute }) in &m.goals {
        let key = format!("mapping.goals.{}.attribute", kind.key());
        let Some((attr, shape)) = goal_shape(issues, &key, attribute, location_type, type_declared)
        else {
            continue;
        };
        if *kind == GoalKind::ReturnHome && shape != GoalShape::ValueIsLocation {
            issues.error(
                key,
                d.attr(attr).line,
                IssueKind::WrongAttribute {
                    name: attribute.clone(),
                    reason: "a return-home goal is a position: no parameters, valued in the location type"
                        .into(),
                },
            );
            continue;
        }
        out.goals.insert(*kind, GoalTarget { attr, shape });
    }
    if m.goals.contains_key(&GoalKind::ReturnHome) && m.home_object.is_none() {
        issues.error(
            "mapping.home_object".into(),
            None,
            IssueKind::MissingKey {
                needed_by: "mapping.goals.return_home".into(),
            },
        );
    }
    if let (Some(name), Some(p)) = (&m.home_object, problem) {
        match p.object_id(name) {
            None => issues.error(
                "mapping.home_object".into(),
                None,
                IssueKind::UnknownObject { name: name.clone() },
            ),
            Some(o) => {
                let ty = p.object(o).map(|ob| ob.ty);
                match (ty, location_type) {
                    (Some(t), Some(lt)) if t != lt => issues.error(
                        "mapping.home_object".into(),
                        None,
                        IssueKind::WrongObjectType {
                            name: name.clone(),
                            found: d.ty(t).name.clone(),
                            expected: d.ty(lt).name.clone(),
                        },
                    ),
                    _ => out.home_object = Some(o),
                }
            }
        }
    }
    out
}

/// The attribute `name` and how a location sits on it: `NAME(): location` or `NAME(?l: location): bool`.
fn goal_shape(
    issues: &mut Issues,
    key: &str,
    name: &str,
    location_type: Option<TypeId>,
    type_declared: bool,
) -> Option<(AttrId, GoalShape)> {
    let d = issues.domain;
    let attr = issues.attribute(key, name)?;
    let Some(lt) = location_type else {
        // Without a location type the shape cannot be told; an unknown one is reported where it is named.
        if !type_declared {
            issues.error(
                "mapping.location_type".into(),
                None,
                IssueKind::MissingKey {
                    needed_by: key.into(),
                },
            );
        }
        return None;
    };
    let a = d.attr(attr);
    match a.params.as_slice() {
        [] if a.value_type == lt => Some((attr, GoalShape::ValueIsLocation)),
        [(_, t)] if *t == lt && a.value_type == Domain::BOOL => {
            Some((attr, GoalShape::LocationIsTrue))
        }
        _ => {
            let lname = &d.ty(lt).name;
            issues.error(
                key.into(),
                a.line,
                IssueKind::WrongAttribute {
                    name: name.into(),
                    reason: format!(
                        "it must be `{name}(): {lname}` or `{name}(?l: {lname}): bool`"
                    ),
                },
            );
            None
        }
    }
}

/// The problem's home when it gives one (a warning when the config's is elsewhere), else the config's.
fn effective_home(
    issues: &mut Issues,
    config: Home,
    problem: Option<&Problem>,
) -> (Home, HomeSource) {
    let Some(g) = problem.and_then(|p| p.home) else {
        return (config, HomeSource::Config);
    };
    let home = Home {
        lat: g.lat,
        lon: g.lon,
        alt: g.alt,
    };
    let distance_m = config
        .to_local(home.lat, home.lon, home.alt)
        .horizontal_distance(&mavtempo_vehicle::Enu::default());
    if distance_m.is_nan() || distance_m > HOME_TOLERANCE_M {
        issues.push(
            Severity::Warning,
            "home".into(),
            None,
            IssueKind::HomeDiffers {
                config_lat: config.lat,
                config_lon: config.lon,
                problem_lat: home.lat,
                problem_lon: home.lon,
                distance_m,
            },
        );
    }
    (home, HomeSource::Problem)
}
