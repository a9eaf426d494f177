//! `nearfield reference`: the CPU ground truth of one AOV, cached.

use crate::BadInput;
use crate::options::{Loaded, SceneOpts};
use anyhow::Result;
use clap::Args;
use nearfield_reference::{ReferenceAov, ReferenceImage, ReferenceSettings, cache, exr_io};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Bumped whenever the reference's results change for the same inputs (invalidates caches).
const REFERENCE_VERSION: u32 = 4;

/// Reference options shared by `reference` and `compare`.
#[derive(Args, Debug, Clone)]
pub struct ReferenceOpts {
    /// Samples per pixel of the reference (1..=1048576).
    #[arg(long, default_value_t = 64)]
    pub spp: u32,
    /// Path length limit of the `radiance` path tracer (segments, ≥ 1).
    #[arg(long, default_value_t = 5)]
    pub max_depth: u32,
    /// Ignore and do not update the reference cache.
    #[arg(long)]
    pub no_cache: bool,
    /// Worker threads (default: all cores); results do not depend on it.
    #[arg(long)]
    pub threads: Option<usize>,
    /// What the senders of indirect-irradiance (and diffuse) emit: physical (their direct light
    /// with shadows, docs/src/aovs.md) or unshadowed (V ≡ 1 at the sender, for analysis).
    #[arg(long, default_value = "physical")]
    pub senders: String,
}

#[derive(Args, Debug)]
pub struct ReferenceArgs {
    #[command(flatten)]
    pub scene: SceneOpts,
    #[command(flatten)]
    pub reference: ReferenceOpts,
    /// Near-field radius R in metres (≥ 0, or inf); 0 = nothing is near.
    #[arg(long, default_value = "inf", allow_hyphen_values = true)]
    pub radius: String,
    /// Seed of the reference's sample sequences.
    #[arg(long, default_value_t = 0)]
    pub seed: u32,
    /// AOV: ao, env-irradiance, light-irradiance, indirect-irradiance, diffuse, radiance, albedo,
    /// normal, depth.
    #[arg(long, default_value = "ao")]
    pub aov: String,
    /// Output EXR (R, G, B, A, stderr.R/G/B, Z). Default: reference-AOV.exr.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
}

pub fn parse_radius(s: &str) -> Result<f32> {
    if s == "inf" {
        return Ok(f32::INFINITY);
    }
    let v: f32 = s
        .parse()
        .map_err(|_| BadInput(format!("--radius {s}: expected a number ≥ 0 or inf")))?;
    if v.is_nan() || v < 0.0 {
        return Err(BadInput(format!("--radius {s}: must be ≥ 0 (or inf)")).into());
    }
    Ok(v)
}

pub fn parse_aov(s: &str) -> Result<ReferenceAov> {
    ReferenceAov::parse(s).ok_or_else(|| {
        BadInput(format!(
            "--aov {s}: the reference does not compute it (known: {})",
            ReferenceAov::names().join(", ")
        ))
        .into()
    })
}

impl ReferenceOpts {
    pub fn settings(
        &self,
        aov: ReferenceAov,
        size: (u32, u32),
        radius: f32,
        seed: u32,
    ) -> Result<ReferenceSettings> {
        if self.spp == 0 || self.spp > 1 << 20 {
            return Err(BadInput(format!("--spp {}: must be in 1..=1048576", self.spp)).into());
        }
        if self.max_depth == 0 || self.max_depth > 1000 {
            return Err(BadInput(format!(
                "--max-depth {}: must be in 1..=1000",
                self.max_depth
            ))
            .into());
        }
        if let Some(t) = self.threads
            && (t == 0 || t > 4096)
        {
            return Err(BadInput(format!("--threads {t}: must be in 1..=4096")).into());
        }
        let senders = nearfield_reference::Senders::parse(&self.senders).ok_or_else(|| {
            BadInput(format!(
                "--senders {}: expected {}",
                self.senders,
                nearfield_reference::Senders::NAMES.join(" or ")
            ))
        })?;
        Ok(ReferenceSettings {
            aov,
            size,
            radius,
            spp: self.spp,
            seed,
            max_depth: self.max_depth,
            senders,
        })
    }
}

/// A fingerprint of the scene's content (geometry, materials, lights), so that a changed file
/// or built-in scene never meets a stale cache entry.
pub fn scene_fingerprint(scene: &nearfield_scene::Scene) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = std::collections::hash_map::DefaultHasher::new();
    for m in &scene.meshes {
        m.material.hash(&mut h);
        for p in m.positions.iter().chain(&m.normals) {
            p.to_array().map(f32::to_bits).hash(&mut h);
        }
        m.indices.hash(&mut h);
    }
    format!("{:?}|{:?}", scene.materials, scene.lights).hash(&mut h);
    h.finish()
}

/// The cache key's description of everything the result depends on.
fn describe(opts: &SceneOpts, loaded: &Loaded, s: &ReferenceSettings) -> String {
    let c = loaded.camera;
    format!(
        "v{REFERENCE_VERSION}|{}|scene={}|content={:016x}|env={}|intensity={}|rotation={}|eye={}|target={}|up={}|yfov={}|size={}x{}|aov={}|radius={}|spp={}|seed={}|depth={}|senders={}|sun={}",
        env!("CARGO_PKG_VERSION"),
        cache::describe_input(&opts.scene),
        scene_fingerprint(&loaded.scene),
        cache::describe_input(&loaded.env_source.to_string()),
        opts.env_intensity,
        opts.env_rotation,
        c.eye,
        c.target,
        c.up,
        c.yfov,
        s.size.0,
        s.size.1,
        s.aov.name(),
        // One cache entry for every R where the image does not depend on it.
        if s.aov.depends_on_radius() {
            s.radius
        } else {
            f32::INFINITY
        },
        s.spp,
        s.seed,
        s.max_depth,
        s.senders.name(),
        opts.sun
    )
}

/// Renders the reference or takes it from the cache. Returns the image and the cache path used.
pub fn compute(
    opts: &SceneOpts,
    ref_opts: &ReferenceOpts,
    loaded: &Loaded,
    settings: &ReferenceSettings,
) -> Result<(ReferenceImage, Option<PathBuf>)> {
    if let Some(t) = ref_opts.threads {
        // Only the first call configures the global pool; later ones keep it.
        let _ = rayon::ThreadPoolBuilder::new()
            .num_threads(t)
            .build_global();
    }
    let key = describe(opts, loaded, settings);
    let path = cache::path_for(&key);
    if !ref_opts.no_cache
        && let Ok(img) = exr_io::read(&path)
        && (img.width, img.height) == settings.size
    {
        eprintln!("nearfield: reference from cache {}", path.display());
        return Ok((img, Some(path)));
    }
    let t0 = Instant::now();
    let img =
        nearfield_reference::render(&loaded.scene, &loaded.env, &loaded.camera, settings, true);
    let secs = t0.elapsed().as_secs_f64();
    eprintln!(
        "nearfield: reference {} {}×{} at {} spp: {:.2} M rays in {:.2} s = {:.2} M rays/s",
        settings.aov.name(),
        settings.size.0,
        settings.size.1,
        settings.spp,
        img.rays as f64 * 1e-6,
        secs,
        img.rays as f64 * 1e-6 / secs.max(1e-9)
    );
    if ref_opts.no_cache {
        return Ok((img, None));
    }
    if let Some(dir) = path.parent()
        && std::fs::create_dir_all(dir).is_ok()
        && exr_io::write(&img, &path).is_ok()
    {
        return Ok((img, Some(path)));
    }
    log::warn!("could not write the reference cache {}", path.display());
    Ok((img, None))
}

pub fn run(args: ReferenceArgs) -> Result<()> {
    let aov = parse_aov(&args.aov)?;
    let size = crate::options::parse_size(&args.scene.size)?;
    let radius = parse_radius(&args.radius)?;
    let settings = args.reference.settings(aov, size, radius, args.seed)?;
    let output = args
        .output
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("reference-{}.exr", aov.name())));
    check_exr_output(&output)?;
    let loaded = args.scene.load()?;
    loaded.report_sun();
    let (img, _) = compute(&args.scene, &args.reference, &loaded, &settings)?;
    crate::output::save_atomically(&output, |tmp| exr_io::write(&img, tmp).map_err(Into::into))?;
    eprintln!("nearfield: wrote {}", output.display());
    Ok(())
}

fn check_exr_output(path: &Path) -> Result<()> {
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
    if !ext.eq_ignore_ascii_case("exr") {
        return Err(BadInput(format!(
            "{}: the reference is written as .exr",
            path.display()
        ))
        .into());
    }
    crate::output::check_parent_dir(path)
}
