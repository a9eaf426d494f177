//! Renders every registered technique's AOVs on every built-in scene at 96×54 (after frame 1 and
//! after frame 4, which covers the temporal techniques) into a folder of raw images, or compares
//! such a folder with a fresh rendering: the check that a refactoring left the pictures alone.
//!
//! ```text
//! cargo run --release -p nearfield-render --example goldens -- write DIR
//! cargo run --release -p nearfield-render --example goldens -- check DIR
//! ```
//! `check` prints, per AOV, how many images differ and the largest absolute difference it found
//! (float AOVs in their own units, `final` in 8-bit steps), and exits 1 when an image is missing.

use nearfield_render::{Aov, GpuContext, RenderSettings, Renderer, TechniqueParams, technique};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

const SIZE: (u32, u32) = (96, 54);
const FRAMES: [u32; 2] = [1, 4];
const AOVS: [Aov; 6] = [
    Aov::Ao,
    Aov::EnvIrradiance,
    Aov::LightIrradiance,
    Aov::IndirectIrradiance,
    Aov::Diffuse,
    Aov::Final,
];

/// One rendered image as little-endian bytes (f32 RGBA for float AOVs, RGBA8 for `final`).
fn images(ctx: &GpuContext, scene_name: &str, method: &str) -> Vec<(String, Vec<u8>)> {
    let scene = nearfield_scene::builtin::scene(scene_name).expect("built-in scene");
    let env = scene.default_env.load().expect("built-in environment");
    let settings = RenderSettings {
        size: SIZE,
        ..Default::default()
    };
    let technique = nearfield_render::technique::Spec::resolve(method, &TechniqueParams::default())
        .unwrap_or_else(|e| panic!("{scene_name} {method}: {e}"));
    let mut r = Renderer::new(
        ctx,
        &scene,
        &env,
        None,
        scene.default_camera(),
        &technique,
        settings,
    )
    .unwrap_or_else(|e| panic!("{scene_name} {method}: {e}"));
    let mut out = Vec::new();
    for frame in 1..=*FRAMES.last().unwrap() {
        r.render_frame();
        if !FRAMES.contains(&frame) {
            continue;
        }
        for aov in AOVS {
            let bytes = if aov == Aov::Final {
                r.read_final().into_raw()
            } else {
                bytemuck::cast_slice(&r.read_aov(aov).pixels).to_vec()
            };
            out.push((
                format!("{scene_name}.{method}.f{frame}.{}.raw", aov.name()),
                bytes,
            ));
        }
    }
    out
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (mode, dir) = match args.as_slice() {
        [m, d] if m == "write" || m == "check" => (m.as_str(), PathBuf::from(d)),
        _ => {
            eprintln!("usage: goldens write|check DIR");
            std::process::exit(2);
        }
    };
    let ctx = GpuContext::new(None).expect("a GPU adapter");
    if mode == "write" {
        std::fs::create_dir_all(&dir).expect("golden folder");
    }
    // Per AOV: (images compared, images that differ, largest difference).
    let mut stats: BTreeMap<&str, (u32, u32, f32)> = BTreeMap::new();
    let mut missing = 0;
    for scene_name in nearfield_scene::builtin::NAMES {
        for method in technique::names() {
            let t = std::time::Instant::now();
            for (name, bytes) in images(&ctx, scene_name, method) {
                let path = dir.join(&name);
                if mode == "write" {
                    nearfield_scene::atomic::write_bytes(&path, &bytes).expect("write golden");
                    continue;
                }
                let aov = name.split('.').nth(3).unwrap();
                let Some(golden) = read(&path) else {
                    eprintln!("missing: {}", path.display());
                    missing += 1;
                    continue;
                };
                let d = difference(aov == "final", &golden, &bytes);
                let e = stats.entry(Aov::parse(aov).unwrap().name()).or_default();
                e.0 += 1;
                if d != 0.0 {
                    e.1 += 1;
                    e.2 = e.2.max(d);
                    eprintln!("differs: {name} by {d}");
                }
            }
            eprintln!("{scene_name} {method}: {:.1} s", t.elapsed().as_secs_f32());
        }
    }
    for (aov, (n, differ, max)) in &stats {
        println!("{aov:>20}: {n} images, {differ} differ, largest difference {max}");
    }
    if missing > 0 {
        eprintln!("{missing} golden images missing");
        std::process::exit(1);
    }
}

fn read(path: &Path) -> Option<Vec<u8>> {
    std::fs::read(path).ok()
}

/// The largest absolute difference between two images (a length mismatch counts as infinite).
fn difference(ldr: bool, a: &[u8], b: &[u8]) -> f32 {
    if a.len() != b.len() {
        return f32::INFINITY;
    }
    if ldr {
        return a
            .iter()
            .zip(b)
            .map(|(x, y)| (*x as f32 - *y as f32).abs())
            .fold(0.0, f32::max);
    }
    let a: Vec<f32> = bytemuck::pod_collect_to_vec(a);
    let b: Vec<f32> = bytemuck::pod_collect_to_vec(b);
    a.iter()
        .zip(&b)
        .map(|(x, y)| {
            if x.to_bits() == y.to_bits() {
                0.0
            } else if x.is_nan() || y.is_nan() {
                f32::INFINITY
            } else {
                (x - y).abs()
            }
        })
        .fold(0.0, f32::max)
}
