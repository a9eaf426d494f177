//! "Adding a technique is its folder plus one registry line" (docs/src/architecture.md), held
//! by the source tree itself: nothing outside `technique/<family>/` names a family's module
//! except the registry, which names each family once per registered technique (its
//! `TechniqueDesc`) and once to declare it. The CLI, the viewer, the book's tables, the goldens,
//! the pass reflection and the tests enumerate the registry instead.

use nearfield_render::technique::REGISTRY;
use std::path::{Path, PathBuf};

fn sources(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            sources(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

#[test]
fn a_technique_is_its_folder_and_one_registry_line() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let technique_dir = root.join("src/technique");
    let families: Vec<String> = std::fs::read_dir(&technique_dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_dir())
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    assert!(families.len() >= 5, "{families:?}");
    for desc in REGISTRY {
        assert!(
            families.iter().any(|f| f == desc.family),
            "{}: no folder technique/{}/",
            desc.name,
            desc.family
        );
    }
    let mut files = Vec::new();
    sources(&root.join("src"), &mut files);
    sources(&root.join("../cli/src"), &mut files);
    for family in &families {
        let path = format!("technique::{family}");
        let item = format!("{family}::");
        for f in &files {
            if f.starts_with(technique_dir.join(family)) {
                continue;
            }
            let text = std::fs::read_to_string(f).unwrap();
            let code: Vec<&str> = text
                .lines()
                .filter(|l| !l.trim_start().starts_with("//"))
                .collect();
            if *f == technique_dir.join("mod.rs") {
                // `pub mod F;` and one `F::DESC` line per registered technique of the family (a
                // family a feature leaves out of this build, the test build's `scratch`, is named
                // by its two gated lines).
                let registered = REGISTRY
                    .iter()
                    .filter(|d| d.family == family)
                    .count()
                    .max(1);
                let lines = code
                    .iter()
                    .filter(|l| l.contains(&item) || l.trim() == format!("pub mod {family};"))
                    .count();
                assert!(
                    lines <= registered + 1,
                    "technique/mod.rs names {family} {lines} times (registered {registered})"
                );
                continue;
            }
            // Other families may reuse a family's passes (vbgi runs on horizon's machinery);
            // nothing else names it.
            if f.starts_with(&technique_dir) {
                continue;
            }
            for l in &code {
                assert!(
                    !l.contains(&path),
                    "{} names {path}: a technique must not need an edit there\n{l}",
                    f.display()
                );
            }
        }
    }
}
