//! The book (docs/, mdBook) and the README:
//! - the generated pages (command line from clap, settings from their declarations, results
//!   from docs/src/generated/results.json) and the README's headline table are current;
//! - every page is in SUMMARY.md and every SUMMARY entry exists;
//! - every `{{#include}}`, link and image of every page (includes expanded, as mdBook does)
//!   and of the README resolves to a file, every `#anchor` to a heading of its page, and
//!   nothing points off the machine;
//! - every picture the book shows is made by scripts/figures.sh (crates/cli/examples/figures.rs);
//! - the README is at most 150 lines and starts with the two commands.

use pulldown_cmark::{Event, Parser, Tag, TagEnd};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn src() -> PathBuf {
    root().join("docs/src")
}

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// The page's text with every `{{#include FILE}}` replaced by the file (paths relative to the
/// page), recursively; an include of a missing file is an error.
fn expand(page: &Path, errors: &mut Vec<String>) -> String {
    let text = read(page);
    let mut out = String::new();
    let mut rest = text.as_str();
    while let Some(i) = rest.find("{{#include ") {
        out.push_str(&rest[..i]);
        let after = &rest[i + "{{#include ".len()..];
        let Some(j) = after.find("}}") else {
            errors.push(format!("{}: unclosed include", page.display()));
            break;
        };
        let target = page.parent().unwrap().join(after[..j].trim());
        if target.is_file() {
            out.push_str(&expand(&target, errors));
        } else {
            errors.push(format!(
                "{}: include of missing {}",
                page.display(),
                target.display()
            ));
        }
        rest = &after[j + 2..];
    }
    out.push_str(rest);
    out
}

/// mdBook's heading ids: lower case, alphanumerics, `-` and `_` kept, white space → `-`,
/// repeats numbered.
fn heading_ids(markdown: &str) -> BTreeSet<String> {
    let mut ids = BTreeSet::new();
    let mut text: Option<String> = None;
    let mut seen = std::collections::HashMap::<String, usize>::new();
    for event in Parser::new(markdown) {
        match event {
            Event::Start(Tag::Heading { .. }) => text = Some(String::new()),
            Event::Text(t) | Event::Code(t) => {
                if let Some(s) = text.as_mut() {
                    s.push_str(&t);
                }
            }
            Event::End(TagEnd::Heading(_)) => {
                let s = text.take().unwrap_or_default();
                let id: String = s
                    .trim()
                    .chars()
                    .filter_map(|c| {
                        if c.is_alphanumeric() || c == '_' || c == '-' {
                            Some(c.to_ascii_lowercase())
                        } else if c.is_whitespace() {
                            Some('-')
                        } else {
                            None
                        }
                    })
                    .collect();
                let n = seen.entry(id.clone()).or_insert(0);
                ids.insert(if *n == 0 {
                    id.clone()
                } else {
                    format!("{id}-{n}")
                });
                *n += 1;
            }
            _ => {}
        }
    }
    ids
}

/// Link and image targets of a markdown text, with `<img src=…>` of raw HTML.
fn targets(markdown: &str) -> Vec<(String, bool)> {
    let mut out = Vec::new();
    for event in Parser::new(markdown) {
        match event {
            Event::Start(Tag::Link { dest_url, .. }) => out.push((dest_url.to_string(), false)),
            Event::Start(Tag::Image { dest_url, .. }) => out.push((dest_url.to_string(), true)),
            Event::Html(h) | Event::InlineHtml(h) => {
                for part in h.split("src=\"").skip(1) {
                    if let Some(end) = part.find('"') {
                        out.push((part[..end].to_string(), true));
                    }
                }
            }
            _ => {}
        }
    }
    out
}

fn md_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let p = entry.unwrap().path();
        if p.is_dir() {
            md_files(&p, out);
        } else if p.extension().is_some_and(|e| e == "md") {
            out.push(p);
        }
    }
}

/// Checks every target of `page` (already expanded); images found are added to `images`.
fn check_targets(
    page: &Path,
    text: &str,
    errors: &mut Vec<String>,
    images: &mut BTreeSet<PathBuf>,
) {
    let dir = page.parent().unwrap();
    for (target, image) in targets(text) {
        if target.contains("://") || target.starts_with("mailto:") {
            errors.push(format!(
                "{}: {target} points off the machine",
                page.display()
            ));
            continue;
        }
        if target.starts_with('/') {
            errors.push(format!("{}: {target} is an absolute path", page.display()));
            continue;
        }
        let (path, anchor) = match target.split_once('#') {
            Some((p, a)) => (p, Some(a)),
            None => (target.as_str(), None),
        };
        let file = if path.is_empty() {
            page.to_path_buf()
        } else {
            dir.join(path)
        };
        if !file.exists() {
            errors.push(format!(
                "{}: {} {target} does not exist",
                page.display(),
                if image { "image" } else { "link" }
            ));
            continue;
        }
        if image {
            images.insert(file.canonicalize().unwrap());
        }
        if let Some(anchor) = anchor
            && file.extension().is_some_and(|e| e == "md")
        {
            let mut sub = Vec::new();
            let ids = heading_ids(&expand(&file, &mut sub));
            if !ids.contains(anchor) {
                errors.push(format!(
                    "{}: {target}: no heading #{anchor} in {}",
                    page.display(),
                    file.display()
                ));
            }
        }
    }
}

#[test]
fn generated_pages_and_the_readme_headline_are_current() {
    let results = nearfield_cli::book::read_results(&root()).unwrap();
    let results =
        results.expect("docs/src/generated/results.json (scripts/figures.sh) is committed");
    let fits = nearfield_cli::book::read_fits(&root()).unwrap();
    let fronts = nearfield_cli::book::read_fronts(&root()).unwrap();
    let mut stale = Vec::new();
    for (name, text) in nearfield_cli::book::generated_pages(Some(&results), &fits, &fronts) {
        let path = src().join("generated").join(&name);
        if std::fs::read_to_string(&path).ok().as_deref() != Some(text.as_str()) {
            stale.push(name);
        }
    }
    let readme = read(&root().join("README.md"));
    if nearfield_cli::book::rewrite_readme_headline(&readme, &results).as_deref()
        != Ok(readme.as_str())
    {
        stale.push("README.md headline".into());
    }
    if nearfield_cli::book::rewrite_readme_fits(&readme, &fits).as_deref() != Ok(readme.as_str()) {
        stale.push("README.md fitted table".into());
    }
    assert!(
        stale.is_empty(),
        "stale generated pages {stale:?}: run `cargo run -p nearfield-cli --example book_reference`"
    );
    // Every run lists every technique it was asked for, with a finite error.
    for run in &results.runs {
        assert!(!run.methods.is_empty(), "{}: no methods", run.command);
        for m in &run.methods {
            assert!(
                m.error.is_finite() && m.error >= 0.0,
                "{}: {} {}",
                run.command,
                m.name,
                m.error
            );
        }
    }
}

#[test]
fn every_page_link_and_image_of_the_book_resolves() {
    let src = src();
    let summary = read(&src.join("SUMMARY.md"));
    let mut errors = Vec::new();
    let listed: BTreeSet<PathBuf> = targets(&summary)
        .into_iter()
        .map(|(t, _)| src.join(t))
        .collect();
    for p in &listed {
        if !p.is_file() {
            errors.push(format!("SUMMARY.md: {} does not exist", p.display()));
        }
    }
    let mut pages = Vec::new();
    md_files(&src, &mut pages);
    let mut images = BTreeSet::new();
    let mut checked = 0;
    for page in &pages {
        if page.starts_with(src.join("generated")) || page.ends_with("SUMMARY.md") {
            continue;
        }
        if !listed.contains(page) {
            errors.push(format!("{} is not in SUMMARY.md", page.display()));
        }
        let text = expand(page, &mut errors);
        check_targets(page, &text, &mut errors, &mut images);
        checked += 1;
    }
    let readme = root().join("README.md");
    check_targets(&readme, &read(&readme), &mut errors, &mut images);
    assert!(
        errors.is_empty(),
        "{} problems:\n{}",
        errors.len(),
        errors.join("\n")
    );
    assert!(checked >= 15, "only {checked} pages");

    // Every picture comes from scripts/figures.sh (figures.rs, or bevy-figures.sh for the Bevy
    // plugin's, motion.sh for the In motion page's), or is a front of scripts/pareto-book.sh.
    let figures = read(&root().join("crates/cli/examples/figures.rs"));
    let bevy_figures = read(&root().join("scripts/bevy-figures.sh"));
    let motion = read(&root().join("scripts/motion.sh"));
    let fronts = read(&root().join("scripts/pareto-book.sh"));
    let made = |name: &str| {
        figures.contains(name)
            || (name.starts_with("bevy-") && bevy_figures.contains(name))
            || name.starts_with("failure")
            || (name.starts_with("crops-") && figures.contains("crops-{name}"))
    };
    for img in &images {
        let rel = img.strip_prefix(src.canonicalize().unwrap()).unwrap_or(img);
        let rel = rel.to_string_lossy();
        let name = rel.rsplit('/').next().unwrap();
        let failure = rel.starts_with("img/failures/");
        let front = rel.starts_with("pareto/")
            && name == "pareto.svg"
            && fronts.contains("$out/$scene-$aov");
        let moving = rel.starts_with("motion/") && motion.contains(&format!("docs/src/{rel}"));
        assert!(
            made(name)
                || front
                || moving
                || (failure && figures.contains("img/failures/{technique}.png")),
            "{rel} is not made by crates/cli/examples/figures.rs, scripts/bevy-figures.sh or scripts/motion.sh"
        );
    }
    eprintln!("{checked} pages, {} pictures checked", images.len());
}

#[test]
fn readme_is_short_and_starts_with_the_two_commands() {
    let readme = read(&root().join("README.md"));
    let lines = readme.lines().count();
    assert!(lines <= 150, "README.md has {lines} lines (at most 150)");
    let first_block = readme
        .split("```sh")
        .nth(1)
        .and_then(|b| b.split("```").next())
        .expect("a sh block");
    let commands: Vec<&str> = first_block
        .lines()
        .filter_map(|l| l.split_whitespace().next().map(|_| l.trim()))
        .collect();
    assert!(
        commands.len() == 2
            && commands[0].starts_with("make demo")
            && commands[1].starts_with("make test"),
        "the README's first commands: {commands:?}"
    );
    assert!(
        readme.contains("docs/src/img/cornell-compare.png"),
        "the README shows the strip"
    );
    // Both are targets of the Makefile.
    let makefile = read(&root().join("Makefile"));
    assert!(makefile.contains("\ndemo:") && makefile.contains("\ntest:"));
}

/// Every technique with free constants has a fit (scripts/fits.sh), and its `quality=fitted`
/// preset states exactly the fitted values; the preset measures on the training scenes what the
/// fit reports (same spec, so `compare --methods TECH:quality=fitted` reproduces the row).
#[test]
fn every_fitted_preset_is_the_fit_it_quotes() {
    let fits = nearfield_cli::book::read_fits(&root()).unwrap();
    let names: Vec<&str> = fits.iter().map(|f| f.method.as_str()).collect();
    for t in nearfield_render::technique::names() {
        let desc = nearfield_render::technique::find(t).unwrap();
        let fitted = desc.presets.iter().find(|p| p.name == "fitted");
        if t == "none" {
            assert!(fitted.is_none());
            continue;
        }
        let fitted = fitted.unwrap_or_else(|| panic!("{t}: no quality=fitted preset"));
        let fit = fits
            .iter()
            .find(|f| f.method == t)
            .unwrap_or_else(|| panic!("{t}: no docs/src/fits/{t}.json (have {names:?})"));
        let mut want = fit.settings();
        let mut have: Vec<(String, String)> = fitted
            .set
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect();
        want.sort();
        have.sort();
        let same = want.len() == have.len()
            && want.iter().zip(&have).all(|((wk, wv), (hk, hv))| {
                wk == hk && wv.parse::<f64>().ok() == hv.parse::<f64>().ok()
            });
        assert!(same, "{t}: preset {have:?}, fit {want:?}");
        assert!(fit.spec.starts_with(&format!("{t}:")), "{}", fit.spec);
        assert!(
            fit.train.after <= fit.train.before,
            "{t}: the fit raised the training error"
        );
        assert!(fit.evaluations >= 2 && fit.seconds > 0.0);
        // The preset is accepted where the fit's spec is.
        nearfield_render::technique::check_spec(
            &format!("{t}:quality=fitted"),
            &Default::default(),
        )
        .unwrap_or_else(|e| panic!("{t}: {e}"));
    }
}

/// The book's fronts (scripts/pareto-book.sh) cover the Cornell box and Sponza for ao,
/// env-irradiance, indirect-irradiance and lambertian, and every default that lies off its
/// front on the Cornell box (more than 10 % slower than the fastest configuration at least as
/// accurate) is named, with its reason, in the results page's table of such defaults.
#[test]
fn every_default_off_its_cornell_front_is_explained() {
    let fronts = nearfield_cli::book::read_fronts(&root()).unwrap();
    for scene in ["cornell", "sponza"] {
        for aov in ["ao", "env-irradiance", "indirect-irradiance", "lambertian"] {
            assert!(
                fronts.iter().any(|f| f.dir == format!("{scene}-{aov}")),
                "no docs/src/pareto/{scene}-{aov}/pareto.json"
            );
        }
    }
    let results = read(&src().join("results.md"));
    let mut missing = Vec::new();
    for f in fronts.iter().filter(|f| f.scene == "builtin:cornell") {
        for m in f.methods.iter().filter(|m| !m.default_near_front) {
            let row = format!("| `{}` | `{}` |", m.name, f.aov);
            if !results.contains(&row) {
                missing.push(format!("{row} (slack {:+.0} %)", 100.0 * m.default_slack));
            }
        }
    }
    assert!(
        missing.is_empty(),
        "defaults off their front on the Cornell box, not explained in results.md: {missing:#?}"
    );
}
