//! The example's command line (main.rs's module docs list it).

use super::BENCH;
use bevy::prelude::*;
use bevy_nearfield::NearFieldQuality;
use std::path::PathBuf;

#[derive(Resource, Clone)]
pub struct Options {
    pub scene: PathBuf,
    /// SCENE was named (its own camera is used).
    pub scene_given: bool,
    pub technique: String,
    pub quality: NearFieldQuality,
    pub volume: Option<PathBuf>,
    pub env: Option<String>,
    pub env_intensity: f32,
    /// None: 8 for Sponza's view (the book's pictures of it), else nearfield's 0.
    pub exposure: Option<f32>,
    pub size: (u32, u32),
    pub screenshot: Option<PathBuf>,
    pub mean: bool,
    pub linear: Option<PathBuf>,
    pub frames: u32,
    pub bench: bool,
    /// Timed frames per configuration and round of `--bench`.
    pub bench_frames: u32,
    /// No window: the camera draws into an image (with --bench, --mean, --linear).
    pub headless: bool,
    pub moving: bool,
    pub taa: bool,
}

pub fn fail(msg: &str) -> ! {
    eprintln!("sponza: {msg}");
    std::process::exit(2);
}

pub fn options() -> Options {
    let mut o = Options {
        scene: PathBuf::from(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../shared/assets/scenes/crytek_sponza/Sponza.gltf"
        )),
        scene_given: false,
        technique: "vbgi".into(),
        quality: NearFieldQuality::High,
        volume: None,
        env: None,
        env_intensity: 1.0,
        exposure: None,
        size: (1280, 720),
        screenshot: None,
        mean: false,
        linear: None,
        frames: 60,
        bench: false,
        bench_frames: 30,
        headless: false,
        moving: false,
        taa: false,
    };
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let mut value = || {
            args.next()
                .unwrap_or_else(|| fail(&format!("{a} needs a value")))
        };
        match a.as_str() {
            "--technique" => o.technique = value(),
            "--quality" => {
                o.quality = match value().as_str() {
                    "low" => NearFieldQuality::Low,
                    "medium" => NearFieldQuality::Medium,
                    "high" => NearFieldQuality::High,
                    "ultra" => NearFieldQuality::Ultra,
                    q => fail(&format!("--quality {q}: one of low, medium, high, ultra")),
                }
            }
            "--volume" => o.volume = Some(value().into()),
            "--env" => o.env = Some(value()),
            "--env-intensity" => {
                let v = value();
                o.env_intensity = v
                    .parse()
                    .ok()
                    .filter(|k: &f32| k.is_finite() && *k > 0.0)
                    .unwrap_or_else(|| fail(&format!("--env-intensity {v}: a number > 0")))
            }
            "--exposure" => {
                let v = value();
                o.exposure = Some(
                    v.parse()
                        .ok()
                        .filter(|e: &f32| (-20.0..=20.0).contains(e))
                        .unwrap_or_else(|| fail(&format!("--exposure {v}: stops in -20..=20"))),
                )
            }
            "--screenshot" => o.screenshot = Some(value().into()),
            "--frames" => {
                o.frames = value()
                    .parse()
                    .ok()
                    .filter(|n| *n > 0)
                    .unwrap_or_else(|| fail("--frames: a whole number > 0"))
            }
            "--size" => {
                let v = value();
                o.size = v
                    .split_once('x')
                    .and_then(|(w, h)| Some((w.parse().ok()?, h.parse().ok()?)))
                    .filter(|(w, h)| *w > 0 && *h > 0 && *w <= 8192 && *h <= 8192)
                    .unwrap_or_else(|| fail(&format!("--size {v}: WxH, each 1..=8192")))
            }
            "--bench" => o.bench = true,
            "--bench-frames" => {
                o.bench_frames = value()
                    .parse()
                    .ok()
                    .filter(|n| (1..=10_000).contains(n))
                    .unwrap_or_else(|| fail("--bench-frames: a whole number in 1..=10000"))
            }
            "--headless" => o.headless = true,
            "--mean" => o.mean = true,
            "--linear" => {
                o.linear = Some(value().into());
                o.mean = true;
            }
            "--move" => o.moving = true,
            "--taa" => o.taa = true,
            s if !s.starts_with("--") => {
                o.scene = s.into();
                o.scene_given = true;
            }
            s => fail(&format!("unknown option {s}")),
        }
    }
    if !BENCH.contains(&o.technique.as_str()) {
        fail(&format!(
            "--technique {}: one of {}",
            o.technique,
            BENCH.join(", ")
        ));
    }
    o
}
