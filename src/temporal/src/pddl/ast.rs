//! The PDDL 2.1 (level 3) / 2.2 (timed initial literals) syntax trees the reader builds. Names are
//! lower-cased; every node keeps its span for messages.

use super::sexpr::Span;

/// A name and where it is written.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Name {
    pub name: String,
    pub span: Span,
}

/// A typed name (`?x - rover`, `rover0 - rover`); `types` has several members for `(either a b)` and is
/// `["object"]` when no type is written.
#[derive(Debug, Clone, PartialEq)]
pub struct Typed {
    pub name: Name,
    pub types: Vec<Name>,
}

/// An argument of an atom: a `?variable` or a constant.
#[derive(Debug, Clone, PartialEq)]
pub enum Arg {
    Var(Name),
    Const(Name),
}

impl Arg {
    pub fn name(&self) -> &Name {
        match self {
            Arg::Var(n) | Arg::Const(n) => n,
        }
    }
}

/// `(pred args...)` or `(function args...)`.
#[derive(Debug, Clone, PartialEq)]
pub struct Atom {
    pub pred: Name,
    pub args: Vec<Arg>,
    pub span: Span,
}

/// A numeric expression.
#[derive(Debug, Clone, PartialEq)]
pub enum NExpr {
    Num(f64, Span),
    Fluent(Atom),
    Duration(Span),
    /// `+ - * /`.
    Bin(char, Box<NExpr>, Box<NExpr>, Span),
    Neg(Box<NExpr>, Span),
}

impl NExpr {
    pub fn span(&self) -> Span {
        match self {
            NExpr::Num(_, s) | NExpr::Duration(s) | NExpr::Bin(_, _, _, s) | NExpr::Neg(_, s) => *s,
            NExpr::Fluent(a) => a.span,
        }
    }

    /// Whether `?duration` occurs in it.
    pub fn uses_duration(&self) -> bool {
        match self {
            NExpr::Duration(_) => true,
            NExpr::Num(..) | NExpr::Fluent(_) => false,
            NExpr::Bin(_, a, b, _) => a.uses_duration() || b.uses_duration(),
            NExpr::Neg(a, _) => a.uses_duration(),
        }
    }
}

/// `x op y` for a [`NExpr::Bin`] operator (`+ - * /`).
pub fn arithmetic(op: char, x: f64, y: f64) -> f64 {
    match op {
        '+' => x + y,
        '-' => x - y,
        '*' => x * y,
        _ => x / y,
    }
}

/// A comparison operator.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Cmp {
    Lt,
    Le,
    Eq,
    Ge,
    Gt,
}

impl Cmp {
    /// Whether `x op y`.
    pub fn holds(self, x: f64, y: f64) -> bool {
        match self {
            Cmp::Lt => x < y,
            Cmp::Le => x <= y,
            Cmp::Eq => x == y,
            Cmp::Ge => x >= y,
            Cmp::Gt => x > y,
        }
    }
}

/// A literal of a condition or goal (conditions are conjunctions of these).
#[derive(Debug, Clone, PartialEq)]
pub enum Lit {
    Pos(Atom),
    Neg(Atom),
    /// `(= a b)` (`true`) or `(not (= a b))` (`false`).
    Equal(Arg, Arg, bool, Span),
    Compare(Cmp, NExpr, NExpr, Span),
}

impl Lit {
    pub fn span(&self) -> Span {
        match self {
            Lit::Pos(a) | Lit::Neg(a) => a.span,
            Lit::Equal(_, _, _, s) | Lit::Compare(_, _, _, s) => *s,
        }
    }
}

/// When a condition or effect of a durative action applies.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum When {
    Start,
    OverAll,
    End,
}

/// A numeric effect's operator.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NumOp {
    Assign,
    Increase,
    Decrease,
    ScaleUp,
    ScaleDown,
}

/// One effect.
#[derive(Debug, Clone, PartialEq)]
pub enum Effect {
    Add(Atom),
    Del(Atom),
    Num(NumOp, Atom, NExpr, Span),
}

/// A (durative) action. Plain `:action`s are read as durative actions of duration 0 whose conditions and
/// effects are all `at start`.
#[derive(Debug, Clone, PartialEq)]
pub struct Action {
    pub name: Name,
    pub params: Vec<Typed>,
    /// `(= ?duration e)`, `(<= ?duration e)`, `(>= ?duration e)`, conjoined.
    pub duration: Vec<(Cmp, NExpr, Span)>,
    pub conditions: Vec<(When, Lit)>,
    pub effects: Vec<(When, Effect)>,
    pub durative: bool,
    pub span: Span,
}

/// A domain file (empty by default: the reader fills it section by section).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Domain {
    pub name: Name,
    pub requirements: Vec<Name>,
    /// `(child, parent)`; the parent is `object` when not written.
    pub types: Vec<(Name, Name)>,
    pub constants: Vec<Typed>,
    pub predicates: Vec<(Name, Vec<Typed>)>,
    pub functions: Vec<(Name, Vec<Typed>)>,
    pub actions: Vec<Action>,
}

/// One `:init` element.
#[derive(Debug, Clone, PartialEq)]
pub enum Init {
    /// A true atom, at the origin or (timed initial literal) at a date in seconds.
    Atom(Atom, Option<f64>),
    /// `(at T (not atom))`.
    NotAtom(Atom, f64),
    /// `(= (f args) value)`.
    Value(Atom, f64),
}

/// The metric: minimise (`true`) or maximise an expression (`total-time` is read as a fluent named so).
#[derive(Debug, Clone, PartialEq)]
pub struct Metric {
    pub minimize: bool,
    pub expr: NExpr,
    pub span: Span,
}

/// A problem file (empty by default: the reader fills it section by section).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Problem {
    pub name: Name,
    pub domain: Name,
    pub objects: Vec<Typed>,
    pub init: Vec<Init>,
    pub goal: Vec<Lit>,
    pub metric: Option<Metric>,
}
