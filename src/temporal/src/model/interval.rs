//! Intervals with open / closed / infinite bounds, as written in the language (`]2, 60]`, `[0, +oo[`).

use serde::Serialize;

use super::Time;

/// One end of an interval. `Inf` is −∞ for a lower bound and +∞ for an upper bound.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub enum Bound<T> {
    /// The value belongs to the interval.
    Closed(T),
    /// The value does not belong to the interval.
    Open(T),
    /// Unbounded on this side.
    Inf,
}

/// A set `lb .. ub` with each bound open, closed or infinite: of durations or dates in milliseconds
/// ([`TimeInterval`]) or of reals ([`NumInterval`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Interval<T> {
    pub lb: Bound<T>,
    pub ub: Bound<T>,
}

/// Durations or dates in milliseconds.
pub type TimeInterval = Interval<Time>;

/// Reals (numeric variable domains, resource quantities).
pub type NumInterval = Interval<f64>;

impl<T> Interval<T> {
    /// `]-oo, +oo[`: no constraint (the domain of a numeric variable declared without one).
    pub const ANY: Self = Interval {
        lb: Bound::Inf,
        ub: Bound::Inf,
    };

    /// `[lb, ub]`.
    pub fn closed(lb: T, ub: T) -> Self {
        Interval {
            lb: Bound::Closed(lb),
            ub: Bound::Closed(ub),
        }
    }
}

impl TimeInterval {
    /// `[v, v]`.
    pub fn exactly(v: Time) -> Self {
        Self::closed(v, v)
    }

    /// `[lb, +oo[`.
    pub fn at_least(lb: Time) -> Self {
        TimeInterval {
            lb: Bound::Closed(lb),
            ub: Bound::Inf,
        }
    }

    /// The smallest member on the integer millisecond grid (an open bound `]a` becomes `a + 1`, the STN's
    /// "one unit inside"); `None` for −∞.
    pub fn min_ms(&self) -> Option<Time> {
        match self.lb {
            Bound::Closed(v) => Some(v),
            Bound::Open(v) => Some(v.saturating_add(1)),
            Bound::Inf => None,
        }
    }

    /// The largest member on the millisecond grid (`b[` becomes `b − 1`); `None` for +∞.
    pub fn max_ms(&self) -> Option<Time> {
        match self.ub {
            Bound::Closed(v) => Some(v),
            Bound::Open(v) => Some(v.saturating_sub(1)),
            Bound::Inf => None,
        }
    }

    /// True when no millisecond satisfies the interval (e.g. `[5, 3]` or `]2, 3[`).
    pub fn is_empty(&self) -> bool {
        matches!((self.min_ms(), self.max_ms()), (Some(a), Some(b)) if a > b)
    }

    /// True when `t` belongs to the interval.
    pub fn contains(&self, t: Time) -> bool {
        self.min_ms().is_none_or(|a| a <= t) && self.max_ms().is_none_or(|b| t <= b)
    }
}

impl NumInterval {
    /// The lower end as a number (−∞ when unbounded), ignoring openness.
    pub fn lo(&self) -> f64 {
        match self.lb {
            Bound::Closed(v) | Bound::Open(v) => v,
            Bound::Inf => f64::NEG_INFINITY,
        }
    }

    /// The upper end as a number (+∞ when unbounded), ignoring openness.
    pub fn hi(&self) -> f64 {
        match self.ub {
            Bound::Closed(v) | Bound::Open(v) => v,
            Bound::Inf => f64::INFINITY,
        }
    }

    /// True when no real satisfies the interval.
    pub fn is_empty(&self) -> bool {
        let (lo, hi) = (self.lo(), self.hi());
        let open = matches!(self.lb, Bound::Open(_)) || matches!(self.ub, Bound::Open(_));
        lo > hi || (lo == hi && open)
    }

    /// True when `x` belongs to the interval.
    pub fn contains(&self, x: f64) -> bool {
        let above = match self.lb {
            Bound::Closed(v) => x >= v,
            Bound::Open(v) => x > v,
            Bound::Inf => true,
        };
        let below = match self.ub {
            Bound::Closed(v) => x <= v,
            Bound::Open(v) => x < v,
            Bound::Inf => true,
        };
        above && below
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn open_bounds_step_one_millisecond_inside() {
        let i = TimeInterval {
            lb: Bound::Open(2_000),
            ub: Bound::Closed(60_000),
        };
        assert_eq!(i.min_ms(), Some(2_001));
        assert_eq!(i.max_ms(), Some(60_000));
        assert!(!i.contains(2_000));
        assert!(i.contains(2_001));
        assert!(!i.is_empty());
        let e = TimeInterval {
            lb: Bound::Open(3),
            ub: Bound::Open(4),
        };
        assert!(e.is_empty());
        assert!(!TimeInterval::ANY.is_empty());
    }

    #[test]
    fn numeric_emptiness_respects_openness() {
        assert!(!NumInterval::closed(1.0, 1.0).is_empty());
        let half_open = NumInterval {
            lb: Bound::Open(1.0),
            ub: Bound::Closed(1.0),
        };
        assert!(half_open.is_empty());
        assert!(NumInterval::closed(2.0, 1.0).is_empty());
        assert!(NumInterval::ANY.contains(-1e300));
    }
}

/// An interval in the language's notation from its bounds: `[a, b]`, `]a, +oo[`.
pub fn show_bounds<T: std::fmt::Display>(lb: &Bound<T>, ub: &Bound<T>) -> String {
    let lb = match lb {
        Bound::Closed(v) => format!("[{v}"),
        Bound::Open(v) => format!("]{v}"),
        Bound::Inf => "]-oo".to_string(),
    };
    let ub = match ub {
        Bound::Closed(v) => format!("{v}]"),
        Bound::Open(v) => format!("{v}["),
        Bound::Inf => "+oo[".to_string(),
    };
    format!("{lb}, {ub}")
}

/// The language's notation in seconds, e.g. `[0 s, 330 s]`, `]2 s, +oo[`.
impl std::fmt::Display for TimeInterval {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let s = |v: Time| v as f64 / 1000.0;
        match self.lb {
            Bound::Closed(v) => write!(f, "[{} s", s(v))?,
            Bound::Open(v) => write!(f, "]{} s", s(v))?,
            Bound::Inf => f.write_str("]-oo")?,
        }
        match self.ub {
            Bound::Closed(v) => write!(f, ", {} s]", s(v)),
            Bound::Open(v) => write!(f, ", {} s[", s(v)),
            Bound::Inf => f.write_str(", +oo["),
        }
    }
}

#[cfg(test)]
mod display_tests {
    use super::*;

    #[test]
    fn intervals_print_in_the_language_notation() {
        assert_eq!(TimeInterval::closed(0, 330_000).to_string(), "[0 s, 330 s]");
        assert_eq!(TimeInterval::at_least(1_500).to_string(), "[1.5 s, +oo[");
        let open = TimeInterval {
            lb: Bound::Open(2_000),
            ub: Bound::Inf,
        };
        assert_eq!(open.to_string(), "]2 s, +oo[");
    }
}
