//! Syntax trees of domain and problem files, with spans (semantic checks happen in `resolve`).

use super::diag::Span;
pub use super::lexer::RelOp;
use super::lexer::Unit;

/// A name with where it was written.
#[derive(Debug, Clone, PartialEq)]
pub struct Ident {
    pub name: String,
    pub span: Span,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BinOp {
    Add,
    Sub,
    Mul,
    Div,
}

#[derive(Debug, Clone, PartialEq)]
pub enum ExprKind {
    /// `?x`
    Var(String),
    /// `st`, `FORWARD`, `base`
    Name(String),
    Num(f64, Option<Unit>),
    /// Milliseconds since midnight.
    Clock(i64),
    PosInf,
    NegInf,
    /// `*` as an attribute argument in `initial` (every object of the parameter's type).
    Wildcard,
    /// `distance(?a, ?b)`
    Call(Ident, Vec<Expr>),
    Bin(BinOp, Box<Expr>, Box<Expr>),
    Neg(Box<Expr>),
}

#[derive(Debug, Clone, PartialEq)]
pub struct Expr {
    pub kind: ExprKind,
    pub span: Span,
}

/// `name(args)` on a logical attribute (or `name` / `name()` on a resource).
#[derive(Debug, Clone, PartialEq)]
pub struct AttrRef {
    pub name: Ident,
    pub args: Vec<Expr>,
    pub span: Span,
}

/// `[a, b]`, `]a, b]`, ... Bounds are expressions (`+oo`, `-oo`, numbers, clock times).
#[derive(Debug, Clone, PartialEq)]
pub struct IntervalAst {
    pub lb: Expr,
    pub lb_open: bool,
    pub ub: Expr,
    pub ub_open: bool,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq)]
pub enum InSet {
    Interval(IntervalAst),
    /// `{a, b, c}`
    Set(Vec<Ident>),
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum UsageAst {
    Use,
    Consume,
    Produce,
}

/// `use(r: q, (from, to));`, `consume(r: q, t);`, `[secondary] [saturating] produce(r: q, t);`
#[derive(Debug, Clone, PartialEq)]
pub struct UsageStmt {
    pub kind: UsageAst,
    pub secondary: bool,
    /// `saturating produce(…)`: the level rises by the quantity but never above the capacity.
    pub saturating: bool,
    pub resource: Ident,
    pub quantity: Expr,
    pub from: Ident,
    pub to: Option<Ident>,
    pub span: Span,
}

/// A statement of a task or goal body.
#[derive(Debug, Clone, PartialEq)]
pub enum Stmt {
    Event {
        secondary: bool,
        attr: AttrRef,
        from: Expr,
        to: Expr,
        at: Ident,
        span: Span,
    },
    Hold {
        attr: AttrRef,
        value: Expr,
        from: Ident,
        /// `None` for `hold(a: v, t)` (an instant).
        to: Option<Ident>,
        span: Span,
    },
    Usage(UsageStmt),
    /// `variable ?a, ?b: location;` (untyped = numeric)
    Variables(Vec<(Ident, Option<Ident>)>),
    /// `?a, ?b in ]-oo, +oo[;`, `?w in {W1, W2};`, `(et - st) in [2, 60];`
    In {
        lhs: Vec<Expr>,
        set: InSet,
        span: Span,
    },
    Rel {
        lhs: Expr,
        op: RelOp,
        rhs: Expr,
        span: Span,
    },
    /// `achieve 30s;` (goals only)
    Achieve(Expr, Span),
    /// `contingent (et - st) in [a, b];`, `contingent ?d = et - st;`: the task's duration is decided by
    /// the world (tasks only).
    Contingent(Box<Stmt>, Span),
}

#[derive(Debug, Clone, PartialEq)]
pub struct TaskAst {
    pub name: Ident,
    pub params: Vec<(Ident, Ident)>,
    pub timepoints: Vec<Ident>,
    pub body: Vec<Stmt>,
    pub preemption: Option<Ident>,
}

#[derive(Debug, Clone, PartialEq)]
pub enum PositionAst {
    /// `at (east, north[, up])`
    Local(Vec<Expr>, Span),
    /// `at lat X lon Y [alt Z]`
    Geo {
        lat: Box<Expr>,
        lon: Box<Expr>,
        alt: Option<Box<Expr>>,
        span: Span,
    },
}

#[derive(Debug, Clone, PartialEq)]
pub enum DomainItem {
    Type {
        name: Ident,
        members: Option<Vec<Ident>>,
    },
    /// `constant surface: location at (0, 0);`
    Constant {
        names: Vec<Ident>,
        ty: Ident,
        position: Option<PositionAst>,
    },
    Attribute {
        name: Ident,
        params: Vec<(Ident, Ident)>,
        value_ty: Ident,
    },
    Resource {
        name: Ident,
        kind: Ident,
        capacity: Option<Expr>,
    },
    Task(TaskAst),
}

#[derive(Debug, Clone, PartialEq)]
pub struct DomainAst {
    pub name: Ident,
    pub items: Vec<DomainItem>,
}

/// `attr(args) = value [at time];` in `initial { ... }`.
#[derive(Debug, Clone, PartialEq)]
pub struct InitAst {
    pub attr: AttrRef,
    pub value: Expr,
    pub at: Option<Expr>,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq)]
pub struct GoalAst {
    pub name: Ident,
    pub kind: Option<Ident>,
    pub priority: Option<Expr>,
    pub body: Vec<Stmt>,
}

/// One `key value [from time]` of a problem's `resource` line.
#[derive(Debug, Clone, PartialEq)]
pub struct ResourceItemAst {
    pub key: Ident,
    pub value: Expr,
    pub from: Option<Expr>,
}

#[derive(Debug, Clone, PartialEq)]
pub enum ProblemItem {
    Start(Expr),
    Home {
        lat: Expr,
        lon: Expr,
        alt: Option<Expr>,
        span: Span,
    },
    Horizon(Expr),
    Object {
        names: Vec<Ident>,
        ty: Ident,
        position: Option<PositionAst>,
    },
    Initial(Vec<InitAst>),
    Resource {
        name: Ident,
        items: Vec<ResourceItemAst>,
    },
    Goal(GoalAst),
}

#[derive(Debug, Clone, PartialEq)]
pub struct ProblemAst {
    pub name: Ident,
    pub domain: Ident,
    pub items: Vec<ProblemItem>,
}
