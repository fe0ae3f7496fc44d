//! Pictures of a mission (seed 1 §5 Figs 5–8): the executed plan over time with its repairs, replannings
//! and goal arrivals, each reservoir's level against its theoretical bounds, the track on a map; one
//! self-contained HTML page holding them, and the live page served while a mission runs.

pub mod data;
pub mod form;
pub mod goal_rows;
pub mod guard;
pub mod html;
pub mod live;
pub mod origin;
pub mod svg;

use std::path::{Path, PathBuf};

use data::{Charts, RunView};

/// Why a report could not be drawn.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    #[error("{0}")]
    Read(#[from] srctext::ReadError),
    /// Malformed JSON, or not a mission report: at its `file:line:col`.
    #[error("{0}")]
    Parse(srctext::Located),
    #[error(transparent)]
    Draw(#[from] svg::DrawError),
    #[error("cannot write {path}: {source}")]
    Write {
        path: String,
        source: std::io::Error,
    },
    /// An in-memory report that does not read back as one (a bug, not an input error).
    #[error("the mission report does not read back: {0}")]
    ReadBack(#[from] serde_json::Error),
}

/// Reads a mission report (`demo`/`run`/`soak --report FILE`).
pub fn read_report(path: &Path) -> Result<RunView, ReportError> {
    let text = srctext::read(path)?;
    parse_report(&path.display().to_string(), &text)
}

/// A mission report from its JSON text; errors at `file:line:col`.
pub fn parse_report(file: &str, text: &str) -> Result<RunView, ReportError> {
    // serde would also read a struct from an array: a report is an object.
    let start = text.len() - text.trim_start().len();
    if !text[start..].starts_with('{') {
        let what =
            "not a mission report: expected a JSON object (`--report FILE` of demo, run or soak)";
        return Err(ReportError::Parse(srctext::locate(file, text, start, what)));
    }
    serde_json::from_str(text).map_err(|e| {
        let offset = offset_of(text, e.line(), e.column());
        // The place is given by `file:line:col`: serde's own "at line L column C" is dropped.
        let full = e.to_string();
        let message = full
            .rfind(" at line ")
            .map_or(full.as_str(), |i| &full[..i]);
        ReportError::Parse(srctext::locate(file, text, offset, message))
    })
}

/// Byte offset of 1-based `line`, `col` (serde_json's column counts bytes).
fn offset_of(text: &str, line: usize, col: usize) -> usize {
    let start: usize = text
        .split_inclusive('\n')
        .take(line.saturating_sub(1))
        .map(str::len)
        .sum();
    start + col.saturating_sub(1)
}

/// The files `mavtempo report` writes: `index.html` (everything), `gantt.svg`, `map.svg` and one
/// `resource-NAME.svg` per reservoir. Returns their paths.
pub fn write_all(dir: &Path, title: &str, c: &Charts) -> Result<Vec<PathBuf>, ReportError> {
    std::fs::create_dir_all(dir).map_err(|source| ReportError::Write {
        path: dir.display().to_string(),
        source,
    })?;
    let mut files = vec![
        ("index.html".to_string(), html::page(title, c)?),
        ("gantt.svg".to_string(), svg::gantt(c, false)?),
        ("map.svg".to_string(), svg::map(c)?),
    ];
    for s in &c.series {
        let name: String = s
            .resource
            .chars()
            .map(|ch| {
                if ch.is_ascii_alphanumeric() {
                    ch.to_ascii_lowercase()
                } else {
                    '_'
                }
            })
            .collect();
        files.push((format!("resource-{name}.svg"), svg::resource(c, s)?));
    }
    let mut written = Vec::new();
    for (name, text) in files {
        let path = dir.join(name);
        std::fs::write(&path, text).map_err(|source| ReportError::Write {
            path: path.display().to_string(),
            source,
        })?;
        written.push(path);
    }
    Ok(written)
}

/// The page of a finished mission report (what `demo --html FILE` writes).
pub fn write_page(path: &Path, title: &str, c: &Charts) -> Result<(), ReportError> {
    let text = html::page(title, c)?;
    std::fs::write(path, text).map_err(|source| ReportError::Write {
        path: path.display().to_string(),
        source,
    })
}

/// The charts of an in-memory report (no file between): through its JSON, as `mavtempo report` reads it.
pub fn charts_of(r: &crate::exec::mission::MissionReport) -> Result<Charts, ReportError> {
    let value = serde_json::to_value(r)?;
    let view: RunView = serde_json::from_value(value)?;
    Ok(Charts::from_report(&view))
}
