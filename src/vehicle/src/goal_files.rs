//! Goal list files: QGroundControl `.plan` (JSON) and `.waypoints` (`QGC WPL 110`, tab-separated). Errors name
//! the place: `file:line:col` for text, the JSON path (e.g. `mission.items[2].params[4]`) for `.plan`.

use std::path::Path;

use serde_json::Value;

use super::geo::Home;
use super::items::MissionItem;

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{place}: {message}")]
pub struct FileError {
    /// `file:line:col`, or `file: json.path`.
    pub place: String,
    pub message: String,
}

/// The items of a goal file and its home position, if it gives one; what of the file was left out, each
/// with its place and why.
#[derive(Debug, Clone, PartialEq)]
pub struct GoalFile {
    pub home: Option<Home>,
    pub items: Vec<MissionItem>,
    pub skipped: Vec<FileError>,
}

/// Reads a `.plan` or `.waypoints` file, chosen by extension (else by content).
pub fn load(path: &Path) -> Result<GoalFile, FileError> {
    let name = path.display().to_string();
    let text = srctext::read(path).map_err(|e| match e {
        srctext::ReadError::Utf8(at) => FileError {
            place: format!("{}:{}:{}", at.file, at.line, at.col),
            message: at.message,
        },
        srctext::ReadError::Io { path, source } => FileError {
            place: path,
            message: source.to_string(),
        },
    })?;
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
    if ext == "plan" || (ext != "waypoints" && text.trim_start().starts_with('{')) {
        parse_plan(&text, &name)
    } else {
        parse_waypoints(&text, &name)
    }
}

/// Why a home position cannot be a place, if it cannot.
fn absurd_home(h: &Home) -> Option<&'static str> {
    let ok =
        (-90.0..=90.0).contains(&h.lat) && (-180.0..=180.0).contains(&h.lon) && h.alt.is_finite();
    (!ok)
        .then_some("home: latitude must be in [-90, 90], longitude in [-180, 180], altitude finite")
}

fn at_path(name: &str, path: &str, message: impl Into<String>) -> FileError {
    FileError {
        place: format!("{name}: {path}"),
        message: message.into(),
    }
}

fn field<'a>(obj: &'a Value, key: &str, name: &str, path: &str) -> Result<&'a Value, FileError> {
    obj.get(key)
        .ok_or_else(|| at_path(name, path, format!("missing key `{key}`")))
}

/// QGroundControl `.plan`: `mission.items[]` of `SimpleItem`s; `mission.plannedHomePosition` = home.
pub fn parse_plan(text: &str, name: &str) -> Result<GoalFile, FileError> {
    let root: Value = serde_json::from_str(text).map_err(|e| FileError {
        place: format!("{name}:{}:{}", e.line(), e.column()),
        message: e.to_string(),
    })?;
    if !root.is_object() {
        return Err(at_path(name, "$", "expected a JSON object"));
    }
    match root.get("fileType").and_then(Value::as_str) {
        Some("Plan") => {}
        Some(other) => {
            return Err(at_path(
                name,
                "fileType",
                format!("expected \"Plan\", found \"{other}\""),
            ))
        }
        None => {
            return Err(at_path(
                name,
                "fileType",
                "missing (not a QGroundControl plan)",
            ))
        }
    }
    let mission = field(&root, "mission", name, "$")?;
    let home = match mission.get("plannedHomePosition") {
        None | Some(Value::Null) => None,
        Some(Value::Array(a)) if a.len() >= 2 => {
            let num = |i: usize| {
                a[i].as_f64().ok_or_else(|| {
                    at_path(
                        name,
                        &format!("mission.plannedHomePosition[{i}]"),
                        "expected a number",
                    )
                })
            };
            let home = Home {
                lat: num(0)?,
                lon: num(1)?,
                alt: if a.len() > 2 { num(2)? } else { 0.0 },
            };
            if let Some(why) = absurd_home(&home) {
                return Err(at_path(name, "mission.plannedHomePosition", why));
            }
            Some(home)
        }
        Some(_) => {
            return Err(at_path(
                name,
                "mission.plannedHomePosition",
                "expected [lat, lon, alt]",
            ))
        }
    };
    let items = field(mission, "items", name, "mission")?
        .as_array()
        .ok_or_else(|| at_path(name, "mission.items", "expected an array"))?;
    let mut out = Vec::with_capacity(items.len());
    let mut skipped = Vec::new();
    for (i, it) in items.iter().enumerate() {
        let p = format!("mission.items[{i}]");
        match it.get("type").and_then(Value::as_str) {
            Some("SimpleItem") => out.push(simple_item(it, name, &p)?),
            Some("ComplexItem") => complex_item(it, name, &p, &mut out, &mut skipped)?,
            Some(other) => skipped.push(at_path(
                name,
                &format!("{p}.type"),
                format!("\"{other}\" items are not goals: skipped"),
            )),
            None => return Err(at_path(name, &format!("{p}.type"), "missing")),
        }
    }
    Ok(GoalFile {
        home,
        items: out,
        skipped,
    })
}

/// A QGroundControl `SimpleItem` at JSON path `p`.
fn simple_item(it: &Value, name: &str, p: &str) -> Result<MissionItem, FileError> {
    let command = field(it, "command", name, p)?
        .as_u64()
        .filter(|c| *c <= u64::from(u16::MAX))
        .ok_or_else(|| at_path(name, &format!("{p}.command"), "expected a MAV_CMD number"))?;
    let frame = field(it, "frame", name, p)?
        .as_u64()
        .filter(|f| *f <= 255)
        .ok_or_else(|| at_path(name, &format!("{p}.frame"), "expected a MAV_FRAME number"))?;
    let params = field(it, "params", name, p)?
        .as_array()
        .filter(|a| a.len() == 7)
        .ok_or_else(|| {
            at_path(
                name,
                &format!("{p}.params"),
                "expected an array of 7 numbers",
            )
        })?;
    let mut v = [0f64; 7];
    for (k, x) in params.iter().enumerate() {
        // QGroundControl writes NaN as null.
        v[k] = match x {
            Value::Null => f64::NAN,
            other => other.as_f64().ok_or_else(|| {
                at_path(
                    name,
                    &format!("{p}.params[{k}]"),
                    "expected a number or null",
                )
            })?,
        };
    }
    let autocontinue = match it.get("autoContinue") {
        None => true,
        Some(Value::Bool(b)) => *b,
        Some(_) => {
            return Err(at_path(
                name,
                &format!("{p}.autoContinue"),
                "expected true or false",
            ))
        }
    };
    Ok(MissionItem {
        command: command as u16,
        frame: frame as u8,
        params: [v[0] as f32, v[1] as f32, v[2] as f32, v[3] as f32],
        x: if v[4].is_nan() { 0.0 } else { v[4] },
        y: if v[5].is_nan() { 0.0 } else { v[5] },
        z: v[6] as f32,
        autocontinue,
    })
}

/// A QGroundControl `ComplexItem` (survey, corridor scan, structure scan) at JSON path `p`: the mission
/// items QGroundControl generated for it (`TransectStyleComplexItem.Items`: the transects' waypoints and
/// the camera trigger distance, DO_SET_CAM_TRIGG_DIST), which become picture goals along the transects in
/// their order (the rover domains have no survey task; docs/goal-items.md). Without generated items it is
/// skipped with why.
fn complex_item(
    it: &Value,
    name: &str,
    p: &str,
    out: &mut Vec<MissionItem>,
    skipped: &mut Vec<FileError>,
) -> Result<(), FileError> {
    let kind = it
        .get("complexItemType")
        .and_then(Value::as_str)
        .unwrap_or("?");
    let Some(generated) = it
        .get("TransectStyleComplexItem")
        .and_then(|t| t.get("Items"))
        .and_then(Value::as_array)
    else {
        skipped.push(at_path(
            name,
            p,
            format!("\"{kind}\" complex item without generated items (TransectStyleComplexItem.Items): skipped"),
        ));
        return Ok(());
    };
    for (k, g) in generated.iter().enumerate() {
        let q = format!("{p}.TransectStyleComplexItem.Items[{k}]");
        out.push(simple_item(g, name, &q)?);
    }
    Ok(())
}

/// `.waypoints`: `QGC WPL 110`, then INDEX CURRENT FRAME COMMAND P1 P2 P3 P4 LAT LON ALT AUTOCONTINUE per
/// line; row 0 is the home position (Mission Planner's convention), not a goal.
pub fn parse_waypoints(text: &str, name: &str) -> Result<GoalFile, FileError> {
    let mut lines = text.lines().enumerate();
    let at = |line: usize, col: usize, message: String| FileError {
        place: format!("{name}:{}:{}", line + 1, col),
        message,
    };
    match lines.next() {
        Some((_, l)) if l.trim_start().starts_with("QGC WPL") => {}
        Some((i, l)) => {
            return Err(at(
                i,
                1,
                format!("expected the header `QGC WPL 110`, found `{}`", l.trim()),
            ))
        }
        None => {
            return Err(at(
                0,
                1,
                "empty file: expected the header `QGC WPL 110`".into(),
            ))
        }
    }
    let mut home = None;
    let mut items = Vec::new();
    for (i, line) in lines {
        if line.trim().is_empty() {
            continue;
        }
        // Fields with their 1-based column, split on tabs (or spaces, which some tools write).
        let mut fields = Vec::new();
        let mut start = None;
        for (c, ch) in line
            .char_indices()
            .chain(std::iter::once((line.len(), ' ')))
        {
            match (ch.is_whitespace(), start) {
                (false, None) => start = Some(c),
                (true, Some(s)) => {
                    fields.push((&line[s..c], s + 1));
                    start = None;
                }
                _ => {}
            }
        }
        if fields.len() != 12 {
            return Err(at(
                i,
                1,
                format!("expected 12 tab-separated fields, found {}", fields.len()),
            ));
        }
        let num = |k: usize, what: &str| -> Result<f64, FileError> {
            let (s, col) = fields[k];
            s.parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| at(i, col, format!("{what}: `{s}` is not a number")))
        };
        let int = |k: usize, what: &str, max: f64| -> Result<f64, FileError> {
            let v = num(k, what)?;
            if v < 0.0 || v > max || v.fract() != 0.0 {
                let (s, col) = fields[k];
                return Err(at(
                    i,
                    col,
                    format!("{what}: `{s}` is not an integer in 0..={max}"),
                ));
            }
            Ok(v)
        };
        let index = int(0, "INDEX", 65535.0)?;
        let frame = int(2, "FRAME", 255.0)?;
        let command = int(3, "COMMAND", 65535.0)?;
        let p: Vec<f64> = (4..11)
            .map(|k| num(k, ["P1", "P2", "P3", "P4", "LAT", "LON", "ALT"][k - 4]))
            .collect::<Result<_, _>>()?;
        let autocontinue = int(11, "AUTOCONTINUE", 1.0)? == 1.0;
        if index == 0.0 {
            let h = Home {
                lat: p[4],
                lon: p[5],
                alt: p[6],
            };
            if let Some(why) = absurd_home(&h) {
                return Err(at(i, fields[8].1, why.into()));
            }
            home = Some(h);
            continue;
        }
        items.push(MissionItem {
            command: command as u16,
            frame: frame as u8,
            params: [p[0] as f32, p[1] as f32, p[2] as f32, p[3] as f32],
            x: p[4],
            y: p[5],
            z: p[6] as f32,
            autocontinue,
        });
    }
    Ok(GoalFile {
        home,
        items,
        skipped: Vec::new(),
    })
}
