//! Real scenes from ../shared/assets (SOURCES.md there): each loads and has the triangle count
//! SOURCES.md states. Skipped when the folder is absent, unless REQUIRE_GPU=1 (CI, which always
//! has ../shared beside the checkout).

use nearfield_scene::{EnvSource, load_scene};
use std::path::PathBuf;

pub fn assets() -> Option<PathBuf> {
    let dir = std::env::var_os("NEARFIELD_ASSETS")
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/assets")
        });
    if dir.is_dir() {
        Some(dir)
    } else if std::env::var("REQUIRE_GPU").as_deref() == Ok("1") {
        panic!("{} is missing", dir.display());
    } else {
        eprintln!("skipping: {} is missing", dir.display());
        None
    }
}

#[test]
fn triangle_counts_match_sources_md() {
    let Some(dir) = assets() else { return };
    for (path, triangles) in [
        ("scenes/damaged_helmet/DamagedHelmet.gltf", 15_452),
        ("scenes/happy_buddha/buddha.obj", 100_000),
        ("scenes/stanford_lucy_100k/Lucy100k.ply", 100_000),
        ("scenes/stanford_bunny/stanford-bunny.obj", 69_451),
        ("scenes/stanford_dragon/dragon.obj", 100_000),
        ("scenes/dabrovic_sponza_obj/sponza.obj", 66_454),
        ("scenes/crytek_sponza/Sponza.gltf", 262_267),
    ] {
        let p = dir.join(path);
        if !p.exists() && path.contains("crytek") {
            eprintln!("skipping {path}: not present");
            continue;
        }
        let scene = load_scene(&p).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(scene.triangle_count(), triangles, "{path}");
        assert!(
            scene
                .meshes
                .iter()
                .all(|m| m.normals.iter().all(|n| (n.length() - 1.0).abs() < 1e-3)),
            "{path}: normals"
        );
    }
}

#[test]
fn gltf_features_of_real_files() {
    let Some(dir) = assets() else { return };
    // The Blender Cornell box: 5 materials, one of them emissive; Y-up within about ±1.1 m.
    let cb = load_scene(&dir.join("scenes/cornell_box_suzanne_gltf/cornell-box.glb")).unwrap();
    assert!(cb.triangle_count() > 500);
    assert!(cb.materials.iter().any(|m| m.emissive.max_element() > 0.0));
    let b = cb.bounds();
    assert!(b.min.y > -1.1 && b.max.y < 1.1, "{b:?}");
    // The helmet: textured, its node's +90° rotation about X makes it Y-up (taller than deep).
    let h = load_scene(&dir.join("scenes/damaged_helmet/DamagedHelmet.gltf")).unwrap();
    let m = &h.materials[h.meshes[0].material as usize];
    assert!(
        m.base_color_texture.is_some()
            && m.metallic_roughness_texture.is_some()
            && m.emissive_texture.is_some()
    );
    let t = &h.textures[m.base_color_texture.unwrap()];
    assert_eq!((t.width, t.height), (2048, 2048));
    // Sponza: three alpha-masked materials.
    let sponza = dir.join("scenes/crytek_sponza/Sponza.gltf");
    if sponza.exists() {
        let s = load_scene(&sponza).unwrap();
        let masked = s
            .materials
            .iter()
            .filter(|m| matches!(m.alpha_mode, nearfield_scene::AlphaMode::Mask { .. }))
            .count();
        assert_eq!(masked, 3);
    }
}

#[test]
fn hdr_maps_load_with_the_stated_layout() {
    let Some(dir) = assets() else { return };
    let env = EnvSource::parse(dir.join("env/rooitou_park_1k.hdr").to_str().unwrap())
        .unwrap()
        .load()
        .unwrap();
    assert_eq!((env.width, env.height), (1024, 512));
    // SOURCES.md: sun ≈ 10° elevation, peak ≈ 6.5e4.
    let (i, peak) = env
        .texels
        .iter()
        .enumerate()
        .map(|(i, t)| (i, 0.2126 * t.x + 0.7152 * t.y + 0.0722 * t.z))
        .fold((0, 0.0f32), |a, b| if b.1 > a.1 { b } else { a });
    assert!(peak > 3e4, "{peak}");
    let row = i as u32 / env.width;
    let elevation = 90.0 - (row as f32 + 0.5) / env.height as f32 * 180.0;
    assert!((elevation - 10.0).abs() < 3.0, "sun elevation {elevation}");
}
