//! Domain semantic checks: syntax tree → [`Domain`]. Declarations may appear in any order (types and
//! constants first, then attributes and resources, then tasks). Errors are collected, not fatal.

use std::collections::HashMap;

use crate::model::{Domain, LogicalAttr, Object, ResourceAttr, ResourceKind, TypeId, TypeKind};

use super::ast::{DomainAst, DomainItem, Ident, PositionAst};
use super::diag::Span;
use super::eval::{self, Ctx};
use super::resolve_task;

/// Remembers where each name of one namespace was declared, to report duplicates.
#[derive(Default)]
pub struct Names(HashMap<String, Span>);

impl Names {
    /// Declares `id`; reports a duplicate (with the first declaration's line) and returns false.
    pub fn declare(&mut self, ctx: &mut Ctx<'_>, id: &Ident, what: &str) -> bool {
        if let Some(prev) = self.0.get(&id.name) {
            let line = ctx.src.error(*prev, "").line;
            ctx.err(
                id.span,
                format!("{what} `{}` is already declared (line {line})", id.name),
            );
            return false;
        }
        self.0.insert(id.name.clone(), id.span);
        true
    }
}

/// Looks up a type by name, reporting an unknown one.
pub fn type_ref(ctx: &mut Ctx<'_>, domain: &Domain, id: &Ident) -> Option<TypeId> {
    let t = domain.type_id(&id.name);
    if t.is_none() {
        let known: Vec<&str> = domain.types.iter().map(|t| t.name.as_str()).collect();
        ctx.err(
            id.span,
            format!("unknown type `{}` (known: {})", id.name, known.join(", ")),
        );
    }
    t
}

/// The type of declared objects (domain constants, problem objects): a known type, not an enumeration
/// (whose values are `enum_values`).
pub fn object_type(
    ctx: &mut Ctx<'_>,
    domain: &Domain,
    ty: &Ident,
    enum_values: &str,
) -> Option<TypeId> {
    let t = type_ref(ctx, domain, ty)?;
    if domain.ty(t).kind == TypeKind::Enum {
        ctx.err(
            ty.span,
            format!(
                "`{}` is an enumeration: its values are {enum_values}",
                ty.name
            ),
        );
        return None;
    }
    Some(t)
}

/// The logical attribute `a` names, with the right number of arguments; `resource_hint` says what to
/// write instead when `a` names a resource.
pub fn logical_attr(
    ctx: &mut Ctx<'_>,
    domain: &Domain,
    a: &super::ast::AttrRef,
    resource_hint: &str,
) -> Option<crate::model::AttrId> {
    let Some(id) = domain.attr_id(&a.name.name) else {
        let msg = if domain.resource_id(&a.name.name).is_some() {
            format!("`{}` is a resource: {resource_hint}", a.name.name)
        } else {
            let hint = super::lint::did_you_mean(
                &a.name.name,
                domain.attrs.iter().map(|x| x.name.as_str()),
            );
            format!("unknown attribute `{}`{hint}", a.name.name)
        };
        ctx.err(a.name.span, msg);
        return None;
    };
    let attr = domain.attr(id);
    if a.args.len() != attr.arity() {
        ctx.err(
            a.span,
            format!(
                "wrong number of arguments: `{}` takes {}, found {}",
                attr.name,
                attr.arity(),
                a.args.len()
            ),
        );
        return None;
    }
    Some(id)
}

/// Evaluates `at (e, n[, u])` / `at lat .. lon .. [alt ..]`.
pub fn position(ctx: &mut Ctx<'_>, p: &PositionAst) -> Option<crate::model::Position> {
    use crate::model::Position;
    match p {
        PositionAst::Local(coords, span) => {
            if coords.len() < 2 || coords.len() > 3 {
                ctx.err(
                    *span,
                    "a local position is `(east, north)` or `(east, north, up)` in metres",
                );
                return None;
            }
            let v: Vec<Option<f64>> = coords.iter().map(|c| eval::num(ctx, c, false)).collect();
            let east = v[0]?;
            let north = v[1]?;
            let up = match v.get(2) {
                Some(u) => (*u)?,
                None => 0.0,
            };
            Some(Position::Local { east, north, up })
        }
        PositionAst::Geo { lat, lon, alt, .. } => {
            let g = geo(ctx, lat, lon, alt.as_deref())?;
            Some(Position::Geo(g))
        }
    }
}

/// Latitude / longitude (degrees, range-checked) and altitude (metres).
pub fn geo(
    ctx: &mut Ctx<'_>,
    lat: &super::ast::Expr,
    lon: &super::ast::Expr,
    alt: Option<&super::ast::Expr>,
) -> Option<crate::model::GeoPoint> {
    let la = eval::num(ctx, lat, false);
    let lo = eval::num(ctx, lon, false);
    let al = match alt {
        Some(a) => eval::num(ctx, a, false),
        None => Some(0.0),
    };
    let (la, lo, al) = (la?, lo?, al?);
    if !(-90.0..=90.0).contains(&la) {
        ctx.err(lat.span, "latitude must be within [-90, 90] degrees");
        return None;
    }
    if !(-180.0..=180.0).contains(&lo) {
        ctx.err(lon.span, "longitude must be within [-180, 180] degrees");
        return None;
    }
    Some(crate::model::GeoPoint {
        lat: la,
        lon: lo,
        alt: al,
    })
}

pub fn resolve(ctx: &mut Ctx<'_>, ast: &DomainAst) -> Domain {
    let mut d = Domain::new(ast.name.name.clone());
    d.source = Some(ctx.src.file.to_string());
    let mut types = Names::default();
    let mut objects = Names::default();
    types.0.insert("bool".into(), Span::default());
    for name in ["false", "true"] {
        objects.0.insert(name.into(), Span::default());
    }
    // Pass 1: types, then constants (whose types may be declared later in the file).
    for item in &ast.items {
        if let DomainItem::Type { name, members } = item {
            if !types.declare(ctx, name, "type") {
                continue;
            }
            let kind = if members.is_some() {
                TypeKind::Enum
            } else {
                TypeKind::Object
            };
            let t = d.add_type(&name.name, kind);
            d.types[t.index()].line = Some(ctx.src.line(name.span.start));
            for m in members.iter().flatten() {
                if objects.declare(ctx, m, "value") {
                    d.add_enum_member(t, &m.name);
                }
            }
        }
    }
    for item in &ast.items {
        if let DomainItem::Constant {
            names,
            ty,
            position: pos,
        } = item
        {
            let Some(t) = object_type(ctx, &d, ty, "listed in its `type` declaration") else {
                continue;
            };
            let p = pos.as_ref().and_then(|p| position(ctx, p));
            for n in names {
                if objects.declare(ctx, n, "object") {
                    d.add_object(Object {
                        name: n.name.clone(),
                        ty: t,
                        position: p,
                    });
                }
            }
        }
    }
    // Pass 2: attributes and resources share one namespace (both are "attributes" in IxTeT).
    let mut attrs = Names::default();
    for item in &ast.items {
        match item {
            DomainItem::Attribute {
                name,
                params,
                value_ty,
            } => {
                let mut pnames = Names::default();
                let mut ps = Vec::new();
                for (v, t) in params {
                    pnames.declare(ctx, v, "parameter");
                    if let Some(t) = type_ref(ctx, &d, t) {
                        ps.push((v.name.clone(), t));
                    }
                }
                let vt = type_ref(ctx, &d, value_ty);
                if !attrs.declare(ctx, name, "attribute") {
                    continue;
                }
                if let (Some(vt), true) = (vt, ps.len() == params.len()) {
                    d.add_attr(LogicalAttr {
                        name: name.name.clone(),
                        params: ps,
                        value_type: vt,
                        line: Some(ctx.src.line(name.span.start)),
                    });
                }
            }
            DomainItem::Resource {
                name,
                kind,
                capacity,
            } => {
                if !attrs.declare(ctx, name, "resource") {
                    continue;
                }
                let kind_v = match kind.name.as_str() {
                    "unary" => ResourceKind::Unary,
                    "reservoir" => ResourceKind::Reservoir,
                    _ => {
                        ctx.err(
                            kind.span,
                            format!("expected `unary` or `reservoir`, found `{}`", kind.name),
                        );
                        continue;
                    }
                };
                let cap = match (kind_v, capacity) {
                    (ResourceKind::Unary, None) => 1.0,
                    (ResourceKind::Unary, Some(c)) => {
                        ctx.err(c.span, "a unary resource has capacity 1; remove `capacity`");
                        continue;
                    }
                    (ResourceKind::Reservoir, None) => {
                        ctx.err(name.span, "a reservoir needs a `capacity` (e.g. `resource storage: reservoir capacity 3;`)");
                        continue;
                    }
                    (ResourceKind::Reservoir, Some(c)) => match eval::num(ctx, c, false) {
                        Some(v) if v >= 0.0 => v,
                        Some(_) => {
                            ctx.err(c.span, "a capacity cannot be negative");
                            continue;
                        }
                        None => continue,
                    },
                };
                d.add_resource(ResourceAttr {
                    name: name.name.clone(),
                    kind: kind_v,
                    capacity: cap,
                    line: Some(ctx.src.line(name.span.start)),
                });
            }
            _ => {}
        }
    }
    // Pass 3: tasks.
    let mut tasks = Names::default();
    for item in &ast.items {
        if let DomainItem::Task(t) = item {
            if !tasks.declare(ctx, &t.name, "task") {
                continue;
            }
            if let Some(task) = resolve_task::resolve(ctx, &d, t) {
                d.add_task(task);
            }
        }
    }
    d
}
