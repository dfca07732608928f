//! The layering of `src/`: every module path `crate::X` in a layer's
//! non-test code (doc links included) names a layer at or below its own,
//! and the files inside one layer import each other without a cycle.
//! The layers, bottom first, are [`LAYERS`]; the crate root (`lib.rs`)
//! re-exports from all of them and is not checked.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// The layers in the order data flows through them: a layer may use the
/// ones before it, never the ones after it.
const LAYERS: [&str; 9] = [
    "geom", "spatial", "anatomy", "curve", "section", "surface", "segment", "body", "measure",
];

/// Root items a layer may name as `crate::X` (macros are exported there).
const ROOT_ITEMS: [&str; 3] = ["assert_near", "assert_rel_near", "assert_vec_near"];

/// A source file: its layer, its file name inside the layer (`None` for a
/// layer's `mod.rs` or a one-file layer) and its text.
struct Source {
    layer: String,
    file: Option<String>,
    text: String,
}

/// The text before a file's first `#[cfg(test)]`: its test modules may
/// use anything.
fn non_test(text: &str) -> String {
    let mut out = String::new();
    for line in text.lines() {
        if line.trim_start().starts_with("#[cfg(test)]") {
            break;
        }
        out.push_str(line);
        out.push('\n');
    }
    out
}

/// Each `crate::a::b` in `text` as `(a, b)` (`b` empty when absent).
fn crate_paths(text: &str) -> Vec<(String, String)> {
    let ident = |s: &str| -> String {
        s.chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect()
    };
    let mut out = Vec::new();
    for (i, _) in text.match_indices("crate::") {
        let before = text[..i].chars().next_back();
        if before.is_some_and(|c| c.is_alphanumeric() || c == '_') {
            continue;
        }
        let rest = &text[i + "crate::".len()..];
        let a = ident(rest);
        let after = &rest[a.len()..];
        let b = after.strip_prefix("::").map(ident).unwrap_or_default();
        out.push((a, b));
    }
    out
}

/// Every violation in `sources`: upward imports, unknown root paths, and
/// cycles among the files of one layer.
fn violations(sources: &[Source]) -> Vec<String> {
    let rank = |l: &str| LAYERS.iter().position(|x| *x == l);
    let mut bad = Vec::new();
    // Per layer, the edges between its files.
    let mut edges: BTreeMap<String, BTreeMap<String, BTreeSet<String>>> = BTreeMap::new();
    for s in sources {
        let name = match &s.file {
            Some(f) => format!("{}/{f}", s.layer),
            None => s.layer.clone(),
        };
        let Some(own) = rank(&s.layer) else {
            bad.push(format!("{name}: not in a layer (add it to LAYERS)"));
            continue;
        };
        for (a, b) in crate_paths(&s.text) {
            match rank(&a) {
                None if ROOT_ITEMS.contains(&a.as_str()) => {}
                None => bad.push(format!("{name}: crate::{a} is not a layer")),
                Some(r) if r > own => bad.push(format!("{name}: upward import crate::{a}")),
                Some(r) if r == own => {
                    if let Some(f) = &s.file {
                        if !b.is_empty() && &b != f {
                            edges
                                .entry(s.layer.clone())
                                .or_default()
                                .entry(f.clone())
                                .or_default()
                                .insert(b);
                        }
                    }
                }
                Some(_) => {}
            }
        }
    }
    for (layer, graph) in &edges {
        if let Some(cycle) = find_cycle(graph) {
            bad.push(format!("{layer}: import cycle {}", cycle.join(" -> ")));
        }
    }
    bad
}

/// A cycle of `graph` (as the nodes around it, first repeated at the end),
/// if there is one.
fn find_cycle(graph: &BTreeMap<String, BTreeSet<String>>) -> Option<Vec<String>> {
    fn visit(
        v: &str,
        graph: &BTreeMap<String, BTreeSet<String>>,
        state: &mut BTreeMap<String, u8>,
        path: &mut Vec<String>,
    ) -> Option<Vec<String>> {
        state.insert(v.to_string(), 1);
        path.push(v.to_string());
        for w in graph.get(v).into_iter().flatten() {
            match state.get(w.as_str()) {
                Some(1) => {
                    let start = path.iter().position(|x| x == w).unwrap_or(0);
                    let mut c = path[start..].to_vec();
                    c.push(w.clone());
                    return Some(c);
                }
                Some(_) => {}
                None => {
                    if let Some(c) = visit(w, graph, state, path) {
                        return Some(c);
                    }
                }
            }
        }
        path.pop();
        state.insert(v.to_string(), 2);
        None
    }
    let mut state = BTreeMap::new();
    for v in graph.keys() {
        if !state.contains_key(v.as_str()) {
            if let Some(c) = visit(v, graph, &mut state, &mut Vec::new()) {
                return Some(c);
            }
        }
    }
    None
}

/// Every `.rs` file under `src/` but the root, as a [`Source`].
fn read_sources(src: &Path) -> Vec<Source> {
    let mut out = Vec::new();
    let mut dirs = vec![src.to_path_buf()];
    while let Some(d) = dirs.pop() {
        let entries = std::fs::read_dir(&d).unwrap_or_else(|e| panic!("{}: {e}", d.display()));
        for e in entries {
            let p = e.expect("a directory entry").path();
            if p.is_dir() {
                dirs.push(p);
                continue;
            }
            if p.extension().is_none_or(|x| x != "rs") {
                continue;
            }
            let rel = p.strip_prefix(src).expect("under src");
            let parts: Vec<String> = rel
                .iter()
                .map(|c| c.to_string_lossy().trim_end_matches(".rs").to_string())
                .collect();
            let (layer, file) = match parts.as_slice() {
                [root] if root == "lib" => continue,
                [one] => (one.clone(), None),
                [layer, m] if m == "mod" => (layer.clone(), None),
                [layer, rest @ ..] => (layer.clone(), Some(rest[0].clone())),
                [] => continue,
            };
            let text = std::fs::read_to_string(&p).expect("a readable source file");
            out.push(Source {
                layer,
                file,
                text: non_test(&text),
            });
        }
    }
    out
}

#[test]
fn no_upward_imports_and_no_cycles() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let sources = read_sources(&src);
    assert!(sources.len() > 30, "read only {} files", sources.len());
    let bad = violations(&sources);
    assert!(bad.is_empty(), "layering violations:\n{}", bad.join("\n"));
}

#[test]
fn the_check_catches_an_upward_import_and_a_cycle() {
    let src = |layer: &str, file: Option<&str>, text: &str| Source {
        layer: layer.into(),
        file: file.map(Into::into),
        text: non_test(text),
    };
    let sources = [
        src("geom", Some("mesh"), "use crate::body::Body;"),
        src("spatial", Some("a"), "use crate::spatial::b::X;"),
        src("spatial", Some("b"), "/// [`crate::spatial::a::Y`]"),
        src("curve", None, "#[cfg(test)]\nuse crate::measure::Z;"),
        src("section", None, "use crate::nowhere::W;"),
    ];
    let bad = violations(&sources);
    assert_eq!(bad.len(), 3, "{bad:?}");
    assert!(bad[0].contains("upward import crate::body"), "{bad:?}");
    assert!(bad[1].contains("not a layer"), "{bad:?}");
    assert!(bad[2].contains("spatial: import cycle"), "{bad:?}");
}
