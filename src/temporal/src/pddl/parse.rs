//! From s-expressions to the PDDL syntax trees ([`super::ast`]): the domain and problem grammar of PDDL 2.1
//! level 3 with timed initial literals. What the reader does not support is refused at its place.

use super::ast::{
    Action, Arg, Atom, Cmp, Domain, Effect, Init, Lit, Metric, NExpr, Name, NumOp, Problem, Typed,
    When,
};
use super::sexpr::{self, Span, Sx};
use super::{PddlError, Src};

type R<T> = Result<T, PddlError>;

/// Requirements the reader and the translation handle (others are refused where they are written).
const SUPPORTED: &[&str] = &[
    ":strips",
    ":typing",
    ":negative-preconditions",
    ":equality",
    ":durative-actions",
    ":duration-inequalities",
    ":fluents",
    ":numeric-fluents",
    ":timed-initial-literals",
];

struct P<'a> {
    src: &'a Src,
}

impl P<'_> {
    fn err<T>(&self, span: Span, msg: impl Into<String>) -> R<T> {
        Err(self.src.error(span.start, msg))
    }

    fn list<'s>(&self, sx: &'s Sx, what: &str) -> R<&'s [Sx]> {
        match sx.list() {
            Some(l) => Ok(l),
            None => self.err(
                sx.span,
                format!("expected {what}, found `{}`", sx.atom().unwrap_or("")),
            ),
        }
    }

    fn name(&self, sx: &Sx, what: &str) -> R<Name> {
        match sx.atom() {
            Some(a) if !a.starts_with('?') && !a.starts_with(':') => Ok(Name {
                name: a.to_string(),
                span: sx.span,
            }),
            _ => self.err(sx.span, format!("expected {what}")),
        }
    }

    fn var(&self, sx: &Sx) -> R<Name> {
        match sx.atom() {
            Some(a) if a.starts_with('?') && a.len() > 1 => Ok(Name {
                name: a.to_string(),
                span: sx.span,
            }),
            _ => self.err(sx.span, "expected a `?variable`"),
        }
    }

    /// `a b - t c - (either u v) d`: `vars` says whether the names are `?variables`.
    fn typed(&self, items: &[Sx], vars: bool) -> R<Vec<Typed>> {
        let mut out = Vec::new();
        let mut pending: Vec<Name> = Vec::new();
        let mut i = 0;
        while i < items.len() {
            if items[i].atom() == Some("-") {
                let Some(t) = items.get(i + 1) else {
                    return self.err(items[i].span, "a type must follow `-`");
                };
                let types = if t.head() == Some("either") {
                    let l = self.list(t, "a type")?;
                    l[1..]
                        .iter()
                        .map(|x| self.name(x, "a type name"))
                        .collect::<R<Vec<_>>>()?
                } else {
                    vec![self.name(t, "a type name")?]
                };
                if pending.is_empty() {
                    return self.err(items[i].span, "no name before this `-`");
                }
                for n in pending.drain(..) {
                    out.push(Typed {
                        name: n,
                        types: types.clone(),
                    });
                }
                i += 2;
                continue;
            }
            pending.push(if vars {
                self.var(&items[i])?
            } else {
                self.name(&items[i], "a name")?
            });
            i += 1;
        }
        for n in pending {
            let span = n.span;
            out.push(Typed {
                name: n,
                types: vec![Name {
                    name: "object".into(),
                    span,
                }],
            });
        }
        Ok(out)
    }

    fn arg(&self, sx: &Sx) -> R<Arg> {
        match sx.atom() {
            Some(a) if a.starts_with('?') => Ok(Arg::Var(self.var(sx)?)),
            Some(_) => Ok(Arg::Const(self.name(sx, "a constant")?)),
            None => self.err(
                sx.span,
                "expected a `?variable` or a constant, found a list",
            ),
        }
    }

    fn atom(&self, sx: &Sx) -> R<Atom> {
        let l = self.list(sx, "an atom `(predicate args...)`")?;
        let Some(h) = l.first() else {
            return self.err(sx.span, "empty list where an atom is expected");
        };
        let pred = self.name(h, "a predicate or function name")?;
        if is_keyword_head(&pred.name) {
            return self.err(h.span, format!("`{}` is not supported here", pred.name));
        }
        Ok(Atom {
            pred,
            args: l[1..].iter().map(|a| self.arg(a)).collect::<R<_>>()?,
            span: sx.span,
        })
    }

    /// A function term: `(f args...)`, or a 0-ary function written without parentheses (`total-fuel-used`,
    /// which PDDL 2.1 allows).
    fn fluent(&self, sx: &Sx) -> R<Atom> {
        match sx.atom() {
            Some(a) if !a.starts_with('?') && a.parse::<f64>().is_err() => Ok(Atom {
                pred: self.name(sx, "a function name")?,
                args: Vec::new(),
                span: sx.span,
            }),
            _ => self.atom(sx),
        }
    }

    fn nexpr(&self, sx: &Sx) -> R<NExpr> {
        if let Some(a) = sx.atom() {
            if a == "?duration" {
                return Ok(NExpr::Duration(sx.span));
            }
            return match a.parse::<f64>() {
                Ok(v) if v.is_finite() => Ok(NExpr::Num(v, sx.span)),
                Err(_) if !a.starts_with('?') => Ok(NExpr::Fluent(self.fluent(sx)?)),
                _ => self.err(
                    sx.span,
                    format!("expected a number or a numeric expression, found `{a}`"),
                ),
            };
        }
        let l = self.list(sx, "a numeric expression")?;
        let op = l.first().and_then(Sx::atom).unwrap_or("");
        match (op, l.len()) {
            ("-", 2) => Ok(NExpr::Neg(Box::new(self.nexpr(&l[1])?), sx.span)),
            ("+" | "-" | "*" | "/", n) if n >= 3 => {
                let c = op.chars().next().unwrap_or('+');
                let mut acc = self.nexpr(&l[1])?;
                for x in &l[2..] {
                    acc = NExpr::Bin(c, Box::new(acc), Box::new(self.nexpr(x)?), sx.span);
                }
                Ok(acc)
            }
            ("+" | "-" | "*" | "/", _) => self.err(sx.span, format!("`{op}` needs two operands")),
            _ => Ok(NExpr::Fluent(self.atom(sx)?)),
        }
    }

    /// A goal description: a conjunction of literals (`or`, quantifiers and implications are refused).
    fn gd(&self, sx: &Sx, out: &mut Vec<Lit>) -> R<()> {
        let l = self.list(sx, "a condition `(...)`")?;
        let head = l.first().and_then(Sx::atom).unwrap_or("");
        match head {
            "and" => {
                for x in &l[1..] {
                    self.gd(x, out)?;
                }
                Ok(())
            }
            "not" => {
                let [_, inner] = l else {
                    return self.err(sx.span, "`not` takes one condition");
                };
                match inner.head() {
                    Some("=") if is_symbolic_eq(inner) => {
                        let il = self.list(inner, "(= a b)")?;
                        out.push(self.equal(il, false, sx.span)?);
                        Ok(())
                    }
                    Some("<" | "<=" | "=" | ">=" | ">") => self.err(
                        inner.span,
                        "a negated numeric comparison is not supported: compare the other way",
                    ),
                    _ => {
                        out.push(Lit::Neg(self.atom(inner)?));
                        Ok(())
                    }
                }
            }
            "=" if is_symbolic_eq(sx) => {
                out.push(self.equal(l, true, sx.span)?);
                Ok(())
            }
            "<" | "<=" | "=" | ">=" | ">" => {
                let [_, a, b] = l else {
                    return self.err(sx.span, format!("`{head}` compares two expressions"));
                };
                out.push(Lit::Compare(
                    cmp(head),
                    self.nexpr(a)?,
                    self.nexpr(b)?,
                    sx.span,
                ));
                Ok(())
            }
            "or" | "imply" | "exists" | "forall" | "preference" | "when" => self.err(
                sx.span,
                format!("`{head}` is not supported: conditions are conjunctions of literals"),
            ),
            _ => {
                out.push(Lit::Pos(self.atom(sx)?));
                Ok(())
            }
        }
    }

    /// `(= a b)` (checked by `is_symbolic_eq`), or its negation.
    fn equal(&self, l: &[Sx], positive: bool, span: Span) -> R<Lit> {
        Ok(Lit::Equal(
            self.arg(&l[1])?,
            self.arg(&l[2])?,
            positive,
            span,
        ))
    }

    /// A durative action's condition: a conjunction of `(at start|at end|over all GD)`.
    fn timed_gd(&self, sx: &Sx, out: &mut Vec<(When, Lit)>) -> R<()> {
        self.conjuncts(sx, "a condition `(...)`", &mut |sx| {
            let Some((when, body)) = self.when(sx)? else {
                return self.err(sx.span, "a durative action's condition is `(at start ...)`, `(at end ...)` or `(over all ...)`");
            };
            let mut lits = Vec::new();
            self.gd(body, &mut lits)?;
            out.extend(lits.into_iter().map(|x| (when, x)));
            Ok(())
        })
    }

    /// Hands each conjunct of `sx` to `each`: nested `(and ...)` are flattened, `()` has none; `what` is
    /// what a conjunct looks like, for messages.
    fn conjuncts(&self, sx: &Sx, what: &str, each: &mut dyn FnMut(&Sx) -> R<()>) -> R<()> {
        let l = self.list(sx, what)?;
        if l.is_empty() {
            return Ok(());
        }
        if sx.head() == Some("and") {
            for x in &l[1..] {
                self.conjuncts(x, what, each)?;
            }
            return Ok(());
        }
        each(sx)
    }

    /// `(at start X)`, `(at end X)`, `(over all X)` → the time specifier and `X`.
    fn when<'s>(&self, sx: &'s Sx) -> R<Option<(When, &'s Sx)>> {
        let Some(l) = sx.list() else { return Ok(None) };
        let w = match (l.first().and_then(Sx::atom), l.get(1).and_then(Sx::atom)) {
            (Some("at"), Some("start")) => When::Start,
            (Some("at"), Some("end")) => When::End,
            (Some("over"), Some("all")) => When::OverAll,
            _ => return Ok(None),
        };
        match l {
            [_, _, body] if body.list().is_some() => Ok(Some((w, body))),
            _ => self.err(sx.span, "a time specifier takes one condition or effect"),
        }
    }

    fn effect(&self, sx: &Sx, when: When, out: &mut Vec<(When, Effect)>) -> R<()> {
        let l = self.list(sx, "an effect `(...)`")?;
        let head = l.first().and_then(Sx::atom).unwrap_or("");
        match head {
            "and" => {
                for x in &l[1..] {
                    self.effect(x, when, out)?;
                }
                Ok(())
            }
            "not" => {
                let [_, inner] = l else {
                    return self.err(sx.span, "`not` takes one atom");
                };
                out.push((when, Effect::Del(self.atom(inner)?)));
                Ok(())
            }
            "assign" | "increase" | "decrease" | "scale-up" | "scale-down" => {
                let [_, f, e] = l else {
                    return self.err(
                        sx.span,
                        format!("`{head}` takes a function and an expression"),
                    );
                };
                let op = match head {
                    "assign" => NumOp::Assign,
                    "increase" => NumOp::Increase,
                    "decrease" => NumOp::Decrease,
                    "scale-up" => NumOp::ScaleUp,
                    _ => NumOp::ScaleDown,
                };
                out.push((
                    when,
                    Effect::Num(op, self.fluent(f)?, self.nexpr(e)?, sx.span),
                ));
                Ok(())
            }
            "when" | "forall" => self.err(
                sx.span,
                format!("`{head}` (conditional / universal effects) is not supported"),
            ),
            _ => {
                out.push((when, Effect::Add(self.atom(sx)?)));
                Ok(())
            }
        }
    }

    fn timed_effect(&self, sx: &Sx, out: &mut Vec<(When, Effect)>) -> R<()> {
        self.conjuncts(sx, "an effect `(...)`", &mut |sx| match self.when(sx)? {
            Some((When::OverAll, _)) => self.err(
                sx.span,
                "continuous effects (`over all` effects with `#t`) are not supported",
            ),
            Some((w, body)) => self.effect(body, w, out),
            None => self.err(
                sx.span,
                "a durative action's effect is `(at start ...)` or `(at end ...)`",
            ),
        })
    }

    fn duration(&self, sx: &Sx, out: &mut Vec<(Cmp, NExpr, Span)>) -> R<()> {
        let l = self.list(sx, "a duration constraint `(= ?duration ...)`")?;
        match l.first().and_then(Sx::atom) {
            Some("and") => {
                for x in &l[1..] {
                    self.duration(x, out)?;
                }
                Ok(())
            }
            Some(op @ ("=" | "<=" | ">=" | "<" | ">")) => {
                let [_, d, e] = l else {
                    return self.err(sx.span, "a duration constraint is `(op ?duration expression)`");
                };
                if d.atom() != Some("?duration") {
                    return self.err(d.span, "expected `?duration`");
                }
                let c = match op {
                    "<" => Cmp::Le,
                    ">" => Cmp::Ge,
                    o => cmp(o),
                };
                out.push((c, self.nexpr(e)?, sx.span));
                Ok(())
            }
            Some("at") => self.err(sx.span, "time-specified duration constraints are not supported"),
            _ => self.err(sx.span, "a duration constraint is `(= ?duration e)`, `(<= ?duration e)` or `(>= ?duration e)`"),
        }
    }

    fn action(&self, sx: &Sx, durative: bool) -> R<Action> {
        let l = self.list(sx, "an action")?;
        let Some(name) = l.get(1) else {
            return self.err(sx.span, "the action needs a name");
        };
        let mut a = Action {
            name: self.name(name, "the action's name")?,
            params: Vec::new(),
            duration: Vec::new(),
            conditions: Vec::new(),
            effects: Vec::new(),
            durative,
            span: sx.span,
        };
        let mut i = 2;
        while i < l.len() {
            let key = l[i].atom().unwrap_or("");
            let Some(val) = l.get(i + 1) else {
                return self.err(l[i].span, format!("`{key}` needs a value"));
            };
            match key {
                ":parameters" => {
                    a.params = self.typed(self.list(val, "a parameter list")?, true)?
                }
                ":duration" if durative => self.duration(val, &mut a.duration)?,
                ":condition" if durative => self.timed_gd(val, &mut a.conditions)?,
                ":effect" if durative => self.timed_effect(val, &mut a.effects)?,
                ":precondition" if !durative => {
                    let mut lits = Vec::new();
                    self.gd(val, &mut lits)?;
                    a.conditions = lits.into_iter().map(|x| (When::Start, x)).collect();
                }
                ":effect" => self.effect(val, When::Start, &mut a.effects)?,
                _ => return self.err(l[i].span, format!("unexpected `{key}` in an action")),
            }
            i += 2;
        }
        if durative && a.duration.is_empty() {
            return self.err(sx.span, "a durative action needs a `:duration`");
        }
        Ok(a)
    }

    /// `(define (KIND name) sections...)` → the name and the sections.
    fn define<'s>(&self, top: &'s [Sx], kind: &str) -> R<(Name, &'s [Sx])> {
        let Some(def) = top.first() else {
            return self.err(
                Span::default(),
                format!("empty file: expected `(define ({kind} ...) ...)`"),
            );
        };
        if let Some(extra) = top.get(1) {
            return self.err(extra.span, "text after the end of the definition");
        }
        let l = self.list(def, "`(define ...)`")?;
        if def.head() != Some("define") {
            return self.err(def.span, "expected `(define ...)`");
        }
        let Some(h) = l.get(1) else {
            return self.err(def.span, format!("expected `({kind} NAME)` after `define`"));
        };
        let hl = self.list(h, &format!("`({kind} NAME)`"))?;
        match hl {
            [k, n] if k.atom() == Some(kind) => Ok((self.name(n, "a name")?, &l[2..])),
            _ => self.err(h.span, format!("expected `({kind} NAME)`")),
        }
    }
}

fn cmp(op: &str) -> Cmp {
    match op {
        "<" => Cmp::Lt,
        "<=" => Cmp::Le,
        ">=" => Cmp::Ge,
        ">" => Cmp::Gt,
        _ => Cmp::Eq,
    }
}

/// `(= a b)` between two objects (not numbers, not lists).
fn is_symbolic_eq(sx: &Sx) -> bool {
    matches!(sx.list(), Some([_, a, b]) if [a, b].iter().all(|x| x.atom().is_some_and(|s| s.parse::<f64>().is_err() && s != "?duration")))
}

fn is_keyword_head(h: &str) -> bool {
    matches!(
        h,
        "and" | "or" | "not" | "imply" | "exists" | "forall" | "when"
    )
}

/// Parses a domain file.
pub fn domain(src: &Src) -> R<Domain> {
    let p = P { src };
    let top = sexpr::read(src)?;
    let (name, sections) = p.define(&top, "domain")?;
    let mut d = Domain {
        name,
        ..Domain::default()
    };
    for s in sections {
        let l = p.list(s, "a section `(:keyword ...)`")?;
        let key = s.head().unwrap_or("");
        match key {
            ":requirements" => {
                for r in &l[1..] {
                    let n = r.atom().unwrap_or("");
                    if !SUPPORTED.contains(&n) {
                        return p.err(
                            r.span,
                            format!(
                                "requirement `{n}` is not supported (supported: {})",
                                SUPPORTED.join(" ")
                            ),
                        );
                    }
                    d.requirements.push(Name {
                        name: n.into(),
                        span: r.span,
                    });
                }
            }
            ":types" => {
                for t in p.typed(&l[1..], false)? {
                    let Some(parent) = t.types.first().cloned() else {
                        continue;
                    };
                    if t.types.len() > 1 {
                        return p.err(t.name.span, "a type cannot be a subtype of `(either ...)`");
                    }
                    d.types.push((t.name, parent));
                }
            }
            ":constants" => d.constants = p.typed(&l[1..], false)?,
            ":predicates" | ":functions" => {
                for x in &l[1..] {
                    if x.atom() == Some("-") || x.atom().is_some() {
                        // `(:functions (f ?x) - number)`: the value type is always a number.
                        if x.atom() == Some("number") || x.atom() == Some("-") {
                            continue;
                        }
                        return p.err(x.span, "expected `(name ?params...)`");
                    }
                    let xl = p.list(x, "(name ?params...)")?;
                    let Some(h) = xl.first() else {
                        return p.err(x.span, "empty declaration");
                    };
                    let decl = (p.name(h, "a name")?, p.typed(&xl[1..], true)?);
                    if key == ":predicates" {
                        d.predicates.push(decl);
                    } else {
                        d.functions.push(decl);
                    }
                }
            }
            ":durative-action" => d.actions.push(p.action(s, true)?),
            ":action" => d.actions.push(p.action(s, false)?),
            _ => {
                return p.err(s.span, format!("section `{key}` is not supported"));
            }
        }
    }
    Ok(d)
}

/// Parses a problem file.
pub fn problem(src: &Src) -> R<Problem> {
    let p = P { src };
    let top = sexpr::read(src)?;
    let (name, sections) = p.define(&top, "problem")?;
    let mut pr = Problem {
        name,
        ..Problem::default()
    };
    let mut has_domain = false;
    for s in sections {
        let l = p.list(s, "a section `(:keyword ...)`")?;
        let key = s.head().unwrap_or("");
        match key {
            ":domain" => {
                let [_, n] = l else {
                    return p.err(s.span, "expected `(:domain NAME)`");
                };
                pr.domain = p.name(n, "the domain's name")?;
                has_domain = true;
            }
            ":requirements" => {}
            ":objects" => pr.objects = p.typed(&l[1..], false)?,
            ":init" => {
                for x in &l[1..] {
                    pr.init.push(init(&p, x)?);
                }
            }
            ":goal" => {
                let [_, g] = l else {
                    return p.err(s.span, "expected `(:goal CONDITION)`");
                };
                p.gd(g, &mut pr.goal)?;
            }
            ":metric" => {
                let [_, dir, e] = l else {
                    return p.err(s.span, "expected `(:metric minimize|maximize EXPRESSION)`");
                };
                let minimize = match dir.atom() {
                    Some("minimize") => true,
                    Some("maximize") => false,
                    _ => return p.err(dir.span, "expected `minimize` or `maximize`"),
                };
                pr.metric = Some(Metric {
                    minimize,
                    expr: p.nexpr(e)?,
                    span: s.span,
                });
            }
            _ => return p.err(s.span, format!("section `{key}` is not supported")),
        }
    }
    if !has_domain {
        return p.err(top[0].span, "the problem needs `(:domain NAME)`");
    }
    Ok(pr)
}

fn init(p: &P, x: &Sx) -> R<Init> {
    let l = p.list(x, "an initial fact `(...)`")?;
    match l {
        [h, t, lit] if h.atom() == Some("at") && lit.list().is_some() => {
            let at = match t.atom().map(str::parse::<f64>) {
                Some(Ok(v)) if v.is_finite() && v >= 0.0 => v,
                _ => {
                    return p.err(
                        t.span,
                        "a timed initial literal's date is a number of seconds >= 0",
                    )
                }
            };
            if lit.head() == Some("not") {
                let ll = p.list(lit, "(not atom)")?;
                let [_, a] = ll else {
                    return p.err(lit.span, "`not` takes one atom");
                };
                Ok(Init::NotAtom(p.atom(a)?, at))
            } else {
                Ok(Init::Atom(p.atom(lit)?, Some(at)))
            }
        }
        [h, f, v] if h.atom() == Some("=") => {
            let val = match v.atom().map(str::parse::<f64>) {
                Some(Ok(v)) if v.is_finite() => v,
                _ => return p.err(v.span, "expected a number"),
            };
            Ok(Init::Value(p.fluent(f)?, val))
        }
        _ if x.head() == Some("not") => p.err(
            x.span,
            "negative initial facts are implicit (closed world): leave them out",
        ),
        _ => Ok(Init::Atom(p.atom(x)?, None)),
    }
}
