//! The executive's files import each other without a circle (issue 36): each file's imports are drawn
//! from its source (`super::x` and `crate::exec::x` paths outside comments) and the graph is searched for
//! a cycle. A circle means two files that cannot be read, changed or tested one without the other.

use std::collections::{BTreeMap, BTreeSet};

/// File stem → the stems of the executive's files it names.
fn imports() -> BTreeMap<String, BTreeSet<String>> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src/exec");
    let mut sources = BTreeMap::new();
    for entry in std::fs::read_dir(&dir).expect("src/exec is readable") {
        let path = entry.expect("a directory entry").path();
        if path.extension().is_some_and(|e| e == "rs") {
            let stem = path.file_stem().expect("a file name").to_string_lossy();
            let text = std::fs::read_to_string(&path).expect("a source file");
            sources.insert(stem.into_owned(), text);
        }
    }
    let stems: BTreeSet<String> = sources.keys().cloned().collect();
    sources
        .iter()
        .map(|(stem, text)| (stem.clone(), named_files(text, &stems, stem)))
        .collect()
}

/// The files of `stems` that `text` reaches through `super::` or `crate::exec::`, comments left out.
fn named_files(text: &str, stems: &BTreeSet<String>, own: &str) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    for line in text.lines() {
        let code = line.split("//").next().unwrap_or("");
        for prefix in ["super::", "crate::exec::"] {
            for (i, _) in code.match_indices(prefix) {
                let rest = &code[i + prefix.len()..];
                let name: String = rest
                    .chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect();
                if name != own && stems.contains(&name) {
                    out.insert(name);
                }
            }
        }
    }
    out
}

/// A circle of the graph, as the files along it, if there is one.
fn find_circle(graph: &BTreeMap<String, BTreeSet<String>>) -> Option<Vec<String>> {
    #[derive(Clone, Copy, PartialEq)]
    enum Mark {
        Open,
        Done,
    }
    fn visit(
        n: &str,
        graph: &BTreeMap<String, BTreeSet<String>>,
        marks: &mut BTreeMap<String, Mark>,
        path: &mut Vec<String>,
    ) -> Option<Vec<String>> {
        match marks.get(n) {
            Some(Mark::Done) => return None,
            Some(Mark::Open) => {
                let from = path.iter().position(|p| p == n).unwrap_or(0);
                let mut circle = path[from..].to_vec();
                circle.push(n.to_string());
                return Some(circle);
            }
            None => {}
        }
        marks.insert(n.to_string(), Mark::Open);
        path.push(n.to_string());
        for m in graph.get(n).into_iter().flatten() {
            if let Some(c) = visit(m, graph, marks, path) {
                return Some(c);
            }
        }
        path.pop();
        marks.insert(n.to_string(), Mark::Done);
        None
    }
    let mut marks = BTreeMap::new();
    graph
        .keys()
        .find_map(|n| visit(n, graph, &mut marks, &mut Vec::new()))
}

#[test]
fn the_executive_files_import_each_other_without_a_circle() {
    let graph = imports();
    assert!(graph.len() > 30, "the executive's files were not found");
    assert!(
        graph["sense"].contains("executive"),
        "the import reader misses plain `use super::x` lines"
    );
    if let Some(circle) = find_circle(&graph) {
        panic!("import circle: {}", circle.join(" -> "));
    }
}

#[test]
fn a_circle_is_found_when_there_is_one() {
    let stems: BTreeSet<String> = ["a", "b", "c"].iter().map(|s| s.to_string()).collect();
    let graph: BTreeMap<String, BTreeSet<String>> = [
        (
            "a",
            "use super::b::X;\n// super::c in a comment is no import",
        ),
        ("b", "fn f() { super::c::g() }"),
        ("c", "use crate::exec::a::Y;"),
    ]
    .iter()
    .map(|(n, t)| (n.to_string(), named_files(t, &stems, n)))
    .collect();
    assert_eq!(
        find_circle(&graph),
        Some(vec!["a".into(), "b".into(), "c".into(), "a".into()])
    );
    let mut cut = graph.clone();
    cut.insert("c".into(), BTreeSet::new());
    assert_eq!(find_circle(&cut), None);
}
