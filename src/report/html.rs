//! One self-contained HTML page: the charts (inline SVG), the goals table, the counters and the last
//! events. The live page is the same body, replaced as the mission runs (server-sent events), with an
//! optional goal form.

use std::fmt::Write;

use super::data::Charts;
use super::svg::{self, DrawError};

/// `<`, `>`, `&` and quotes escaped.
pub fn esc(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for ch in s.chars() {
        match ch {
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '&' => out.push_str("&amp;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

/// The page's body: summary, goals, charts, counters, events. `live`: the mission is still running (the
/// Gantt chart gets a now-line).
pub fn body(c: &Charts, live: bool) -> Result<String, DrawError> {
    let mut h = String::new();
    let state = match &c.end {
        Some(end) => format!(
            "mission ended ({}) at {:.1} s",
            esc(end),
            c.now_ms as f64 / 1000.0
        ),
        None => format!("mission running: {:.1} s", c.now_ms as f64 / 1000.0),
    };
    let _ = write!(
        h,
        "<p id=\"state\" data-now-ms=\"{}\">{state}</p>",
        c.now_ms
    );
    if let Some(v) = &c.vehicle {
        vehicle(&mut h, v);
    }
    h.push_str(
        "<h2>Goals</h2><table id=\"goals\"><tr><th>goal</th><th>state</th><th>what</th><th>where</th>\
         <th>start window</th><th>source</th><th>reason</th><th></th></tr>",
    );
    for g in &c.goals {
        let state = if g.state.is_empty() {
            &g.fate
        } else {
            &g.state
        };
        let button = if g.cancellable {
            format!(
                "<button class=\"cancel\" data-cancel=\"{}\">cancel</button>",
                esc(&g.name)
            )
        } else {
            String::new()
        };
        let _ = write!(
            h,
            "<tr class=\"{fate}\" data-goal=\"{name}\" data-state=\"{state}\"><td>{name}</td><td>{state}</td>\
             <td>{what}</td><td>{place}</td><td>{window}</td><td>{source}</td><td>{reason}</td><td>{button}</td></tr>",
            name = esc(&g.name),
            fate = esc(&g.fate),
            state = esc(state),
            what = esc(&g.what),
            place = esc(&g.place),
            window = esc(&g.window),
            source = esc(&g.source),
            reason = esc(&g.reason)
        );
    }
    h.push_str("</table>");
    let _ = write!(
        h,
        "<h2>Executed plan</h2><div id=\"gantt\" data-bars=\"{}\">{}</div>",
        c.bars.len(),
        svg::gantt(c, live)?
    );
    h.push_str("<h2>Resources against their bounds</h2>");
    for s in &c.series {
        let _ = write!(
            h,
            "<div class=\"resource\" data-resource=\"{}\" data-samples=\"{}\">{}</div>",
            esc(&s.resource),
            s.reported.len(),
            svg::resource(c, s)?
        );
    }
    let _ = write!(
        h,
        "<h2>Mission map</h2><div id=\"map\">{}</div>",
        svg::map(c)?
    );
    h.push_str("<h2>Counters</h2><table id=\"counters\">");
    for (k, v) in &c.counters {
        let _ = write!(
            h,
            "<tr><td>{}</td><td>{}</td></tr>",
            esc(k),
            esc(&v.to_string())
        );
    }
    h.push_str("</table><h2>Last events</h2><pre id=\"events\">");
    for e in &c.events {
        h.push_str(&esc(e));
        h.push('\n');
    }
    h.push_str("</pre>");
    Ok(h)
}

/// The vehicle as last heard: mode, arming, battery, link.
fn vehicle(h: &mut String, v: &crate::vehicle::status::VehicleStatus) {
    let battery = v
        .battery_percent
        .map_or("unknown".to_string(), |b| format!("{b:.0} %"));
    let _ = write!(
        h,
        "<h2>Vehicle</h2><table id=\"vehicle\"><tr><td>mode</td><td id=\"vehicle-mode\">{}</td></tr>\
         <tr><td>armed</td><td id=\"vehicle-armed\">{}</td></tr>\
         <tr><td>battery</td><td id=\"vehicle-battery\">{}</td></tr>\
         <tr><td>link</td><td id=\"vehicle-link\">{}</td></tr></table>",
        esc(v.mode.as_deref().unwrap_or("unknown")),
        if v.armed { "yes" } else { "no" },
        esc(&battery),
        esc(&v.link)
    );
}

const STYLE: &str = "body{font-family:sans-serif;margin:1em 2em;max-width:1140px}\
table{border-collapse:collapse}td,th{border:1px solid #ccc;padding:2px 8px;text-align:left}\
tr.achieved td:nth-child(2){color:#147a3c}tr.rejected td:nth-child(2){color:#c05a00}\
tr.cancelled td:nth-child(2){color:#777}\
pre{background:#f6f6f6;padding:6px;font-size:12px}svg{max-width:100%;height:auto}\
form label{margin-right:1em}#goal-result{font-weight:bold}";

/// The whole page of a finished report.
pub fn page(title: &str, c: &Charts) -> Result<String, DrawError> {
    Ok(format!(
        "<!DOCTYPE html><html><head><meta charset=\"utf-8\"><title>{t}</title><style>{STYLE}</style>\
         </head><body><h1>{t}</h1><div id=\"live\">{}</div></body></html>\n",
        body(c, false)?,
        t = esc(title)
    ))
}

/// The goal form: a picture goal at east/north metres from home, through the same intake as a MAVLink
/// upload. Its answer (accepted, or rejected with the reason) shows in `#goal-result`.
const FORM: &str = "<h2>Submit a goal</h2><form id=\"goal-form\">\
<label>east (m) <input name=\"east\" value=\"30\" size=\"6\"></label>\
<label>north (m) <input name=\"north\" value=\"0\" size=\"6\"></label>\
<label>start window end (s) <input name=\"window_end_s\" value=\"1800\" size=\"6\"></label>\
<label>d_achiev (s) <input name=\"d_achiev_s\" value=\"60\" size=\"6\"></label>\
<button type=\"submit\">submit</button></form><p id=\"goal-result\"></p>";

const SCRIPT: &str = "<script>\
const es=new EventSource('events');\
es.onmessage=function(e){document.getElementById('live').innerHTML=e.data;};\
const f=document.getElementById('goal-form');\
if(f){f.addEventListener('submit',async function(ev){ev.preventDefault();\
const out=document.getElementById('goal-result');out.textContent='submitting...';\
try{const r=await fetch('goal',{method:'POST',body:new URLSearchParams(new FormData(f))});\
const j=await r.json();out.textContent=j.verdict;out.className=j.accepted?'accepted':'rejected';}\
catch(err){out.textContent='error: '+err;}});}\
document.addEventListener('click',async function(ev){const b=ev.target.closest('button[data-cancel]');\
if(!b)return;const out=document.getElementById('goal-result');const g=b.dataset.cancel;\
out.textContent='withdrawing '+g+'...';\
try{const r=await fetch('cancel',{method:'POST',body:new URLSearchParams({goal:g})});\
const j=await r.json();out.textContent=j.verdict;out.className=j.accepted?'cancelled':'rejected';}\
catch(err){out.textContent='error: '+err;}});\
</script>";

/// The live page: the current body, the goal form when enabled, and the script that replaces the body
/// with each snapshot the server pushes.
pub fn live_page(body: &str, goal_form: bool) -> String {
    format!(
        "<!DOCTYPE html><html><head><meta charset=\"utf-8\"><title>mavtempo: live mission</title>\
         <style>{STYLE}</style></head><body><h1>mavtempo: live mission</h1>{}<div id=\"live\">{body}</div>\
         {SCRIPT}</body></html>\n",
        if goal_form { FORM } else { "" }
    )
}
