//! Printing helpers: facts, goals and dates written the way the language writes them.

use super::{AttrId, Domain, Fact, Goal, GoalOrigin, ObjectId, Problem, Time, TimeInterval, Value};
use super::{Bound, MS_PER_S};

impl Problem {
    /// `base`, or `+oo` for the unknown value.
    pub fn value_name(&self, v: Value) -> &str {
        match v {
            Value::Obj(o) => self.object_name(o),
            Value::Unknown => "+oo",
        }
    }

    /// `PICTURE(p1)`.
    pub fn instance_string(&self, d: &Domain, attr: AttrId, args: &[ObjectId]) -> String {
        let name = d.attrs.get(attr.index()).map_or("?", |a| a.name.as_str());
        let args: Vec<&str> = args.iter().map(|o| self.object_name(*o)).collect();
        format!("{name}({})", args.join(", "))
    }

    /// `PICTURE(p1) = true`.
    pub fn fact_string(&self, d: &Domain, f: &Fact) -> String {
        format!(
            "{} = {}",
            self.instance_string(d, f.attr, &f.args),
            self.value_name(f.value)
        )
    }

    /// A date relative to the origin as a clock time when the problem has a `start` (`08:20:05`), else in
    /// seconds (`125.5s`).
    pub fn time_string(&self, t: Time) -> String {
        match self.start_clock {
            Some(start) => {
                let ms = start + t;
                let s = ms.div_euclid(MS_PER_S);
                let frac = ms.rem_euclid(MS_PER_S);
                let (h, m, sec) = (s / 3600, (s / 60) % 60, s % 60);
                if frac == 0 {
                    format!("{h:02}:{m:02}:{sec:02}")
                } else {
                    format!("{h:02}:{m:02}:{sec:02}.{frac:03}")
                }
            }
            None => seconds(t),
        }
    }

    /// The goal in the language's syntax (parseable by `mavtempo::lang::parse_goal` against this problem).
    pub fn goal_string(&self, d: &Domain, g: &Goal) -> String {
        let kind = match g.kind {
            GoalOrigin::External => "external",
            GoalOrigin::Internal => "internal",
        };
        let mut s = format!(
            "goal {} {kind} priority {} {{ hold({}: {}, (st, et)); st in {};",
            g.name,
            g.priority,
            self.instance_string(d, g.attr, &g.args),
            self.value_name(g.value),
            interval_string(&g.start_window)
        );
        if !g.is_instantaneous() {
            s.push_str(&format!(" (et - st) in {};", interval_string(&g.duration)));
        }
        if g.achieve != 0 {
            s.push_str(&format!(" achieve {};", seconds(g.achieve)));
        }
        s.push_str(" }");
        s
    }
}

/// Milliseconds as the language's seconds (`125.5s`, `-3s`).
fn seconds(t: Time) -> String {
    if t % MS_PER_S == 0 {
        format!("{}s", t / MS_PER_S)
    } else {
        format!("{}ms", t)
    }
}

/// `[0s, 8min]`-style text for a time interval, in the language's syntax.
pub fn interval_string(i: &TimeInterval) -> String {
    let lb = match i.lb {
        Bound::Closed(v) => format!("[{}", seconds(v)),
        Bound::Open(v) => format!("]{}", seconds(v)),
        Bound::Inf => "]-oo".to_string(),
    };
    let ub = match i.ub {
        Bound::Closed(v) => format!("{}]", seconds(v)),
        Bound::Open(v) => format!("{}[", seconds(v)),
        Bound::Inf => "+oo[".to_string(),
    };
    format!("{lb}, {ub}")
}
