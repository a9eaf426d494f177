//! The far field of every command (`--far auto|sky|volume`, `--volume FILE`) and `nearfield
//! bake`: a probe volume traced by the reference's BVH (`nearfield_reference::bake`), cached
//! like the reference (the book, "The far field").

use crate::BadInput;
use crate::options::{Loaded, SceneOpts};
use anyhow::Result;
use clap::Args;
use nearfield_reference::bake::{self, BakeSettings};
use nearfield_reference::cache;
use nearfield_scene::probes::{ProbeGrid, ProbeVolume};
use nearfield_scene::{Environment, Scene};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Bumped whenever a bake's result changes for the same inputs (invalidates cached volumes).
pub const BAKE_VERSION: u32 = 1;

/// What lights the directions a technique finds unoccluded within R.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Far {
    /// `volume`, except for the near-field AOVs whose definitions see the open sky beyond R
    /// (`env-irradiance`, `indirect-irradiance` and their sum `diffuse`), which get `sky`.
    Auto,
    /// The environment, unoccluded beyond R.
    Sky,
    /// The scene's probe volume (baked and cached, or `--volume FILE`).
    Volume,
}

impl Far {
    pub const NAMES: [&'static str; 3] = ["auto", "sky", "volume"];

    pub fn parse(s: &str) -> Result<Self> {
        match s {
            "auto" => Ok(Far::Auto),
            "sky" => Ok(Far::Sky),
            "volume" => Ok(Far::Volume),
            _ => Err(BadInput(format!("--far {s}: expected {}", Far::NAMES.join(", "))).into()),
        }
    }

    /// Whether the frame uses the volume for `aov` (an AOV name, or `A1+A2` as `fit` takes
    /// them; `None`: the image). `auto` gives the sky when any of them is `ao`,
    /// `env-irradiance`, `indirect-irradiance` or `diffuse` (ρ × the sum of the two with
    /// `light-irradiance`), so that every near-field AOV keeps its definition
    /// (docs/src/aovs.md): a technique's settings for a volume (`with_volume`) are for the
    /// image, and would change what its `ao` estimates.
    pub fn volume_for(self, aov: Option<&str>) -> bool {
        match self {
            Far::Sky => false,
            Far::Volume => true,
            Far::Auto => !aov.is_some_and(|a| {
                a.split('+').any(|p| {
                    matches!(
                        p.trim(),
                        "ao" | "env-irradiance" | "indirect-irradiance" | "diffuse"
                    )
                })
            }),
        }
    }
}

/// `--far` and `--volume`, shared by every command that renders.
#[derive(Args, Clone, Debug)]
pub struct FarOpts {
    /// The far field, what the directions a technique finds unoccluded within R see: `sky` (the
    /// environment, unoccluded), `volume` (the scene's probe volume, baked on first use and
    /// cached; `nearfield bake`), or `auto`: the volume, except for ao, env-irradiance,
    /// indirect-irradiance and diffuse, whose definitions see the open sky.
    #[arg(long, default_value = "auto")]
    pub far: String,
    /// A probe volume written by `nearfield bake --out` instead of the cached default bake
    /// (implies `--far volume`).
    #[arg(long)]
    pub volume: Option<PathBuf>,
    /// The bake's grid and rays when the volume is baked here (cached like any bake).
    #[command(flatten)]
    pub grid: GridOpts,
}

/// The far field a command will use, known before anything is baked: its grid sets the
/// near-field radius `--radius auto`, and a technique's settings are checked against that
/// radius before the bake and the reference run.
pub enum FarPlan {
    /// The open sky beyond R.
    Sky,
    /// A volume read from `--volume FILE`.
    File(ProbeVolume),
    /// The cached bake of these settings.
    Bake(BakeSettings),
}

impl FarPlan {
    /// The largest distance between neighbouring probes (m), `None` for the sky.
    pub fn spacing(&self) -> Option<f32> {
        match self {
            FarPlan::Sky => None,
            FarPlan::File(v) => Some(v.grid.spacing.max_element()),
            FarPlan::Bake(s) => Some(s.grid.spacing.max_element()),
        }
    }

    /// The volume itself: read, baked or taken from the cache; `None` for the sky.
    pub fn volume(self, scene_opts: &SceneOpts, loaded: &Loaded) -> Result<Option<ProbeVolume>> {
        match self {
            FarPlan::Sky => Ok(None),
            FarPlan::File(v) => Ok(Some(v)),
            FarPlan::Bake(settings) => Ok(Some(baked(scene_opts, loaded, &settings, false)?.0)),
        }
    }
}

/// The near-field radius R of `--radius auto` (the default of every command that renders):
/// with a probe volume the largest distance between its probes, so that the near field covers
/// what the volume cannot resolve and no more (the book, "Near and far"); under the sky the
/// technique's own default (`None`).
pub fn auto_radius(plan: &FarPlan) -> Option<f32> {
    plan.spacing()
}

/// `--radius auto` (the default, `None` in `params`): [`auto_radius`] with a volume, the
/// technique's own radius under the sky.
pub fn apply_auto_radius(params: &mut nearfield_render::TechniqueParams, plan: &FarPlan) {
    if params.radius.is_none() {
        params.radius = auto_radius(plan);
    }
}

/// The grid and tracing options of a bake.
#[derive(Args, Clone, Debug)]
pub struct GridOpts {
    /// Largest distance between neighbouring probes (m, > 0). Default: 1 m, coarser where the
    /// scene's bounds would need more than 16384 probes.
    #[arg(long, conflicts_with = "probes")]
    pub spacing: Option<f32>,
    /// Probes per axis, X,Y,Z (each ≥ 1; at most 65536 in all).
    #[arg(long)]
    pub probes: Option<String>,
    /// Rays per probe (1..=16384). Default: 512, 1024 for scenes of over 80 000 triangles.
    #[arg(long)]
    pub rays: Option<u32>,
    /// Bounces: how often the rays' hits are lit by the volume of the bounce before (0..=64; 0
    /// = emission and direct light only).
    #[arg(long, default_value_t = bake::DEFAULT_BOUNCES)]
    pub bounces: u32,
}

/// The default grid, rays and bounces.
impl Default for GridOpts {
    fn default() -> Self {
        GridOpts {
            spacing: None,
            probes: None,
            rays: None,
            bounces: bake::DEFAULT_BOUNCES,
        }
    }
}

impl GridOpts {
    /// The bake's settings for `loaded`'s scene (the part the bake sees: no dynamic meshes),
    /// checked.
    pub fn settings(&self, loaded: &Loaded) -> Result<BakeSettings> {
        self.settings_for(&loaded.scene.baked_part())
    }

    /// Whether every option is its default.
    pub fn is_default(&self) -> bool {
        self.spacing.is_none()
            && self.probes.is_none()
            && self.rays.is_none()
            && self.bounces == bake::DEFAULT_BOUNCES
    }

    /// The bake's settings for `scene`, checked.
    pub fn settings_for(&self, scene: &Scene) -> Result<BakeSettings> {
        let bounds = scene.bounds();
        let grid = match (&self.probes, self.spacing) {
            (Some(p), _) => {
                let counts: Vec<u32> = p
                    .split(',')
                    .map(|x| x.trim().parse::<u32>())
                    .collect::<Result<_, _>>()
                    .map_err(|_| BadInput(format!("--probes {p}: expected three counts X,Y,Z")))?;
                let [x, y, z] = counts[..] else {
                    return Err(
                        BadInput(format!("--probes {p}: expected three counts X,Y,Z")).into(),
                    );
                };
                ProbeGrid::with_counts(bounds, [x, y, z])
            }
            (None, Some(s)) => ProbeGrid::with_spacing(bounds, s),
            (None, None) => bake::default_grid(scene),
        }
        .map_err(|e| BadInput(e.to_string()))?;
        let settings = BakeSettings {
            grid,
            rays: self.rays.unwrap_or_else(|| bake::default_rays(scene)),
            bounces: self.bounces,
        };
        settings.check().map_err(|e| BadInput(e.to_string()))?;
        Ok(settings)
    }

    /// Checks what can be checked before the scene is loaded.
    pub fn precheck(&self) -> Result<()> {
        if let Some(s) = self.spacing
            && !(s.is_finite() && s > 0.0)
        {
            return Err(BadInput(format!(
                "--spacing {s}: must be a finite number of metres > 0"
            ))
            .into());
        }
        if let Some(r) = self.rays
            && (r == 0 || r > bake::MAX_RAYS)
        {
            return Err(BadInput(format!("--rays {r}: must be in 1..={}", bake::MAX_RAYS)).into());
        }
        if self.bounces > bake::MAX_BOUNCES {
            return Err(BadInput(format!(
                "--bounces {}: must be in 0..={}",
                self.bounces,
                bake::MAX_BOUNCES
            ))
            .into());
        }
        Ok(())
    }
}

impl FarOpts {
    /// Checks `--far`, `--volume` and the grid's options before anything is loaded.
    pub fn precheck(&self) -> Result<Far> {
        let far = Far::parse(&self.far)?;
        if self.volume.is_some() && far == Far::Sky {
            return Err(
                BadInput("--volume with --far sky: a volume file is the far field".into()).into(),
            );
        }
        self.grid.precheck()?;
        if self.volume.is_some() && !self.grid.is_default() {
            return Err(BadInput(
                "--volume with --spacing, --probes, --rays or --bounces: the file's volume is baked already"
                    .into(),
            )
            .into());
        }
        if far == Far::Sky && !self.grid.is_default() {
            return Err(BadInput(
                "--far sky with --spacing, --probes, --rays or --bounces: there is no volume to bake"
                    .into(),
            )
            .into());
        }
        if let Some(p) = &self.volume
            && !p.is_file()
        {
            return Err(BadInput(format!("--volume {}: no such file", p.display())).into());
        }
        Ok(far)
    }

    /// What far field the command's frames use for `aov` (`None`: the image), before anything is
    /// baked: `--volume FILE`, the sky, or the bake of the grid options (cached).
    pub fn plan(&self, loaded: &Loaded, aov: Option<&str>) -> Result<FarPlan> {
        let far = self.precheck()?;
        if let Some(p) = &self.volume {
            return read_volume(p).map(FarPlan::File);
        }
        if !far.volume_for(aov) {
            return Ok(FarPlan::Sky);
        }
        Ok(FarPlan::Bake(self.grid.settings(loaded)?))
    }

    /// The probe volume the command's frames use for `aov` (`None`: the image), or `None` for the
    /// sky: [`Self::plan`], baked.
    pub fn resolve(
        &self,
        scene_opts: &SceneOpts,
        loaded: &Loaded,
        aov: Option<&str>,
    ) -> Result<Option<ProbeVolume>> {
        self.plan(loaded, aov)?.volume(scene_opts, loaded)
    }
}

/// Reads a volume file; a bad one is bad input (exit 2).
pub fn read_volume(path: &Path) -> Result<ProbeVolume> {
    ProbeVolume::read(path).map_err(|e| BadInput(e.to_string()).into())
}

/// What a bake is baked from, for its cache key: the scene and environment as the user named
/// them, and the loaded scene and environment themselves (whose content, lights and sun the key
/// also covers).
pub struct BakeInput<'a> {
    pub scene_name: &'a str,
    pub scene: &'a Scene,
    pub env_name: &'a str,
    pub env: &'a Environment,
}

impl BakeInput<'_> {
    /// The cache key's description of everything a bake depends on.
    fn describe(&self, s: &BakeSettings) -> String {
        let g = &s.grid;
        format!(
            "bake v{BAKE_VERSION} file v{}|{}|scene={}|content={:016x}|env={}|intensity={}|rotation={}|sun={:?}|origin={}|spacing={}|counts={:?}|rays={}|bounces={}",
            nearfield_scene::probes::VERSION,
            env!("CARGO_PKG_VERSION"),
            cache::describe_input(self.scene_name),
            crate::reference::scene_fingerprint(self.scene),
            cache::describe_input(self.env_name),
            self.env.intensity,
            self.env.rotation,
            self.env.sun,
            g.origin,
            g.spacing,
            g.counts,
            s.rays,
            s.bounces,
        )
    }
}

/// Path of the cached volume for a key.
fn cache_path(key: u64) -> PathBuf {
    cache::cache_dir()
        .join("volume")
        .join(format!("{key:016x}.nfv"))
}

/// Bakes `settings` for `loaded` or takes the volume from the cache (a cached file is used only
/// when it reads cleanly and carries the same key; anything else is baked again). Returns the
/// volume and whether it came from the cache.
pub fn baked(
    opts: &SceneOpts,
    loaded: &Loaded,
    settings: &BakeSettings,
    no_cache: bool,
) -> Result<(ProbeVolume, bool)> {
    let env_name = loaded.env_source.to_string();
    // Dynamic meshes (`--dynamic`, `--add`, extras) are not baked.
    let scene = loaded.scene.baked_part();
    let input = BakeInput {
        scene_name: &opts.scene,
        scene: &scene,
        env_name: &env_name,
        env: &loaded.env,
    };
    baked_from(&input, settings, no_cache, true, None)
}

/// [`baked`] of any scene and environment; `progress` prints the bake's progress on stderr,
/// `monitor` follows it from another thread (the viewer's background bakes).
pub fn baked_from(
    input: &BakeInput,
    settings: &BakeSettings,
    no_cache: bool,
    progress: bool,
    monitor: Option<&bake::Monitor>,
) -> Result<(ProbeVolume, bool)> {
    let key = cache::fnv1a(input.describe(settings).as_bytes());
    let path = cache_path(key);
    if !no_cache
        && let Ok(v) = ProbeVolume::read(&path)
        && v.key == key
    {
        return Ok((v, true));
    }
    let t0 = Instant::now();
    let mut volume = bake::bake(input.scene, input.env, *settings, progress, monitor)
        .map_err(|e| BadInput(e.to_string()))?;
    volume.key = key;
    if progress {
        let g = &settings.grid;
        eprintln!(
            "nearfield: baked {}×{}×{} probes ({} active, {} moved out of geometry), {} rays, {} bounces in {:.2} s",
            g.counts[0],
            g.counts[1],
            g.counts[2],
            volume.active_count(),
            volume
                .probes
                .iter()
                .filter(|p| p.offset != glam::Vec3::ZERO)
                .count(),
            settings.rays,
            settings.bounces,
            t0.elapsed().as_secs_f64()
        );
    }
    if !no_cache {
        let written = path
            .parent()
            .is_some_and(|d| std::fs::create_dir_all(d).is_ok())
            && volume.write(&path).is_ok();
        if !written {
            log::warn!("could not write the volume cache {}", path.display());
        }
    }
    Ok((volume, false))
}

#[derive(Args, Debug)]
pub struct BakeArgs {
    #[command(flatten)]
    pub scene: SceneOpts,
    #[command(flatten)]
    pub grid: GridOpts,
    /// Output file: `.nfv` (read by `--volume`) or, with `--format bevy`, `.ktx2`. Default:
    /// volume.nfv, or volume.ktx2 with `--format bevy`.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// `nfv` (nearfield's volume) or `bevy` (Bevy's `IrradianceVolume` ambient-cube texture,
    /// KTX2). Default: from the extension of `--out`, else nfv.
    #[arg(long)]
    pub format: Option<String>,
    /// Ignore and do not update the volume cache.
    #[arg(long)]
    pub no_cache: bool,
    /// Worker threads (default: all cores); results do not depend on it.
    #[arg(long)]
    pub threads: Option<usize>,
}

pub fn run(args: BakeArgs) -> Result<()> {
    args.grid.precheck()?;
    let (out, bevy) = bake_output(args.out.as_deref(), args.format.as_deref())?;
    crate::output::check_parent_dir(&out)?;
    if let Some(t) = args.threads {
        if t == 0 || t > 4096 {
            return Err(BadInput(format!("--threads {t}: must be in 1..=4096")).into());
        }
        let _ = rayon::ThreadPoolBuilder::new()
            .num_threads(t)
            .build_global();
    }
    let t0 = Instant::now();
    let loaded = args.scene.load()?;
    let settings = args.grid.settings(&loaded)?;
    loaded.report_sun();
    let t_bake = Instant::now();
    let (volume, cached) = baked(&args.scene, &loaded, &settings, args.no_cache)?;
    let bake_s = t_bake.elapsed().as_secs_f64();
    if bevy {
        write_bevy(&volume, &out)?;
    } else {
        volume.write(&out).map_err(anyhow::Error::msg)?;
    }
    let g = &volume.grid;
    eprintln!(
        "nearfield: wrote {} ({}×{}×{} probes at {:.3}×{:.3}×{:.3} m, {} active, {:.1} MB{}) in {:.2} s",
        out.display(),
        g.counts[0],
        g.counts[1],
        g.counts[2],
        g.spacing.x,
        g.spacing.y,
        g.spacing.z,
        volume.active_count(),
        volume.memory_bytes() as f64 / 1e6,
        if cached {
            format!(", read from the cache in {bake_s:.2} s")
        } else {
            String::new()
        },
        t0.elapsed().as_secs_f64()
    );
    Ok(())
}

/// The output path and whether it is Bevy's format, from `--out` and `--format`.
fn bake_output(out: Option<&Path>, format: Option<&str>) -> Result<(PathBuf, bool)> {
    let bevy = match format {
        None => out
            .and_then(|p| p.extension())
            .is_some_and(|e| e.eq_ignore_ascii_case("ktx2")),
        Some("nfv") => false,
        Some("bevy") => true,
        Some(f) => {
            return Err(BadInput(format!("--format {f}: expected nfv or bevy")).into());
        }
    };
    let (want, default) = if bevy {
        ("ktx2", "volume.ktx2")
    } else {
        ("nfv", "volume.nfv")
    };
    let out = out.map_or_else(|| PathBuf::from(default), Path::to_path_buf);
    let ext = out.extension().and_then(|e| e.to_str()).unwrap_or("");
    if !ext.eq_ignore_ascii_case(want) {
        return Err(BadInput(format!(
            "--out {}: {} is written as .{want}",
            out.display(),
            if bevy {
                "a Bevy irradiance volume"
            } else {
                "a probe volume"
            }
        ))
        .into());
    }
    Ok((out, bevy))
}

/// Writes Bevy's ambient-cube texture (KTX2) and says how to place it.
fn write_bevy(volume: &ProbeVolume, out: &Path) -> Result<()> {
    let b = nearfield_scene::probes::bevy::BevyVolume::from_volume(volume);
    let bytes = b.to_ktx2();
    crate::output::save_atomically(out, |tmp| {
        std::fs::write(tmp, &bytes).map_err(|e| anyhow::anyhow!("{}: {e}", out.display()))
    })?;
    eprintln!(
        "nearfield: Bevy irradiance volume {}×{}×{} texels ({:.1} MB): Transform translation ({:.4}, {:.4}, {:.4}), scale ({:.4}, {:.4}, {:.4}); IrradianceVolume intensity {}",
        b.size[0],
        b.size[1],
        b.size[2],
        bytes.len() as f64 / 1e6,
        b.translation.x,
        b.translation.y,
        b.translation.z,
        b.scale.x,
        b.scale.y,
        b.scale.z,
        b.intensity
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::Far;

    /// `auto` renders the near-field AOVs with the open sky of their definitions (a technique's
    /// settings for a volume, such as s3ho's fade, would change what its `ao` estimates) and
    /// the image AOVs with the volume (docs/src/aovs.md).
    #[test]
    fn auto_gives_the_near_field_aovs_the_sky() {
        for aov in [
            "ao",
            "env-irradiance",
            "indirect-irradiance",
            "diffuse",
            "ao+diffuse",
        ] {
            assert!(!Far::Auto.volume_for(Some(aov)), "{aov}");
            assert!(Far::Volume.volume_for(Some(aov)), "{aov}");
        }
        for aov in [
            None,
            Some("lambertian"),
            Some("radiance"),
            Some("far-irradiance"),
        ] {
            assert!(Far::Auto.volume_for(aov), "{aov:?}");
            assert!(!Far::Sky.volume_for(aov), "{aov:?}");
        }
    }
}
