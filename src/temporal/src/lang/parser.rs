//! Recursive-descent parser: tokens → [`DomainAst`] / [`ProblemAst`]. Stops at the first syntax error with a
//! diagnostic saying what was expected; expression nesting is bounded so no input can overflow the stack.

use super::ast::*;
use super::diag::{Diagnostic, Source, Span};
use super::lexer::{lex, Tok, Token};

/// Deepest expression nesting accepted (far beyond any real model).
const MAX_DEPTH: usize = 64;
/// Most operator / call nodes in one expression: bounds the tree depth that evaluation recurses over.
const MAX_NODES: usize = 256;

const DOMAIN_KEYWORDS: &[&str] = &["type", "constant", "attribute", "resource", "task"];
const PREEMPTIONS: &[&str] = &["nonPreemptive", "earlyPreemptive", "latePreemptive"];

pub struct Parser<'a> {
    src: Source<'a>,
    toks: Vec<Token>,
    pos: usize,
    depth: usize,
    nodes: usize,
}

type PResult<T> = Result<T, Diagnostic>;

impl<'a> Parser<'a> {
    pub fn new(src: Source<'a>) -> PResult<Self> {
        let toks = lex(&src)?;
        Ok(Parser {
            src,
            toks,
            pos: 0,
            depth: 0,
            nodes: 0,
        })
    }

    fn peek(&self) -> &Tok {
        // `lex` always ends with Eof and `bump` never moves past it.
        &self.toks[self.pos.min(self.toks.len() - 1)].tok
    }

    fn peek_at(&self, k: usize) -> &Tok {
        &self.toks[(self.pos + k).min(self.toks.len() - 1)].tok
    }

    fn span(&self) -> Span {
        self.toks[self.pos.min(self.toks.len() - 1)].span
    }

    fn prev_span(&self) -> Span {
        self.toks[self.pos.saturating_sub(1).min(self.toks.len() - 1)].span
    }

    fn bump(&mut self) -> Token {
        let t = self.toks[self.pos.min(self.toks.len() - 1)].clone();
        if self.pos < self.toks.len() - 1 {
            self.pos += 1;
        }
        t
    }

    fn err<T>(&self, what: &str) -> PResult<T> {
        Err(self.src.error(
            self.span(),
            format!("expected {what}, found {}", self.peek().describe()),
        ))
    }

    fn eat(&mut self, t: &Tok) -> bool {
        if self.peek() == t {
            self.bump();
            true
        } else {
            false
        }
    }

    fn expect(&mut self, t: Tok, what: &str) -> PResult<Span> {
        if self.peek() == &t {
            Ok(self.bump().span)
        } else {
            self.err(what)
        }
    }

    fn is_kw(&self, kw: &str) -> bool {
        matches!(self.peek(), Tok::Ident(s) if s == kw)
    }

    fn eat_kw(&mut self, kw: &str) -> bool {
        if self.is_kw(kw) {
            self.bump();
            true
        } else {
            false
        }
    }

    /// `kw EXPR` if the next word is `kw`.
    fn opt_kw_expr(&mut self, kw: &str) -> PResult<Option<Expr>> {
        if self.eat_kw(kw) {
            Ok(Some(self.expr()?))
        } else {
            Ok(None)
        }
    }

    fn expect_kw(&mut self, kw: &str) -> PResult<Span> {
        if self.is_kw(kw) {
            Ok(self.bump().span)
        } else {
            self.err(&format!("`{kw}`"))
        }
    }

    fn ident(&mut self, what: &str) -> PResult<Ident> {
        self.named(what, |t| match t {
            Tok::Ident(name) => Some(name),
            _ => None,
        })
    }

    fn var(&mut self, what: &str) -> PResult<Ident> {
        self.named(what, |t| match t {
            Tok::Var(name) => Some(name),
            _ => None,
        })
    }

    /// The name `name_of` finds in the next token (a name or a `?variable`), with its span.
    fn named(&mut self, what: &str, name_of: impl Fn(&Tok) -> Option<&String>) -> PResult<Ident> {
        match name_of(self.peek()).cloned() {
            Some(name) => {
                let span = self.bump().span;
                Ok(Ident { name, span })
            }
            None => self.err(what),
        }
    }

    /// A missing `;` is reported just after the previous token, where it belongs.
    fn semi(&mut self) -> PResult<()> {
        if self.eat(&Tok::Semi) {
            return Ok(());
        }
        Err(self.src.error_at(
            self.prev_span().end,
            format!("expected `;`, found {}", self.peek().describe()),
        ))
    }

    // ---------------------------------------------------------------- files

    /// `domain NAME; item*`
    pub fn domain_file(&mut self) -> PResult<DomainAst> {
        let name = self.header("domain", "the domain's name")?;
        let items = self.items_to_eof(Self::domain_item)?;
        Ok(DomainAst { name, items })
    }

    /// `KEYWORD NAME;`, a header line of a file.
    fn header(&mut self, kw: &str, what: &str) -> PResult<Ident> {
        self.expect_kw(kw)?;
        let name = self.ident(what)?;
        self.semi()?;
        Ok(name)
    }

    /// `item*` up to the end of the file.
    fn items_to_eof<T>(&mut self, item: fn(&mut Self) -> PResult<T>) -> PResult<Vec<T>> {
        let mut items = Vec::new();
        while self.peek() != &Tok::Eof {
            items.push(item(self)?);
        }
        Ok(items)
    }

    fn domain_item(&mut self) -> PResult<DomainItem> {
        let kw = match self.peek() {
            Tok::Ident(s) if DOMAIN_KEYWORDS.contains(&s.as_str()) => s.clone(),
            _ => return self.err("`type`, `constant`, `attribute`, `resource` or `task`"),
        };
        self.bump();
        match kw.as_str() {
            "type" => {
                let name = self.ident("a type name")?;
                let members = if self.eat(&Tok::Rel(RelOp::Eq)) {
                    self.expect(Tok::LBrace, "`{` and the enumeration's values")?;
                    let m = self.ident_list("an enumeration value")?;
                    self.expect(Tok::RBrace, "`,` or `}`")?;
                    Some(m)
                } else {
                    None
                };
                self.semi()?;
                Ok(DomainItem::Type { name, members })
            }
            "constant" => {
                let (names, ty, position) = self.object_decl()?;
                Ok(DomainItem::Constant {
                    names,
                    ty,
                    position,
                })
            }
            "attribute" => {
                let name = self.ident("an attribute name")?;
                let params = self.params()?;
                self.expect(Tok::Colon, "`:` and the attribute's value type")?;
                let value_ty = self.ident("a value type")?;
                self.semi()?;
                Ok(DomainItem::Attribute {
                    name,
                    params,
                    value_ty,
                })
            }
            "resource" => {
                let name = self.ident("a resource name")?;
                self.expect(Tok::Colon, "`:` and `unary` or `reservoir`")?;
                let kind = self.ident("`unary` or `reservoir`")?;
                let capacity = self.opt_kw_expr("capacity")?;
                self.semi()?;
                Ok(DomainItem::Resource {
                    name,
                    kind,
                    capacity,
                })
            }
            _ => self.task().map(DomainItem::Task),
        }
    }

    /// `NAME (, NAME)* : TYPE [at POSITION] ;`
    fn object_decl(&mut self) -> PResult<(Vec<Ident>, Ident, Option<PositionAst>)> {
        let names = self.ident_list("an object name")?;
        self.expect(Tok::Colon, "`,` or `:` and the object's type")?;
        let ty = self.ident("a type name")?;
        let position = if self.eat_kw("at") {
            Some(self.position()?)
        } else {
            None
        };
        self.semi()?;
        Ok((names, ty, position))
    }

    fn position(&mut self) -> PResult<PositionAst> {
        let start = self.span();
        if self.eat_kw("lat") {
            let lat = self.expr()?;
            self.expect_kw("lon")?;
            let lon = self.expr()?;
            let alt = self.opt_kw_expr("alt")?;
            return Ok(PositionAst::Geo {
                lat: Box::new(lat),
                lon: Box::new(lon),
                alt: alt.map(Box::new),
                span: start.to(self.prev_span()),
            });
        }
        if self.peek() != &Tok::LParen {
            return self.err("`(east, north[, up])` or `lat ... lon ...`");
        }
        self.bump();
        let mut coords = vec![self.expr()?];
        while self.eat(&Tok::Comma) {
            coords.push(self.expr()?);
        }
        self.expect(Tok::RParen, "`,` or `)`")?;
        Ok(PositionAst::Local(coords, start.to(self.prev_span())))
    }

    fn ident_list(&mut self, what: &str) -> PResult<Vec<Ident>> {
        let mut v = vec![self.ident(what)?];
        while self.eat(&Tok::Comma) {
            v.push(self.ident(what)?);
        }
        Ok(v)
    }

    /// `( [?p: T (, ?p: T)*] )`
    fn params(&mut self) -> PResult<Vec<(Ident, Ident)>> {
        self.expect(Tok::LParen, "`(` and the parameters")?;
        let mut params = Vec::new();
        if self.eat(&Tok::RParen) {
            return Ok(params);
        }
        loop {
            let v = self.var("a parameter `?name`")?;
            self.expect(Tok::Colon, "`:` and the parameter's type")?;
            let t = self.ident("a type name")?;
            params.push((v, t));
            if self.eat(&Tok::RParen) {
                return Ok(params);
            }
            self.expect(Tok::Comma, "`,` or `)`")?;
        }
    }

    /// `task NAME(params) (tp, ...) { stmt* } [preemption] [;]`
    fn task(&mut self) -> PResult<TaskAst> {
        let name = self.ident("a task name")?;
        let params = self.params()?;
        self.expect(
            Tok::LParen,
            "`(` and the task's timepoints, e.g. `(st, et)`",
        )?;
        let timepoints = self.ident_list("a timepoint name")?;
        self.expect(Tok::RParen, "`,` or `)`")?;
        let body = self.body()?;
        let preemption = match self.peek() {
            Tok::Ident(s) if !DOMAIN_KEYWORDS.contains(&s.as_str()) => {
                if !PREEMPTIONS.contains(&s.as_str()) {
                    return self.err(
                        "`nonPreemptive`, `earlyPreemptive`, `latePreemptive` or a declaration",
                    );
                }
                Some(self.ident("a preemption class")?)
            }
            _ => None,
        };
        self.eat(&Tok::Semi);
        Ok(TaskAst {
            name,
            params,
            timepoints,
            body,
            preemption,
        })
    }

    /// `{ stmt* }`
    fn body(&mut self) -> PResult<Vec<Stmt>> {
        self.expect(Tok::LBrace, "`{`")?;
        let mut body = Vec::new();
        while !self.eat(&Tok::RBrace) {
            if self.peek() == &Tok::Eof {
                return self.err("a statement or `}`");
            }
            body.push(self.stmt()?);
        }
        Ok(body)
    }

    fn stmt(&mut self) -> PResult<Stmt> {
        let start = self.span();
        if self.eat_kw("contingent") {
            let inner =
                match self.peek() {
                    Tok::LParen | Tok::Var(_) => self.constraint()?,
                    _ => return self.err(
                        "a duration after `contingent`: `(et - st) in [a, b];` or `?d = et - st;`",
                    ),
                };
            return Ok(Stmt::Contingent(
                Box::new(inner),
                start.to(self.prev_span()),
            ));
        }
        let secondary = self.eat_kw("secondary");
        let saturating = self.eat_kw("saturating");
        let kw = match self.peek() {
            Tok::Ident(s) => s.clone(),
            _ => String::new(),
        };
        if saturating && kw != "produce" {
            return self.err("`produce` after `saturating`");
        }
        if secondary && kw != "event" && kw != "produce" {
            return self.err("`event` or `produce` after `secondary`");
        }
        match kw.as_str() {
            "event" => {
                self.bump();
                self.expect(Tok::LParen, "`(`")?;
                let attr = self.attr_ref()?;
                self.expect(Tok::Colon, "`:` and `(from, to)`")?;
                self.expect(Tok::LParen, "`(from, to)`")?;
                let from = self.expr()?;
                self.expect(Tok::Comma, "`,`")?;
                let to = self.expr()?;
                self.expect(Tok::RParen, "`)`")?;
                self.expect(Tok::Comma, "`,` and a timepoint")?;
                let at = self.ident("a timepoint name")?;
                self.expect(Tok::RParen, "`)`")?;
                self.semi()?;
                Ok(Stmt::Event {
                    secondary,
                    attr,
                    from,
                    to,
                    at,
                    span: start.to(self.prev_span()),
                })
            }
            "hold" => {
                self.bump();
                self.expect(Tok::LParen, "`(`")?;
                let attr = self.attr_ref()?;
                let (value, (from, to)) = self.value_and_timepoints("a value", "`(from, to)`")?;
                Ok(Stmt::Hold {
                    attr,
                    value,
                    from,
                    to,
                    span: start.to(self.prev_span()),
                })
            }
            "use" | "consume" | "produce" => {
                self.bump();
                let kind = match kw.as_str() {
                    "use" => UsageAst::Use,
                    "consume" => UsageAst::Consume,
                    _ => UsageAst::Produce,
                };
                self.expect(Tok::LParen, "`(`")?;
                let resource = self.ident("a resource name")?;
                if self.eat(&Tok::LParen) {
                    self.expect(Tok::RParen, "`)`: resources take no parameters")?;
                }
                let (quantity, (from, to)) =
                    self.value_and_timepoints("a quantity", "a timepoint")?;
                Ok(Stmt::Usage(UsageStmt {
                    kind,
                    secondary,
                    saturating,
                    resource,
                    quantity,
                    from,
                    to,
                    span: start.to(self.prev_span()),
                }))
            }
            "variable" => {
                self.bump();
                let mut vars = Vec::new();
                loop {
                    let v = self.var("a variable `?name`")?;
                    let ty = if self.eat(&Tok::Colon) {
                        Some(self.ident("a type name")?)
                    } else {
                        None
                    };
                    vars.push((v, ty));
                    if !self.eat(&Tok::Comma) {
                        break;
                    }
                }
                self.semi()?;
                Ok(Stmt::Variables(vars))
            }
            "achieve" => {
                let e = self.keyword_expr()?;
                Ok(Stmt::Achieve(e, start.to(self.prev_span())))
            }
            _ => self.constraint(),
        }
    }

    /// `(t1, t2)` or `t`.
    /// `KEYWORD expr;` (`achieve 30s;`, `horizon 20:00;`), the keyword being the next token.
    fn keyword_expr(&mut self) -> PResult<Expr> {
        self.bump();
        let e = self.expr()?;
        self.semi()?;
        Ok(e)
    }

    /// `: VALUE, TIMEPOINTS);`, the end of a hold and of a resource usage (`what` and `when` name the two
    /// parts in messages).
    fn value_and_timepoints(
        &mut self,
        what: &str,
        when: &str,
    ) -> PResult<(Expr, (Ident, Option<Ident>))> {
        if !self.eat(&Tok::Colon) {
            return self.err(&format!("`:` and {what}"));
        }
        let value = self.expr()?;
        if !self.eat(&Tok::Comma) {
            return self.err(&format!("`,` and {when}"));
        }
        let tps = self.tp_pair()?;
        self.expect(Tok::RParen, "`)`")?;
        self.semi()?;
        Ok((value, tps))
    }

    fn tp_pair(&mut self) -> PResult<(Ident, Option<Ident>)> {
        if self.eat(&Tok::LParen) {
            let a = self.ident("a timepoint name")?;
            self.expect(Tok::Comma, "`,`")?;
            let b = self.ident("a timepoint name")?;
            self.expect(Tok::RParen, "`)`")?;
            Ok((a, Some(b)))
        } else {
            Ok((self.ident("a timepoint or `(from, to)`")?, None))
        }
    }

    /// `expr (, expr)* in SET ;` or `expr REL expr ;`
    fn constraint(&mut self) -> PResult<Stmt> {
        let start = self.span();
        let mut lhs = vec![self.expr()?];
        while self.eat(&Tok::Comma) {
            lhs.push(self.expr()?);
        }
        if self.eat_kw("in") {
            let set = if self.eat(&Tok::LBrace) {
                let s = self.ident_list("a value")?;
                self.expect(Tok::RBrace, "`,` or `}`")?;
                InSet::Set(s)
            } else {
                InSet::Interval(self.interval()?)
            };
            self.semi()?;
            return Ok(Stmt::In {
                lhs,
                set,
                span: start.to(self.prev_span()),
            });
        }
        if lhs.len() > 1 {
            return self.err("`in` after a list of variables");
        }
        let op = match self.peek() {
            Tok::Rel(op) => *op,
            _ => return self.err("a statement (event, hold, use, consume, produce, variable), `in`, `=`, `!=`, `<=` or `>=`"),
        };
        self.bump();
        let rhs = self.expr()?;
        self.semi()?;
        let lhs = lhs.remove(0);
        Ok(Stmt::Rel {
            lhs,
            op,
            rhs,
            span: start.to(self.prev_span()),
        })
    }

    /// `[a, b]`, `]a, b]`, `[a, b[`, `]a, b[`
    pub fn interval(&mut self) -> PResult<IntervalAst> {
        let start = self.span();
        let lb_open = match self.peek() {
            Tok::LBracket => false,
            Tok::RBracket => true,
            _ => return self.err("an interval such as `[a, b]`, `]a, b]` or `{a, b}`"),
        };
        self.bump();
        let lb = self.expr()?;
        self.expect(Tok::Comma, "`,` between the interval's bounds")?;
        let ub = self.expr()?;
        let ub_open = match self.peek() {
            Tok::RBracket => false,
            Tok::LBracket => true,
            _ => return self.err("`]` or `[` closing the interval"),
        };
        self.bump();
        Ok(IntervalAst {
            lb,
            lb_open,
            ub,
            ub_open,
            span: start.to(self.prev_span()),
        })
    }

    /// `NAME`, `NAME()` or `NAME(arg, ...)`
    fn attr_ref(&mut self) -> PResult<AttrRef> {
        let name = self.ident("an attribute name")?;
        let mut args = Vec::new();
        if self.eat(&Tok::LParen) && !self.eat(&Tok::RParen) {
            loop {
                args.push(self.arg()?);
                if self.eat(&Tok::RParen) {
                    break;
                }
                self.expect(Tok::Comma, "`,` or `)`")?;
            }
        }
        let span = name.span.to(self.prev_span());
        Ok(AttrRef { name, args, span })
    }

    fn arg(&mut self) -> PResult<Expr> {
        if self.peek() == &Tok::Star {
            let span = self.bump().span;
            return Ok(Expr {
                kind: ExprKind::Wildcard,
                span,
            });
        }
        self.expr()
    }

    // ---------------------------------------------------------------- expressions

    pub fn expr(&mut self) -> PResult<Expr> {
        if self.depth == 0 {
            self.nodes = 0;
        }
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            let e = self.err("a shallower expression (nesting limit reached)");
            self.depth -= 1;
            return e;
        }
        let r = self.sum();
        self.depth -= 1;
        r
    }

    fn sum(&mut self) -> PResult<Expr> {
        self.left_assoc(
            |t| match t {
                Tok::Plus => Some(BinOp::Add),
                Tok::Minus => Some(BinOp::Sub),
                _ => None,
            },
            Self::product,
        )
    }

    fn product(&mut self) -> PResult<Expr> {
        self.left_assoc(
            |t| match t {
                Tok::Star => Some(BinOp::Mul),
                Tok::Slash => Some(BinOp::Div),
                _ => None,
            },
            Self::atom,
        )
    }

    /// Counts one operator or call node of the current expression.
    fn node(&mut self) -> PResult<()> {
        self.nodes += 1;
        if self.nodes > MAX_NODES {
            return self.err("a shorter expression (size limit reached)");
        }
        Ok(())
    }

    /// `operand (op operand)*`, grouping to the left.
    fn left_assoc(
        &mut self,
        op_of: fn(&Tok) -> Option<BinOp>,
        operand: fn(&mut Self) -> PResult<Expr>,
    ) -> PResult<Expr> {
        let mut lhs = operand(self)?;
        while let Some(op) = op_of(self.peek()) {
            self.node()?;
            self.bump();
            let rhs = operand(self)?;
            let span = lhs.span.to(rhs.span);
            lhs = Expr {
                kind: ExprKind::Bin(op, Box::new(lhs), Box::new(rhs)),
                span,
            };
        }
        Ok(lhs)
    }

    fn atom(&mut self) -> PResult<Expr> {
        let span = self.span();
        let kind = match self.peek().clone() {
            Tok::Var(v) => {
                self.bump();
                ExprKind::Var(v)
            }
            Tok::Num { value, unit } => {
                self.bump();
                ExprKind::Num(value, unit)
            }
            Tok::Clock(ms) => {
                self.bump();
                ExprKind::Clock(ms)
            }
            Tok::PlusInf => {
                self.bump();
                ExprKind::PosInf
            }
            Tok::MinusInf => {
                self.bump();
                ExprKind::NegInf
            }
            Tok::Minus => {
                self.bump();
                self.depth += 1;
                if self.depth > MAX_DEPTH {
                    self.depth -= 1;
                    return self.err("a shallower expression (nesting limit reached)");
                }
                let inner = self.atom();
                self.depth -= 1;
                let inner = inner?;
                let span = span.to(inner.span);
                return Ok(Expr {
                    kind: ExprKind::Neg(Box::new(inner)),
                    span,
                });
            }
            Tok::LParen => {
                self.bump();
                let inner = self.expr()?;
                self.expect(Tok::RParen, "`)`")?;
                // Keep the parenthesised span so `(et - st)` points at its `(`.
                return Ok(Expr {
                    kind: inner.kind,
                    span: span.to(self.prev_span()),
                });
            }
            Tok::Ident(name) => {
                let id = self.ident("a name")?;
                if self.peek() == &Tok::LParen && self.peek_at(1) != &Tok::Eof {
                    self.bump();
                    let mut args = Vec::new();
                    if !self.eat(&Tok::RParen) {
                        loop {
                            args.push(self.expr()?);
                            if self.eat(&Tok::RParen) {
                                break;
                            }
                            self.expect(Tok::Comma, "`,` or `)`")?;
                        }
                    }
                    let span = span.to(self.prev_span());
                    return Ok(Expr {
                        kind: ExprKind::Call(id, args),
                        span,
                    });
                }
                ExprKind::Name(name)
            }
            _ => return self.err("a value, a variable, a number or `(`"),
        };
        Ok(Expr {
            kind,
            span: span.to(self.prev_span()),
        })
    }

    // ---------------------------------------------------------------- problems

    /// `problem NAME; domain NAME; item*`
    pub fn problem_file(&mut self) -> PResult<ProblemAst> {
        let name = self.header("problem", "the problem's name")?;
        let domain = self.header("domain", "the domain's name")?;
        let items = self.items_to_eof(Self::problem_item)?;
        Ok(ProblemAst {
            name,
            domain,
            items,
        })
    }

    fn problem_item(&mut self) -> PResult<ProblemItem> {
        let start = self.span();
        let kw = match self.peek() {
            Tok::Ident(s) => s.clone(),
            _ => String::new(),
        };
        match kw.as_str() {
            "start" => Ok(ProblemItem::Start(self.keyword_expr()?)),
            "horizon" => Ok(ProblemItem::Horizon(self.keyword_expr()?)),
            "home" => {
                self.bump();
                self.expect_kw("lat")?;
                let lat = self.expr()?;
                self.expect_kw("lon")?;
                let lon = self.expr()?;
                let alt = self.opt_kw_expr("alt")?;
                self.semi()?;
                Ok(ProblemItem::Home {
                    lat,
                    lon,
                    alt,
                    span: start.to(self.prev_span()),
                })
            }
            "object" => {
                self.bump();
                let (names, ty, position) = self.object_decl()?;
                Ok(ProblemItem::Object {
                    names,
                    ty,
                    position,
                })
            }
            "initial" => {
                self.bump();
                self.expect(Tok::LBrace, "`{`")?;
                let mut v = Vec::new();
                while !self.eat(&Tok::RBrace) {
                    v.push(self.init()?);
                }
                Ok(ProblemItem::Initial(v))
            }
            "resource" => {
                self.bump();
                let name = self.ident("a resource name")?;
                self.expect(Tok::Colon, "`:` and `level ...` / `capacity ...`")?;
                let mut items = Vec::new();
                loop {
                    let key = self.ident("`level` or `capacity`")?;
                    let value = self.expr()?;
                    let from = self.opt_kw_expr("from")?;
                    items.push(ResourceItemAst { key, value, from });
                    if !self.eat(&Tok::Comma) {
                        break;
                    }
                }
                self.semi()?;
                Ok(ProblemItem::Resource { name, items })
            }
            "goal" => {
                self.bump();
                self.goal().map(ProblemItem::Goal)
            }
            _ => self.err("`start`, `home`, `horizon`, `object`, `initial`, `resource` or `goal`"),
        }
    }

    /// `attr(args) = value [at time];`
    fn init(&mut self) -> PResult<InitAst> {
        let start = self.span();
        if self.peek() == &Tok::Eof {
            return self.err("an initial value `attr(args) = value;` or `}`");
        }
        let attr = self.attr_ref()?;
        self.expect(Tok::Rel(RelOp::Eq), "`=` and the value")?;
        let value = self.expr()?;
        let at = self.opt_kw_expr("at")?;
        self.semi()?;
        Ok(InitAst {
            attr,
            value,
            at,
            span: start.to(self.prev_span()),
        })
    }

    /// `NAME [external|internal] [priority N] { stmt* }` (after `goal`).
    pub fn goal(&mut self) -> PResult<GoalAst> {
        let name = self.ident("the goal's name")?;
        let kind = if self.is_kw("external") || self.is_kw("internal") {
            Some(self.ident("a goal kind")?)
        } else {
            None
        };
        let priority = self.opt_kw_expr("priority")?;
        let body = self.body()?;
        self.eat(&Tok::Semi);
        Ok(GoalAst {
            name,
            kind,
            priority,
            body,
        })
    }

    /// A lone goal declaration (`goal g6 { ... }`) and nothing after it.
    pub fn goal_only(&mut self) -> PResult<GoalAst> {
        self.expect_kw("goal")?;
        let g = self.goal()?;
        if self.peek() != &Tok::Eof {
            return self.err("the end of the goal");
        }
        Ok(g)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse_domain(text: &str) -> PResult<DomainAst> {
        Parser::new(Source::new("t", text))?.domain_file()
    }

    #[test]
    fn parses_fig3b_task() {
        let text = "domain d;\n task INIT_MVT_GENERATION() (st, et) {\n hold(ROBOT_STATUS(): STILL, (st, et));\n use(CAMERA(): 1, (st, et));\n event(MVT_INIT(): (F, IDLE_INIT), st);\n (et-st) in ]2, 60];\n }nonPreemptive\n";
        let d = parse_domain(text);
        let Ok(d) = d else { panic!("{d:?}") };
        let DomainItem::Task(t) = &d.items[0] else {
            panic!("not a task")
        };
        assert_eq!(t.body.len(), 4);
        assert_eq!(
            t.preemption.as_ref().map(|p| p.name.as_str()),
            Some("nonPreemptive")
        );
        assert!(
            matches!(&t.body[3], Stmt::In { set: InSet::Interval(i), .. } if i.lb_open && !i.ub_open)
        );
    }

    #[test]
    fn syntax_error_says_what_was_expected() {
        let e = parse_domain("domain d;\ntask t() (st, et) {\n  hold(A() x, (st, et));\n}\n");
        let e = e.err().map(|d| (d.line, d.col, d.message));
        assert_eq!(
            e,
            Some((3, 12, "expected `:` and a value, found `x`".to_string()))
        );
    }

    #[test]
    fn deep_nesting_is_an_error_not_a_crash() {
        let text = format!(
            "domain d; task t() (st) {{ ?x = {}1; }}",
            "(".repeat(10_000)
        );
        assert!(parse_domain(&text).is_err());
        let text = format!(
            "domain d; task t() (st) {{ ?x = {}1; }}",
            "-".repeat(10_000)
        );
        assert!(parse_domain(&text).is_err());
        // Long operator chains build deep trees too: bounded by the node budget.
        let chain = |n: usize| {
            format!(
                "domain d; task t() (st) {{ variable ?x; ?x = {}1; }}",
                "1 + ".repeat(n)
            )
        };
        let e = parse_domain(&chain(100_000)).err().map(|d| d.message);
        assert!(e.is_some_and(|m| m.contains("size limit")));
        assert!(parse_domain(&chain(200)).is_ok());
    }
}
