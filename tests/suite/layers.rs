//! The layers of ARCHITECTURE.md, enforced: every `crate::MODULE` path in the library's
//! sources (outside `#[cfg(test)]` modules and comments) names a module of the same layer or
//! of a layer above the file's own, so no import circle can form between the top-level
//! modules.

use std::path::{Path, PathBuf};

/// The layers, top first, as ARCHITECTURE.md lists them; a module imports only from its own
/// layer's other modules (where the list allows it) and the layers above.
const LAYERS: &[&[&str]] = &[
    &["math", "units", "range", "rng", "files"],
    &["ground"],
    &["closure"],
    &["geometry"],
    &["layout"],
    &["dem"],
    &["nscd"],
    &["loading"],
    &["limit"],
    &["protocol"],
    &["generator"],
    &["survey"],
    &["verify", "benchmark"],
    &["effects"],
    &["ensemble", "stats"],
    &["io"],
    &["discrepancy"],
    &["study"],
];

/// Pairs within one layer that may import each other in this direction.
const SAME_LAYER: &[(&str, &str)] = &[("benchmark", "verify")];

fn layer_of(module: &str) -> Option<usize> {
    LAYERS.iter().position(|l| l.contains(&module))
}

fn sources(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let p = entry.unwrap().path();
        if p.is_dir() {
            sources(&p, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            out.push(p);
        }
    }
}

#[test]
fn every_import_points_up_the_layers_of_architecture_md() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    sources(&src, &mut files);
    files.sort();
    let mut wrong = Vec::new();
    let mut seen_arrows = 0;
    for f in &files {
        let rel = f.strip_prefix(&src).unwrap();
        let top = rel.iter().next().unwrap().to_string_lossy().trim_end_matches(".rs").to_string();
        if ["lib", "main", "cli"].contains(&top.as_str()) {
            continue; // the crate root and the CLI sit on top of everything
        }
        let own =
            layer_of(&top).unwrap_or_else(|| panic!("{}: module `{top}` is in no layer of this test", rel.display()));
        // Test code may import any layer: a `#[cfg(test)]` block, or a module's tests in a
        // file of their own (`tests.rs`, declared `#[cfg(test)] mod tests;`).
        if f.file_name().is_some_and(|n| n == "tests.rs") {
            continue;
        }
        let text = std::fs::read_to_string(f).unwrap();
        let code = text.split("#[cfg(test)]").next().unwrap();
        for (n, line) in code.lines().enumerate() {
            let line = line.split("//").next().unwrap();
            let mut rest = line;
            while let Some(i) = rest.find("crate::") {
                rest = &rest[i + 7..];
                let name: String = rest.chars().take_while(|c| c.is_ascii_alphanumeric() || *c == '_').collect();
                if name == top || name.is_empty() {
                    continue;
                }
                let Some(theirs) = layer_of(&name) else {
                    // An item of the crate root (lib.rs, which imports every module): an arrow
                    // up to the bottom of the crate.
                    wrong.push(format!(
                        "src/{}:{}: `{top}` imports `{name}` from the crate root; import it from its module",
                        rel.display(),
                        n + 1
                    ));
                    continue;
                };
                seen_arrows += 1;
                let allowed = theirs < own || (theirs == own && SAME_LAYER.contains(&(top.as_str(), name.as_str())));
                if !allowed {
                    wrong.push(format!("src/{}:{}: `{top}` imports `{name}`", rel.display(), n + 1));
                }
            }
        }
    }
    assert!(seen_arrows > 100, "only {seen_arrows} imports found: is the scan reading the sources?");
    assert!(wrong.is_empty(), "imports against the layers of ARCHITECTURE.md:\n{}", wrong.join("\n"));
}

/// The crate root only declares the modules and re-exports (the prelude and the
/// `math` types): it defines nothing a module could import from it.
#[test]
fn the_crate_root_declares_and_re_exports_only() {
    let lib = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("src/lib.rs")).unwrap();
    let defining: Vec<&str> = lib
        .lines()
        .map(|l| l.split("//").next().unwrap().trim())
        .filter(|l| {
            [
                "fn ",
                "pub fn ",
                "type ",
                "pub type ",
                "struct ",
                "pub struct ",
                "enum ",
                "pub enum ",
                "const ",
                "pub const ",
            ]
            .iter()
            .any(|k| l.starts_with(k))
        })
        .collect();
    assert!(defining.is_empty(), "src/lib.rs defines items: {defining:?}");
}

/// The module path of a source file: `src/a/b.rs` and `src/a/b/mod.rs` are `[a, b]`,
/// `src/lib.rs` is `[]`.
fn module_of(rel: &Path) -> Vec<String> {
    let mut parts: Vec<String> = rel.iter().map(|p| p.to_string_lossy().to_string()).collect();
    let last = parts.pop().unwrap();
    let stem = last.trim_end_matches(".rs");
    if stem != "mod" && stem != "lib" {
        parts.push(stem.to_string());
    }
    parts
}

/// The code of a file outside its `#[cfg(test)]` module, comments cut off each line.
fn code_of(text: &str) -> String {
    let code = text.split("#[cfg(test)]").next().unwrap();
    code.lines().map(|l| l.split("//").next().unwrap()).collect::<Vec<_>>().join("\n")
}

/// Every path of a use tree that starts at `s` (`a::b::{c, d::{e, self}}`), each as its
/// segments; `s` begins after the `crate::` or `super::` that anchors it.
fn expand(s: &str) -> Vec<Vec<String>> {
    fn tree(s: &[u8], i: &mut usize) -> Vec<Vec<String>> {
        let mut prefix = Vec::new();
        loop {
            while *i < s.len() && s[*i].is_ascii_whitespace() {
                *i += 1;
            }
            if *i < s.len() && s[*i] == b'{' {
                *i += 1;
                let mut out = Vec::new();
                loop {
                    while *i < s.len() && (s[*i].is_ascii_whitespace() || s[*i] == b',') {
                        *i += 1;
                    }
                    if *i >= s.len() || s[*i] == b'}' {
                        *i += 1;
                        break;
                    }
                    for mut t in tree(s, i) {
                        if t.first().is_some_and(|x| x == "self") {
                            t.remove(0);
                        }
                        let mut p = prefix.clone();
                        p.extend(t);
                        out.push(p);
                    }
                }
                return out;
            }
            let start = *i;
            while *i < s.len() && (s[*i].is_ascii_alphanumeric() || s[*i] == b'_') {
                *i += 1;
            }
            if start == *i {
                return vec![prefix];
            }
            prefix.push(String::from_utf8_lossy(&s[start..*i]).to_string());
            if s[*i..].starts_with(b"::") {
                *i += 2;
            } else {
                return vec![prefix];
            }
        }
    }
    let mut i = 0;
    tree(s.as_bytes(), &mut i)
}

/// The crate's source files by module path, and for each its `crate::`/`super::` paths as
/// absolute module paths (`[dem, engine, Simulation]`) and, for a folder's `mod.rs`, the
/// items it re-exports from its children (`pub use engine::Simulation;` in `dem/mod.rs`:
/// `Simulation` → `[dem, engine, Simulation]`).
type Graph = std::collections::BTreeMap<Vec<String>, (String, Vec<Vec<String>>, Reexports)>;

/// A folder's re-exports: the item's name in the folder → its absolute path.
type Reexports = std::collections::BTreeMap<String, Vec<String>>;

/// The items a file re-exports from its own children (`pub use child::...;`), by name.
fn reexports(module: &[String], code: &str, is_child: impl Fn(&str) -> bool) -> Reexports {
    let mut out = Reexports::new();
    for (at, _) in code.match_indices("pub use ") {
        let rest = &code[at + 8..];
        let first: String = rest.chars().take_while(|c| c.is_ascii_alphanumeric() || *c == '_').collect();
        if first.is_empty() || first == "crate" || first == "super" || first == "self" || !is_child(&first) {
            continue;
        }
        for p in expand(rest) {
            if p.len() >= 2 {
                out.insert(p.last().unwrap().clone(), [module.to_vec(), p].concat());
            }
        }
    }
    out
}

fn read_graph(src: &Path) -> Graph {
    let mut files = Vec::new();
    sources(src, &mut files);
    let mut graph = Graph::new();
    for f in &files {
        let rel = f.strip_prefix(src).unwrap();
        if rel == Path::new("main.rs") {
            continue; // the binary's root: its `crate` is not the library's
        }
        let module = module_of(rel);
        let code = code_of(&std::fs::read_to_string(f).unwrap());
        let mut paths = Vec::new();
        let bytes = code.as_bytes();
        let mut at = 0;
        while at < code.len() {
            let rest = &bytes[at..];
            let (base, skip) = if rest.starts_with(b"crate::") {
                (Vec::new(), 7)
            } else if rest.starts_with(b"super::") {
                // `super` of `a/b.rs` is `a`; of `a/b/mod.rs` (module `a::b`) also `a`.
                let mut base = module.clone();
                let mut skip = 0;
                while bytes[at + skip..].starts_with(b"super::") {
                    base.pop();
                    skip += 7;
                }
                (base, skip)
            } else {
                at += 1;
                continue;
            };
            let preceded = at > 0 && (bytes[at - 1].is_ascii_alphanumeric() || bytes[at - 1] == b'_');
            if preceded || (rest.starts_with(b"super::") && at >= 2 && &bytes[at - 2..at] == b"::") {
                at += skip;
                continue;
            }
            for p in expand(&code[at + skip..]) {
                let mut full = base.clone();
                full.extend(p);
                paths.push(full);
            }
            at += skip;
        }
        let is_child = |name: &str| {
            let dir = f.parent().unwrap();
            let root = matches!(f.file_name().unwrap().to_str(), Some("mod.rs" | "lib.rs"));
            let folder = if root { dir.to_path_buf() } else { dir.join(f.file_stem().unwrap()) };
            folder.join(format!("{name}.rs")).exists() || folder.join(name).join("mod.rs").exists()
        };
        let re = reexports(&module, &code, is_child);
        graph.insert(module, (format!("src/{}", rel.display()), paths, re));
    }
    graph
}

/// The file a path names: the deepest module of the path that is a file of the crate,
/// following the re-exports of a folder's `mod.rs` to the child file that defines the item
/// (`crate::dem::Simulation` names `dem/engine.rs` when `dem/mod.rs` has
/// `pub use engine::Simulation;`).
fn target(graph: &Graph, path: &[String]) -> Vec<String> {
    let mut m: Vec<String> = Vec::new();
    for (i, seg) in path.iter().enumerate() {
        let next = [m.clone(), vec![seg.clone()]].concat();
        if graph.contains_key(&next) {
            m = next;
            continue;
        }
        if let Some(to) = graph.get(&m).and_then(|g| g.2.get(seg)) {
            if to.as_slice() != path && to.len() > m.len() {
                return target(graph, &[to.clone(), path[i + 1..].to_vec()].concat());
            }
        }
        break;
    }
    m
}

/// No two files import each other, directly or round a longer loop, folders included: the
/// file-level graph of the `crate::` and `super::` paths (each path an arrow to the file
/// that defines its item, through a folder's re-exports) has no cycle. A folder's `mod.rs`
/// names its children by relative paths (`mod x; pub use x::Item;`): those are not arrows,
/// so a child may import from it.
#[test]
fn no_import_circle_between_files() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let graph = read_graph(&src);
    let keys: Vec<Vec<String>> = graph.keys().cloned().collect();
    let index = |m: &Vec<String>| keys.iter().position(|k| k == m).unwrap();
    let mut edges = vec![std::collections::BTreeSet::new(); keys.len()];
    let mut arrows = 0;
    for (i, m) in keys.iter().enumerate() {
        for p in &graph[m].1 {
            let t = target(&graph, p);
            let j = index(&t);
            if j != i && !t.is_empty() {
                arrows += usize::from(edges[i].insert(j));
            }
        }
    }
    assert!(arrows > 200, "only {arrows} arrows between files found: is the scan reading the sources?");
    // Depth-first search for a back edge; the cycle is the stack from its target.
    let mut state = vec![0u8; keys.len()];
    let mut circles = Vec::new();
    fn visit(
        v: usize,
        edges: &[std::collections::BTreeSet<usize>],
        state: &mut [u8],
        stack: &mut Vec<usize>,
        out: &mut Vec<Vec<usize>>,
    ) {
        state[v] = 1;
        stack.push(v);
        for &w in &edges[v] {
            if state[w] == 1 {
                let from = stack.iter().position(|&x| x == w).unwrap();
                out.push(stack[from..].to_vec());
            } else if state[w] == 0 {
                visit(w, edges, state, stack, out);
            }
        }
        stack.pop();
        state[v] = 2;
    }
    for v in 0..keys.len() {
        if state[v] == 0 {
            visit(v, &edges, &mut state, &mut Vec::new(), &mut circles);
        }
    }
    let named: Vec<String> = circles
        .iter()
        .map(|c| {
            let mut names: Vec<&str> = c.iter().map(|&i| graph[&keys[i]].0.as_str()).collect();
            names.push(names[0]);
            names.join(" -> ")
        })
        .collect();
    assert!(named.is_empty(), "import circles between files:\n{}", named.join("\n"));
}
