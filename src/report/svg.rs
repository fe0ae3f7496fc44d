//! Drawing the charts as SVG with `plotters`: the executed plan over time (seed 1 Figs 6–7), each
//! reservoir's reported level against its bounds (Fig. 8), the track on a local map (Fig. 5).

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::data::{Charts, MarkKind, Series};
use crate::model::Time;

/// Why a chart could not be drawn (plotters' error, as text).
#[derive(Debug, thiserror::Error)]
#[error("drawing the {chart} chart: {reason}")]
pub struct DrawError {
    pub chart: &'static str,
    pub reason: String,
}

type Area<'a> = DrawingArea<SVGBackend<'a>, Shift>;

fn secs(t: Time) -> f64 {
    t as f64 / 1000.0
}

fn font(size: u32) -> TextStyle<'static> {
    TextStyle::from(("sans-serif", size).into_font())
}

/// Runs `draw` on an SVG of `size` pixels, returning its text.
fn svg(
    chart: &'static str,
    size: (u32, u32),
    draw: impl FnOnce(&Area) -> Result<(), Box<dyn std::error::Error>>,
) -> Result<String, DrawError> {
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, size).into_drawing_area();
        let result = root
            .fill(&WHITE)
            .map_err(|e| e.to_string())
            .and_then(|_| draw(&root).map_err(|e| e.to_string()))
            .and_then(|_| root.present().map_err(|e| e.to_string()));
        result.map_err(|reason| DrawError { chart, reason })?;
    }
    Ok(out)
}

fn mark_color(k: MarkKind) -> RGBColor {
    match k {
        MarkKind::Repair => RGBColor(30, 100, 220),
        MarkKind::Replan => RGBColor(140, 40, 180),
        MarkKind::Abort => RGBColor(220, 30, 30),
        MarkKind::GoalArrival => RGBColor(0, 0, 0),
        MarkKind::GoalAchieved => RGBColor(20, 150, 60),
        MarkKind::GoalRejected => RGBColor(200, 90, 0),
    }
}

fn status_color(status: &str) -> RGBColor {
    match status {
        "nominal" => RGBColor(70, 170, 90),
        "failed" => RGBColor(220, 50, 50),
        "interrupted" => RGBColor(240, 150, 30),
        _ => RGBColor(60, 120, 220),
    }
}

/// The end of the time axis: now, or the last planned end, a little past it.
fn x_max(c: &Charts) -> f64 {
    let planned = c.planned.iter().map(|p| p.end_ms).max().unwrap_or(0);
    secs(c.now_ms.max(planned).max(1_000)) * 1.02
}

/// The executed plan: one row per action, a bar from start to report coloured by the report's status,
/// the planned window of its end as a grey box, the plan's future actions (live) in light blue, and the
/// marks (repairs, replannings, aborts, goal arrivals, achievements, rejections) on the time axis.
pub fn gantt(c: &Charts, live: bool) -> Result<String, DrawError> {
    let rows = c.rows();
    let n = rows.len().max(1) as f64;
    let height = 130 + 22 * rows.len() as u32;
    svg("Gantt", (1100, height), |root| {
        let xmax = x_max(c);
        legend(root, height)?;
        let mut chart = ChartBuilder::on(root)
            .margin(10)
            .margin_top(40)
            .margin_bottom(30)
            .x_label_area_size(30)
            .y_label_area_size(230)
            .build_cartesian_2d(0f64..xmax, 0f64..n)?;
        chart
            .configure_mesh()
            .disable_y_mesh()
            .y_labels(0)
            .x_desc("mission time (s)")
            .draw()?;
        let row_y = |a: &str| n - rows.iter().position(|r| r == a).unwrap_or(0) as f64 - 0.5;
        for (i, name) in rows.iter().enumerate() {
            let (px, py) = chart.backend_coord(&(0.0, n - i as f64 - 0.5));
            root.draw(&Text::new(
                name.clone(),
                (px - 6, py),
                font(12).pos(Pos::new(HPos::Right, VPos::Center)),
            ))?;
        }
        let now = secs(c.now_ms);
        chart.draw_series(c.planned.iter().map(|p| {
            let y = row_y(&p.action);
            Rectangle::new(
                [(secs(p.start_ms), y - 0.3), (secs(p.end_ms), y + 0.3)],
                RGBColor(150, 190, 240).mix(0.5).filled(),
            )
        }))?;
        chart.draw_series(c.bars.iter().filter_map(|b| {
            let (lb, ub) = b.planned_end_ms?;
            let y = row_y(&b.action);
            let ub = ub.map_or(xmax, secs).min(xmax);
            Some(Rectangle::new(
                [(secs(lb), y - 0.42), (ub.max(secs(lb)), y + 0.42)],
                RGBColor(120, 120, 120).stroke_width(1),
            ))
        }))?;
        chart.draw_series(c.bars.iter().map(|b| {
            let y = row_y(&b.action);
            let end = b.end_ms.map_or(now, secs);
            Rectangle::new(
                [(secs(b.start_ms), y - 0.3), (end, y + 0.3)],
                status_color(&b.status).filled(),
            )
        }))?;
        for (i, m) in c.marks.iter().enumerate() {
            let x = secs(m.time_ms);
            let color = mark_color(m.kind);
            chart.draw_series(std::iter::once(PathElement::new(
                vec![(x, 0.0), (x, n)],
                color.mix(0.6).stroke_width(1),
            )))?;
            // Labels above the plot, staggered so that close marks stay readable.
            let (px, py) = chart.backend_coord(&(x, n));
            root.draw(&Text::new(
                m.label.clone(),
                (px, py - 4 - 11 * (i % 3) as i32),
                font(10)
                    .color(&color)
                    .pos(Pos::new(HPos::Center, VPos::Bottom)),
            ))?;
        }
        if live {
            chart.draw_series(std::iter::once(PathElement::new(
                vec![(now, 0.0), (now, n)],
                RED.stroke_width(2),
            )))?;
        }
        Ok(())
    })
}

/// The Gantt chart's key, along its bottom edge.
fn legend(root: &Area, height: u32) -> Result<(), Box<dyn std::error::Error>> {
    let y = height as i32 - 14;
    let mut x = 20;
    let bars = [
        ("nominal", status_color("nominal")),
        ("failed", status_color("failed")),
        ("interrupted", status_color("interrupted")),
        ("running", status_color("running")),
    ];
    for (label, color) in bars {
        root.draw(&Rectangle::new(
            [(x, y - 5), (x + 16, y + 5)],
            color.filled(),
        ))?;
        legend_label(root, label, (x + 20, y), font(11))?;
        x += 30 + 7 * label.len() as i32;
    }
    let grey = RGBColor(120, 120, 120);
    root.draw(&Rectangle::new(
        [(x, y - 6), (x + 16, y + 6)],
        grey.stroke_width(1),
    ))?;
    let text = "planned window of the end";
    legend_label(root, text, (x + 20, y), font(11))?;
    x += 40 + 6 * text.len() as i32;
    let marks = [
        ("repair", MarkKind::Repair),
        ("abort", MarkKind::Abort),
        ("replanning", MarkKind::Replan),
        ("goal arrives", MarkKind::GoalArrival),
        ("achieved", MarkKind::GoalAchieved),
        ("rejected", MarkKind::GoalRejected),
    ];
    for (label, kind) in marks {
        let color = mark_color(kind);
        root.draw(&PathElement::new(
            vec![(x + 6, y - 7), (x + 6, y + 7)],
            color.stroke_width(2),
        ))?;
        legend_label(root, label, (x + 12, y), font(11).color(&color))?;
        x += 22 + 7 * label.len() as i32;
    }
    Ok(())
}

/// A key's label in `style`, starting at `at` and centred on its line.
fn legend_label(
    root: &Area,
    label: &str,
    at: (i32, i32),
    style: TextStyle<'_>,
) -> Result<(), Box<dyn std::error::Error>> {
    root.draw(&Text::new(
        label,
        at,
        style.pos(Pos::new(HPos::Left, VPos::Center)),
    ))?;
    Ok(())
}

/// A reservoir's reported level (points) against `[lev_lb, lev_ub]` (the band; each sample holds until
/// the next).
pub fn resource(c: &Charts, s: &Series) -> Result<String, DrawError> {
    svg("resource", (1100, 260), |root| {
        let xmax = x_max(c);
        let end = secs(c.now_ms);
        let values = s
            .bounds
            .iter()
            .flat_map(|b| [b.1, b.2])
            .chain(s.reported.iter().map(|r| r.1))
            .filter(|v| v.is_finite());
        let (lo, hi) = values.fold((0f64, 1f64), |(lo, hi), v| (lo.min(v), hi.max(v)));
        let pad = (hi - lo) * 0.05;
        let mut chart = ChartBuilder::on(root)
            .caption(
                format!("{}: reported level against its bounds", s.resource),
                ("sans-serif", 16),
            )
            .margin(10)
            .x_label_area_size(30)
            .y_label_area_size(50)
            .build_cartesian_2d(0f64..xmax, (lo - pad)..(hi + pad))?;
        chart
            .configure_mesh()
            .x_desc("mission time (s)")
            .y_desc(s.resource.as_str())
            .draw()?;
        let clamp = |v: f64| v.clamp(lo - pad, hi + pad);
        let mut upper = Vec::new();
        let mut lower = Vec::new();
        for (i, b) in s.bounds.iter().enumerate() {
            let until = s.bounds.get(i + 1).map_or(end, |n| secs(n.0));
            upper.extend([(secs(b.0), clamp(b.2)), (until, clamp(b.2))]);
            lower.extend([(secs(b.0), clamp(b.1)), (until, clamp(b.1))]);
        }
        let band: Vec<(f64, f64)> = upper.iter().chain(lower.iter().rev()).copied().collect();
        let blue = RGBColor(60, 120, 220);
        chart
            .draw_series(std::iter::once(Polygon::new(band, blue.mix(0.2).filled())))?
            .label("[lev_lb, lev_ub]")
            .legend(move |(x, y)| {
                Rectangle::new([(x, y - 5), (x + 14, y + 5)], blue.mix(0.3).filled())
            });
        chart.draw_series(LineSeries::new(upper, blue.stroke_width(1)))?;
        chart.draw_series(LineSeries::new(lower, blue.stroke_width(1)))?;
        let pts: Vec<(f64, f64)> = s.reported.iter().map(|r| (secs(r.0), r.1)).collect();
        // A reported level holds until the next report: steps, not slopes.
        let steps = pts.windows(2).flat_map(|w| [w[0], (w[1].0, w[0].1)]);
        let steps: Vec<(f64, f64)> = steps.chain(pts.last().copied()).collect();
        chart.draw_series(LineSeries::new(steps, BLACK.mix(0.5)))?;
        chart
            .draw_series(pts.iter().map(|&p| Circle::new(p, 2, BLACK.filled())))?
            .label("reported")
            .legend(|(x, y)| Circle::new((x + 7, y), 3, BLACK.filled()));
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK.mix(0.3))
            .draw()?;
        Ok(())
    })
}

/// The track (blue, start green) on a local map, east/north metres from home, with the places and the
/// goals that name them.
pub fn map(c: &Charts) -> Result<String, DrawError> {
    let (w, h) = (700u32, 560u32);
    svg("map", (w, h), |root| {
        let xs = c
            .places
            .iter()
            .map(|p| p.east)
            .chain(c.track.iter().map(|p| p.east));
        let ys = c
            .places
            .iter()
            .map(|p| p.north)
            .chain(c.track.iter().map(|p| p.north));
        let span = |it: &mut dyn Iterator<Item = f64>| {
            it.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                (a.min(v), b.max(v))
            })
        };
        let (mut x0, mut x1) = span(&mut xs.into_iter());
        let (mut y0, mut y1) = span(&mut ys.into_iter());
        if !x0.is_finite() {
            (x0, x1, y0, y1) = (-10.0, 10.0, -10.0, 10.0);
        }
        // Equal scales on both axes (the plot area is about (w-80) x (h-90) pixels).
        let (pw, ph) = (f64::from(w - 80), f64::from(h - 90));
        let scale = ((x1 - x0 + 10.0) / pw).max((y1 - y0 + 10.0) / ph);
        let (cx, cy) = ((x0 + x1) / 2.0, (y0 + y1) / 2.0);
        let (hx, hy) = (scale * pw / 2.0, scale * ph / 2.0);
        let mut chart = ChartBuilder::on(root)
            .caption("Mission: track, places and goals", ("sans-serif", 16))
            .margin(10)
            .x_label_area_size(30)
            .y_label_area_size(40)
            .build_cartesian_2d((cx - hx)..(cx + hx), (cy - hy)..(cy + hy))?;
        chart
            .configure_mesh()
            .x_desc("east (m)")
            .y_desc("north (m)")
            .draw()?;
        let track: Vec<(f64, f64)> = c.track.iter().map(|p| (p.east, p.north)).collect();
        let blue = RGBColor(60, 120, 220);
        chart.draw_series(LineSeries::new(track.clone(), blue.stroke_width(2)))?;
        if let Some(&start) = track.first() {
            chart.draw_series(std::iter::once(Circle::new(start, 5, GREEN.filled())))?;
        }
        if let Some(&last) = track.last() {
            chart.draw_series(std::iter::once(Circle::new(last, 5, blue.filled())))?;
        }
        for p in &c.places {
            let color = if p.goals.is_empty() {
                RGBColor(90, 90, 90)
            } else {
                RGBColor(200, 60, 20)
            };
            chart.draw_series(std::iter::once(Circle::new(
                (p.east, p.north),
                4,
                color.filled(),
            )))?;
            let label = if p.goals.is_empty() {
                p.name.clone()
            } else {
                format!("{} ({})", p.name, p.goals.join(", "))
            };
            let (px, py) = chart.backend_coord(&(p.east, p.north));
            root.draw(&Text::new(
                label,
                (px + 6, py - 6),
                font(11)
                    .color(&color)
                    .pos(Pos::new(HPos::Left, VPos::Bottom)),
            ))?;
        }
        Ok(())
    })
}
