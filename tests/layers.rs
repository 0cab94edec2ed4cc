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
    &["loading"],
    &["limit"],
    &["generator"],
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
