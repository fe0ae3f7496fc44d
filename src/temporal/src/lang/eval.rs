//! Constant expressions: numbers, durations (`20min`; a bare number is seconds), clock times (`08:00`,
//! relative to the problem's `start`), `+oo` / `-oo`, and the interval syntax.

use crate::model::{Bound, NumInterval, Time, TimeInterval};

use super::ast::{BinOp, Expr, ExprKind, IntervalAst};
use super::diag::{Diagnostic, Source, Span};

/// Largest date or duration accepted: ~31,700 years in ms, far from i64 overflow in STN sums.
const MAX_MS: f64 = 1e15;

const EMPTY_INTERVAL: &str = "empty interval: its lower bound exceeds its upper bound";

/// Diagnostics collected while resolving one file.
pub struct Ctx<'a> {
    pub src: Source<'a>,
    pub diags: Vec<Diagnostic>,
    /// What is legal but most likely not what the author meant (`check` prints them).
    pub warnings: Vec<Diagnostic>,
}

impl<'a> Ctx<'a> {
    pub fn new(src: Source<'a>) -> Self {
        Ctx {
            src,
            diags: Vec::new(),
            warnings: Vec::new(),
        }
    }

    /// Records a warning at `span`.
    pub fn warn(&mut self, span: Span, msg: impl Into<String>) {
        self.warnings.push(self.src.error(span, msg));
    }

    /// Records an error at `span`.
    pub fn err(&mut self, span: Span, msg: impl Into<String>) {
        self.diags.push(self.src.error(span, msg));
    }
}

/// How clock times are read: `None` in domains (no clock there), `Some(start)` in problems.
#[derive(Debug, Clone, Copy)]
pub struct Clock(pub Option<Time>);

/// An evaluated time: finite milliseconds or an infinity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TimeVal {
    Ms(Time),
    PosInf,
    NegInf,
}

/// A plain number (units and clock times rejected). `±oo` only if `inf_ok`.
pub fn num(ctx: &mut Ctx<'_>, e: &Expr, inf_ok: bool) -> Option<f64> {
    let v = num_inner(ctx, e)?;
    if v.is_infinite() && !inf_ok {
        ctx.err(e.span, "expected a finite number here");
        return None;
    }
    if v.is_nan() {
        ctx.err(e.span, "this expression has no numeric value");
        return None;
    }
    Some(v)
}

fn num_inner(ctx: &mut Ctx<'_>, e: &Expr) -> Option<f64> {
    match &e.kind {
        ExprKind::Num(v, None) => Some(*v),
        // A duration in a numeric context is in seconds (the unit of duration variables).
        ExprKind::Num(v, Some(u)) => Some(v * u.ms() / 1000.0),
        ExprKind::PosInf => Some(f64::INFINITY),
        ExprKind::NegInf => Some(f64::NEG_INFINITY),
        ExprKind::Neg(inner) => num_inner(ctx, inner).map(|v| -v),
        ExprKind::Bin(op, a, b) => {
            let (a, b) = (num_inner(ctx, a)?, num_inner(ctx, b)?);
            Some(match op {
                BinOp::Add => a + b,
                BinOp::Sub => a - b,
                BinOp::Mul => a * b,
                BinOp::Div => a / b,
            })
        }
        ExprKind::Clock(_) => {
            ctx.err(
                e.span,
                "a clock time is not a number: write a duration or a plain number",
            );
            None
        }
        _ => {
            ctx.err(e.span, "expected a number");
            None
        }
    }
}

/// A date or duration in ms. Bare numbers are seconds; clock times need `clock` (a problem's start).
pub fn time(ctx: &mut Ctx<'_>, e: &Expr, clock: Clock) -> Option<TimeVal> {
    let v = time_inner(ctx, e, clock)?;
    if v.is_nan() {
        ctx.err(e.span, "this expression has no time value");
        return None;
    }
    if v == f64::INFINITY {
        return Some(TimeVal::PosInf);
    }
    if v == f64::NEG_INFINITY {
        return Some(TimeVal::NegInf);
    }
    if v.abs() > MAX_MS {
        ctx.err(e.span, "time out of range");
        return None;
    }
    Some(TimeVal::Ms(v.round() as Time))
}

fn time_inner(ctx: &mut Ctx<'_>, e: &Expr, clock: Clock) -> Option<f64> {
    match &e.kind {
        ExprKind::Num(v, None) => Some(v * 1000.0),
        ExprKind::Num(v, Some(u)) => Some(v * u.ms()),
        ExprKind::PosInf => Some(f64::INFINITY),
        ExprKind::NegInf => Some(f64::NEG_INFINITY),
        ExprKind::Clock(ms) => match clock.0 {
            None => {
                ctx.err(
                    e.span,
                    "clock times are only allowed in problems (relative to their `start`)",
                );
                None
            }
            Some(start) if *ms < start => {
                ctx.err(
                    e.span,
                    format!(
                        "clock time {} is before the problem's start {}",
                        fmt_clock(*ms),
                        fmt_clock(start)
                    ),
                );
                None
            }
            Some(start) => Some((ms - start) as f64),
        },
        ExprKind::Neg(inner) => time_inner(ctx, inner, clock).map(|v| -v),
        ExprKind::Bin(BinOp::Add, a, b) => {
            Some(time_inner(ctx, a, clock)? + time_inner(ctx, b, clock)?)
        }
        ExprKind::Bin(BinOp::Sub, a, b) => {
            Some(time_inner(ctx, a, clock)? - time_inner(ctx, b, clock)?)
        }
        _ => {
            ctx.err(
                e.span,
                "expected a time: a number of seconds, a duration like `20min`, or a clock time like `08:00`",
            );
            None
        }
    }
}

/// `HH:MM` or `HH:MM:SS` for a time of day in ms.
pub fn fmt_clock(ms: Time) -> String {
    let s = ms / 1000;
    let (h, m, sec) = (s / 3600, (s / 60) % 60, s % 60);
    if sec == 0 {
        format!("{h:02}:{m:02}")
    } else {
        format!("{h:02}:{m:02}:{sec:02}")
    }
}

/// A time interval; an empty one is reported at `i.span`.
pub fn time_interval(ctx: &mut Ctx<'_>, i: &IntervalAst, clock: Clock) -> Option<TimeInterval> {
    let lb = time(ctx, &i.lb, clock);
    let ub = time(ctx, &i.ub, clock);
    let (lb, ub) = (lb?, ub?);
    let lb = time_bound(ctx, lb, i.lb_open, &i.lb, true)?;
    let ub = time_bound(ctx, ub, i.ub_open, &i.ub, false)?;
    let iv = TimeInterval { lb, ub };
    if iv.is_empty() {
        ctx.err(i.span, EMPTY_INTERVAL);
        return None;
    }
    Some(iv)
}

/// One end of a time interval: −oo is only a lower bound, +oo only an upper one.
fn time_bound(
    ctx: &mut Ctx<'_>,
    v: TimeVal,
    open: bool,
    e: &Expr,
    lower: bool,
) -> Option<Bound<Time>> {
    match (v, lower) {
        (TimeVal::NegInf, true) | (TimeVal::PosInf, false) => Some(Bound::Inf),
        (TimeVal::PosInf, true) => {
            ctx.err(e.span, "a lower bound cannot be +oo");
            None
        }
        (TimeVal::NegInf, false) => {
            ctx.err(e.span, "an upper bound cannot be -oo");
            None
        }
        (TimeVal::Ms(v), _) if open => Some(Bound::Open(v)),
        (TimeVal::Ms(v), _) => Some(Bound::Closed(v)),
    }
}

/// A numeric interval; an empty one is reported at `i.span`.
pub fn num_interval(ctx: &mut Ctx<'_>, i: &IntervalAst) -> Option<NumInterval> {
    let lb = num(ctx, &i.lb, true);
    let ub = num(ctx, &i.ub, true);
    let (lb, ub) = (lb?, ub?);
    if lb == f64::INFINITY {
        ctx.err(i.lb.span, "a lower bound cannot be +oo");
        return None;
    }
    if ub == f64::NEG_INFINITY {
        ctx.err(i.ub.span, "an upper bound cannot be -oo");
        return None;
    }
    let bound = |v: f64, open: bool| {
        if v.is_infinite() {
            Bound::Inf
        } else if open {
            Bound::Open(v)
        } else {
            Bound::Closed(v)
        }
    };
    let iv = NumInterval {
        lb: bound(lb, i.lb_open),
        ub: bound(ub, i.ub_open),
    };
    if iv.is_empty() {
        ctx.err(i.span, EMPTY_INTERVAL);
        return None;
    }
    Some(iv)
}

/// The intersection of two numeric intervals.
pub fn intersect_num(a: NumInterval, b: NumInterval) -> NumInterval {
    let lb = match (a.lb, b.lb) {
        (Bound::Inf, x) | (x, Bound::Inf) => x,
        (x, y) => {
            let (xv, yv) = (bound_value(x), bound_value(y));
            if xv > yv || (xv == yv && matches!(x, Bound::Open(_))) {
                x
            } else {
                y
            }
        }
    };
    let ub = match (a.ub, b.ub) {
        (Bound::Inf, x) | (x, Bound::Inf) => x,
        (x, y) => {
            let (xv, yv) = (bound_value(x), bound_value(y));
            if xv < yv || (xv == yv && matches!(x, Bound::Open(_))) {
                x
            } else {
                y
            }
        }
    };
    NumInterval { lb, ub }
}

fn bound_value(b: Bound<f64>) -> f64 {
    match b {
        Bound::Closed(v) | Bound::Open(v) => v,
        Bound::Inf => f64::NAN,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lang::parser::Parser;

    fn eval_time(text: &str, clock: Clock) -> Option<TimeVal> {
        let src = Source::new("t", text);
        let e = Parser::new(src).ok()?.expr().ok()?;
        let mut ctx = Ctx::new(src);
        time(&mut ctx, &e, clock)
    }

    #[test]
    fn durations_and_clock_times_in_ms() {
        assert_eq!(eval_time("60", Clock(None)), Some(TimeVal::Ms(60_000)));
        assert_eq!(
            eval_time("20min", Clock(None)),
            Some(TimeVal::Ms(1_200_000))
        );
        assert_eq!(eval_time("1.5h", Clock(None)), Some(TimeVal::Ms(5_400_000)));
        assert_eq!(eval_time("250ms", Clock(None)), Some(TimeVal::Ms(250)));
        let eight = Clock(Some(8 * 3_600_000));
        assert_eq!(eval_time("20:00", eight), Some(TimeVal::Ms(12 * 3_600_000)));
        assert_eq!(eval_time("07:00", eight), None);
        assert_eq!(eval_time("08:00", Clock(None)), None);
        assert_eq!(eval_time("+oo", Clock(None)), Some(TimeVal::PosInf));
        assert_eq!(eval_time("1e", Clock(None)), None);
    }

    #[test]
    fn intersection_keeps_tightest_bounds() {
        let a = NumInterval::closed(0.0, 10.0);
        let b = NumInterval {
            lb: Bound::Open(5.0),
            ub: Bound::Inf,
        };
        let c = intersect_num(a, b);
        assert_eq!(c.lb, Bound::Open(5.0));
        assert_eq!(c.ub, Bound::Closed(10.0));
        assert!(intersect_num(a, NumInterval::closed(11.0, 12.0)).is_empty());
    }
}
