//! A scratch setting and a scratch family, added in the test build (`cargo test -p
//! nearfield-render --features scratch --test scratch`), reach every consumer with no other
//! edit (docs/src/architecture.md, "Where a change goes"):
//! - the setting is one declaration line in `technique/horizon/settings.rs` (a gtao float);
//! - the family is its folder `technique/scratch/` and its lines in `technique/mod.rs`.
//!
//! The last test counts the files each of them touched. The CLI's consumers (the viewer's
//! panel, `pareto`, `fit`, the book) are checked by `crates/cli/src/view/settings_reach.rs`, run
//! with the same feature (`cargo test -p nearfield-cli --features nearfield-render/scratch`).
#![cfg(feature = "scratch")]

mod common;

use nearfield_render::settings::{Declared, Role};
use nearfield_render::technique::{self, Spec};
use nearfield_render::{Aov, Renderer, TechniqueParams};
use std::path::{Path, PathBuf};

fn params(set: &[(&str, &str)]) -> TechniqueParams {
    TechniqueParams {
        set: set
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect(),
        ..Default::default()
    }
}

fn renderer(ctx: &nearfield_render::GpuContext, method: &str, set: &[(&str, &str)]) -> Renderer {
    let scene = nearfield_scene::builtin::scene("cornell").unwrap();
    let env = scene.default_env.load().unwrap();
    let settings = nearfield_render::RenderSettings {
        size: (32, 24),
        ..Default::default()
    };
    let spec = Spec::resolve(method, &params(set)).unwrap();
    Renderer::new(
        ctx,
        &scene,
        &env,
        None,
        scene.default_camera(),
        &spec,
        settings,
    )
    .unwrap()
}

#[test]
fn the_scratch_setting_reaches_every_consumer() {
    let gtao = technique::find("gtao").unwrap();
    // The declaration's table: what the viewer, the book, fit and pareto read.
    let s = gtao.settings.iter().find(|s| s.key == "scratch").unwrap();
    assert_eq!((s.role, s.default), (Role::Uniform, "0"));
    assert!(s.applies("gtao") && !s.applies("hbil"));
    let page = technique::book_pages()
        .into_iter()
        .find(|(name, _)| name == "settings-horizon.md")
        .unwrap()
        .1;
    assert!(page.contains("| `scratch` |"), "{page}");
    // The parser, its range and `check`, before anything is built.
    assert!(Spec::resolve("gtao:scratch=0.5", &TechniqueParams::default()).is_ok());
    let Err(e) = Spec::resolve("gtao:scratch=2", &TechniqueParams::default()) else {
        panic!("scratch=2 accepted")
    };
    assert!(e.to_string().contains("scratch=2"), "{e}");
    assert!((gtao.check)(&params(&[("scratch", "0.5")])).is_ok());
    // vbgi embeds the horizon family's settings: the new field reaches it at its default.
    let vbgi = nearfield_render::technique::vbgi::Settings::default()
        .split()
        .0;
    assert_eq!(vbgi.scratch, 0.0);
    // The renderer: a uniform, changed in place.
    let Some(ctx) = common::context() else { return };
    let mut r = renderer(&ctx, "gtao", &[]);
    r.render_frame();
    r.set_technique("gtao", &params(&[("scratch", "0.5")]))
        .unwrap();
    assert_eq!(r.rebuilds(), 0, "a uniform rebuilt gtao");
}

#[test]
fn the_scratch_family_reaches_every_consumer() {
    // The registry and everything that enumerates it.
    assert!(technique::names().contains(&"scratch"));
    let desc = technique::find("scratch").unwrap();
    let page = technique::book_pages()
        .into_iter()
        .find(|(name, _)| name == "settings-scratch.md")
        .expect("the book's settings page of the family")
        .1;
    assert!(page.contains("| `occlusion` |") && page.contains("| `taps` |"));
    // Its pass against its WGSL (bindings and the uniform's layout), as for every pass.
    let pass = nearfield_render::pass_layouts()
        .into_iter()
        .find(|p| p.name == "technique/scratch")
        .expect("the scratch pass among the pass layouts");
    let mismatches = nearfield_render::reflect::group_mismatches(
        pass.name,
        &pass.source,
        pass.entry_point,
        &[
            nearfield_render::bindings::FrameBindings::SLOTS,
            pass.group1,
        ],
    );
    assert!(mismatches.is_empty(), "{mismatches:?}");
    use nearfield_render::technique::scratch::{ScratchParams, Settings};
    let layout = nearfield_render::reflect::struct_mismatches(
        &pass.source,
        "ScratchParams",
        size_of::<ScratchParams>(),
        ScratchParams::FIELDS,
    );
    assert!(layout.is_empty(), "{layout:?}");
    // Its declaration: the count specialises the kernel.
    let counts = Settings::default().counts();
    assert_eq!(counts, vec![("taps", 1.0)]);
    assert_eq!(
        nearfield_render::settings::count_constants(&pass.source, &counts),
        vec![("TAPS".to_string(), 1.0)]
    );
    assert!((desc.check)(&params(&[("occlusion", "2")])).is_err());

    // Rendered: ao = 1 − occlusion / taps on every surface (the Cornell box fills the image).
    let Some(ctx) = common::context() else { return };
    let mut r = renderer(&ctx, "scratch", &[]);
    let ao = |r: &mut Renderer| {
        r.render_frame();
        let img = r.read_aov(Aov::Ao);
        let surfaces: Vec<f32> = img
            .pixels
            .iter()
            .map(|p| p[0])
            .filter(|&v| v > 0.0)
            .collect();
        assert!(
            surfaces.len() * 2 > img.pixels.len(),
            "{} surface pixels",
            surfaces.len()
        );
        let (lo, hi) = surfaces
            .iter()
            .fold((f32::MAX, f32::MIN), |(lo, hi), &v| (lo.min(v), hi.max(v)));
        assert!(hi - lo < 1e-6, "ao {lo}..{hi}");
        lo
    };
    assert!((ao(&mut r) - 0.75).abs() < 1e-6);
    // A uniform in place, a count by a rebuild.
    r.set_technique("scratch", &params(&[("occlusion", "0.5")]))
        .unwrap();
    assert_eq!(r.rebuilds(), 0);
    assert!((ao(&mut r) - 0.5).abs() < 1e-6);
    r.set_technique("scratch", &params(&[("occlusion", "0.5"), ("taps", "2")]))
        .unwrap();
    assert_eq!(r.rebuilds(), 1);
    assert!((ao(&mut r) - 0.75).abs() < 1e-6);
}

fn files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        let name = p.file_name().unwrap().to_string_lossy();
        if name.starts_with('.') || name == "target" {
            continue;
        }
        if p.is_dir() {
            files(&p, out);
        } else if matches!(
            p.extension().and_then(|x| x.to_str()),
            Some("rs" | "wgsl" | "toml" | "md" | "py" | "sh")
        ) {
            out.push(p);
        }
    }
}

/// The files outside the scratch family's folder and this test that name the test build's
/// feature: each is a place the scratch setting or family had to touch.
#[test]
fn the_scratch_setting_and_family_touch_one_and_two_files() {
    let crate_dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let root = crate_dir.join("../..");
    let mut all = Vec::new();
    files(&root.join("crates"), &mut all);
    files(&root.join("bevy_nearfield"), &mut all);
    files(&root.join("docs/src"), &mut all);
    files(&root.join("scripts"), &mut all);
    let folder = crate_dir.join("src/technique/scratch");
    let mut touched: Vec<(String, usize)> = Vec::new();
    for f in all {
        if f.starts_with(&folder) || f.ends_with("tests/scratch.rs") {
            continue;
        }
        let text = std::fs::read_to_string(&f).unwrap();
        let lines = text
            .lines()
            .filter(|l| l.contains("feature = \"scratch\"") || l.trim() == "scratch = []")
            .count();
        if lines > 0 {
            let rel = f.strip_prefix(&root).unwrap_or(&f).to_string_lossy();
            touched.push((rel.replace("\\", "/"), lines));
        }
    }
    touched.sort();
    eprintln!("touched outside the family's folder: {touched:?}");
    let at = |path: &str| touched.iter().find(|(p, _)| p.ends_with(path)).map(|t| t.1);
    // The setting: its declaration line, nothing else.
    assert_eq!(at("technique/horizon/settings.rs"), Some(1));
    // The family: `pub mod scratch;` and its registry line.
    assert_eq!(at("technique/mod.rs"), Some(2));
    // And the feature that makes them a test build.
    assert_eq!(at("crates/render/Cargo.toml"), Some(1));
    assert_eq!(touched.len(), 3, "{touched:?}");
    // The family's folder: its module and its kernel.
    let mut own = Vec::new();
    files(&folder, &mut own);
    assert_eq!(own.len(), 2, "{own:?}");
}
