//! Real scenes from ../shared/assets render: each covers a good part of the image with finite,
//! lit surface pixels from its default (auto-framed) camera. Skipped without ../shared unless
//! REQUIRE_GPU=1.

mod common;

use nearfield_render::Aov;
use nearfield_scene::{EnvSource, load_scene};
use std::path::PathBuf;

fn assets() -> Option<PathBuf> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/assets");
    if dir.is_dir() {
        Some(dir)
    } else if std::env::var("REQUIRE_GPU").as_deref() == Ok("1") {
        panic!("{} is missing", dir.display());
    } else {
        None
    }
}

#[test]
fn real_scenes_render() {
    let Some(dir) = assets() else { return };
    let Some(ctx) = common::context() else { return };
    let env = EnvSource::parse(dir.join("env/potsdamer_platz_1k.hdr").to_str().unwrap())
        .unwrap()
        .load()
        .unwrap();
    for (path, min_coverage) in [
        ("scenes/damaged_helmet/DamagedHelmet.gltf", 0.1),
        ("scenes/cornell_box_suzanne_gltf/cornell-box.glb", 0.3),
        ("scenes/happy_buddha/buddha.obj", 0.05),
        ("scenes/stanford_lucy_100k/Lucy100k.ply", 0.05),
        ("scenes/crytek_sponza/Sponza.gltf", 0.2),
    ] {
        let p = dir.join(path);
        if !p.exists() {
            assert!(path.contains("crytek"), "{path} missing");
            continue;
        }
        let scene = load_scene(&p).unwrap();
        let size = (64, 48);
        let img = &common::render_aovs(
            &ctx,
            &scene,
            &env,
            scene.default_camera(),
            size,
            &[Aov::Radiance],
        )[0];
        let surface: Vec<_> = img.surface().collect();
        let coverage = surface.len() as f32 / (size.0 * size.1) as f32;
        assert!(coverage >= min_coverage, "{path}: coverage {coverage}");
        assert!(
            surface
                .iter()
                .all(|p| p[..3].iter().all(|c| c.is_finite() && *c >= 0.0)),
            "{path}"
        );
        let lit = surface.iter().filter(|p| p[0] + p[1] + p[2] > 1e-3).count();
        assert!(
            lit as f32 > 0.9 * surface.len() as f32,
            "{path}: {lit} of {} lit",
            surface.len()
        );
    }
}
