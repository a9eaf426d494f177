//! Writes the book's generated pages into docs/src/generated/: the command line from clap, the
//! settings tables from their declarations, and — from the measured
//! docs/src/generated/results.json (scripts/figures.sh) — the results tables, the failure
//! figures' captions and the README's headline table; from docs/src/fits/*.json (scripts/fits.sh)
//! the fitted presets' table:
//!
//! ```text
//! cargo run -p nearfield-cli --example book_reference
//! ```

use std::path::Path;

fn fail(msg: String) -> ! {
    eprintln!("book_reference: {msg}");
    std::process::exit(2)
}

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let dir = root.join("docs/src/generated");
    std::fs::create_dir_all(&dir).unwrap_or_else(|e| fail(format!("{}: {e}", dir.display())));
    let results = nearfield_cli::book::read_results(&root).unwrap_or_else(|e| fail(e));
    let fits = nearfield_cli::book::read_fits(&root).unwrap_or_else(|e| fail(e));
    let fronts = nearfield_cli::book::read_fronts(&root).unwrap_or_else(|e| fail(e));
    for (name, text) in nearfield_cli::book::generated_pages(results.as_ref(), &fits, &fronts) {
        let path = dir.join(&name);
        nearfield_scene::atomic::write_bytes(&path, text.as_bytes())
            .unwrap_or_else(|e| fail(format!("{}: {e}", path.display())));
        println!("wrote docs/src/generated/{name}");
    }
    if let Some(r) = &results {
        let path = root.join("README.md");
        let readme = std::fs::read_to_string(&path)
            .unwrap_or_else(|e| fail(format!("{}: {e}", path.display())));
        let new =
            nearfield_cli::book::rewrite_readme_headline(&readme, r).unwrap_or_else(|e| fail(e));
        nearfield_scene::atomic::write_bytes(&path, new.as_bytes())
            .unwrap_or_else(|e| fail(format!("{}: {e}", path.display())));
        println!("wrote README.md's headline table");
    }
    if !fits.is_empty() {
        let path = root.join("README.md");
        let readme = std::fs::read_to_string(&path)
            .unwrap_or_else(|e| fail(format!("{}: {e}", path.display())));
        let new =
            nearfield_cli::book::rewrite_readme_fits(&readme, &fits).unwrap_or_else(|e| fail(e));
        nearfield_scene::atomic::write_bytes(&path, new.as_bytes())
            .unwrap_or_else(|e| fail(format!("{}: {e}", path.display())));
        println!("wrote README.md's fitted table");
    }
}
