//! What is legal but most likely not what the author meant, and names close to a mistyped one: the
//! warnings `check` prints and the "did you mean" of unknown names.

use std::collections::HashSet;

use super::ast::{Expr, ExprKind};
use super::diag::Span;
use super::eval::Ctx;
use crate::model::{AttrId, Domain, Problem};

/// The candidate a mistyped `name` most likely meant: the same but for case, else the closest within an
/// edit distance of 2 (1 for names of 4 characters or fewer).
pub fn suggest<'a>(name: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    let lower = name.to_lowercase();
    let mut best: Option<(usize, &str)> = None;
    for c in candidates {
        if c == name {
            continue;
        }
        if c.to_lowercase() == lower {
            return Some(c);
        }
        let d = edit_distance(&lower, &c.to_lowercase());
        if best.is_none_or(|(bd, _)| d < bd) {
            best = Some((d, c));
        }
    }
    let limit = if name.chars().count() <= 4 { 1 } else { 2 };
    best.filter(|&(d, _)| d <= limit).map(|(_, c)| c)
}

/// ", did you mean `x`?" or nothing.
pub fn did_you_mean<'a>(name: &str, candidates: impl IntoIterator<Item = &'a str>) -> String {
    suggest(name, candidates).map_or_else(String::new, |c| format!(": did you mean `{c}`?"))
}

fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut prev = row[0];
        row[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let cur = row[j + 1];
            row[j + 1] = (prev + usize::from(ca != cb)).min(row[j] + 1).min(cur + 1);
            prev = cur;
        }
    }
    row[b.len()]
}

/// A time written without a unit is read as seconds: `horizon 20;` is 20 s, most likely meant as minutes.
pub fn unit_less_time(ctx: &mut Ctx<'_>, e: &Expr, what: &str) {
    if let ExprKind::Num(v, None) = e.kind {
        ctx.warn(
            e.span,
            format!(
                "`{what} {v}` has no unit and is read as {v} s; write `{v}s`, `{v}min`, `{v}h` or a clock time such as `20:00`"
            ),
        );
    }
}

/// Attributes that tasks read (a `hold`, or the value an `event` changes from) need a value to start
/// from: with none in `initial` (nor a predicted change), no plan can use those tasks, and `plan` fails
/// with "no resolver for open condition …". Warned at `span` (the problem's name).
pub fn missing_initial_values(ctx: &mut Ctx<'_>, domain: &Domain, p: &Problem, span: Span) {
    let mut given: HashSet<AttrId> = p.initial.iter().map(|f| f.attr).collect();
    given.extend(p.defaults.iter().map(|f| f.attr));
    given.extend(p.exogenous.iter().map(|f| f.fact.attr));
    let mut needed: Vec<(AttrId, Vec<&str>)> = Vec::new();
    for task in &domain.tasks {
        let read = task
            .holds
            .iter()
            .map(|h| h.attr)
            .chain(task.events.iter().map(|e| e.attr));
        for a in read {
            if given.contains(&a) {
                continue;
            }
            match needed.iter_mut().find(|(x, _)| *x == a) {
                Some((_, tasks)) if !tasks.contains(&task.name.as_str()) => {
                    tasks.push(task.name.as_str())
                }
                Some(_) => {}
                None => needed.push((a, vec![task.name.as_str()])),
            }
        }
    }
    for (a, tasks) in needed {
        let attr = domain.attr(a);
        let args = if attr.arity() == 0 { "" } else { "*" };
        let args = vec![args; attr.arity().max(1)].join(", ");
        ctx.warn(
            span,
            format!(
                "`{}` has no initial value, so task{} {} can never be planned; add `{}({}) = …;` to `initial`",
                attr.name,
                if tasks.len() == 1 { "" } else { "s" },
                tasks
                    .iter()
                    .map(|t| format!("`{t}`"))
                    .collect::<Vec<_>>()
                    .join(", "),
                attr.name,
                if attr.arity() == 0 { String::new() } else { args }
            ),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn suggestions_are_close_names_only() {
        assert_eq!(suggest("True", ["true", "false"]), Some("true"));
        assert_eq!(
            suggest("AT_ROBOTT", ["AT_ROBOT", "PICTURE"]),
            Some("AT_ROBOT")
        );
        assert_eq!(suggest("PTU", ["AT_ROBOT", "PICTURE"]), None);
        assert_eq!(suggest("l9", ["l1", "l2"]), Some("l1"));
        assert_eq!(suggest("xyz", Vec::<&str>::new()), None);
        assert_eq!(edit_distance("kitten", "sitting"), 3);
    }
}
