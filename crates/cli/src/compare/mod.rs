//! `nearfield compare`: techniques against the reference for one AOV → DIR/metrics.json,
//! DIR/report.html and PNGs.

use crate::BadInput;
use crate::options::{SceneOpts, TechniqueOpts};
use crate::reference::{ReferenceOpts, parse_aov};
use anyhow::{Context, Result};
use clap::Args;
use judge::Judge;
use nearfield_eval::metrics::{self, Mask, MaskSettings};
use nearfield_eval::report::Report;
use nearfield_reference::ReferenceAov;
use nearfield_reference::{ReferenceImage, exr_io};
use nearfield_render::{Aov, RenderSettings, Renderer, TechniqueParams};
use std::path::PathBuf;
use truths::Truths;

mod frames;
mod judge;
mod truths;

#[derive(Args, Debug)]
pub struct CompareArgs {
    #[command(flatten)]
    pub scene: SceneOpts,
    #[command(flatten)]
    pub technique: TechniqueOpts,
    #[command(flatten)]
    pub reference: ReferenceOpts,
    #[command(flatten)]
    pub far: crate::far::FarOpts,
    /// Techniques, comma-separated (default: every registered one).
    #[arg(long)]
    pub methods: Option<String>,
    /// AOV to compare: ao, env-irradiance, light-irradiance, indirect-irradiance, diffuse,
    /// radiance, lambertian (emission + diffuse, against the reference's path-traced radiance,
    /// which has Lambertian surfaces), albedo, normal, depth.
    #[arg(long, default_value = "ao")]
    pub aov: String,
    /// Frames each technique renders before its AOV is read (≥ 1; default 1, or a camera path's
    /// frames). With more than one frame and a still camera the report also plots the error
    /// after every frame (up to 64 frames; beyond, after powers of two and the last).
    #[arg(long)]
    pub frames: Option<u32>,
    /// Degrees the camera turns about its target before every frame after the first; the
    /// reference is rendered from the last frame's camera.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub orbit: f32,
    #[command(flatten)]
    pub motion: crate::options::MotionOpts,
    /// With a camera path: measure every K-th frame (and the last), each against the reference
    /// from that frame's camera (traced per frame, cached).
    #[arg(long, default_value_t = 1)]
    pub every: u32,
    /// Use this reference EXR instead of rendering (or loading from the cache) one; it must have
    /// the image size.
    #[arg(long = "reference")]
    pub reference_file: Option<PathBuf>,
    /// Excluded band at the image edge in pixels. Default: 2 % of the smaller side, at least 2.
    #[arg(long)]
    pub border: Option<u32>,
    /// Restrict the metrics to the pixel rectangle X0,Y0,X1,Y1 (x0 ≤ x < x1, y0 ≤ y < y1), e.g.
    /// the region an effect is about.
    #[arg(long)]
    pub region: Option<String>,
    /// Output folder.
    #[arg(long, default_value = "compare")]
    pub out: PathBuf,
    /// Also write one PNG strip of the methods' images and the reference side by side, each
    /// labelled with its name and its relative error (--image's images first; the PNGs and the
    /// strip at --exposure).
    #[arg(long)]
    pub strip: Option<PathBuf>,
    /// With --strip: each method's signed error heat map right of its image (blue: too dark,
    /// red: too bright, grey: excluded), labelled with its range.
    #[arg(long, requires = "strip")]
    pub strip_errors: bool,
    /// Also measure each technique's footprint of the scene's dynamic objects (`--dynamic`,
    /// `--add`, a *-dynamic built-in): the change they make to the ambient light around them,
    /// against the path tracer's (the book, "Near and far").
    #[arg(long)]
    pub footprint: bool,
    /// Also measure an image made elsewhere, NAME=FILE.exr (repeatable; RGB of the AOV at the
    /// image size, e.g. another engine's AO from `peers/bevy_ssao`), with the same mask and
    /// metrics as the techniques, beside them in the report.
    #[arg(long = "image", value_name = "NAME=FILE.exr")]
    pub images: Vec<String>,
}

/// `--image NAME=FILE.exr`: the name and the image, which must have `size`.
fn read_images(specs: &[String], size: (u32, u32)) -> Result<Vec<(String, Vec<[f32; 4]>)>> {
    let mut out: Vec<(String, Vec<[f32; 4]>)> = Vec::new();
    for spec in specs {
        let (name, path) = spec
            .split_once('=')
            .filter(|(n, p)| !n.trim().is_empty() && !p.trim().is_empty())
            .ok_or_else(|| BadInput(format!("--image {spec}: expected NAME=FILE.exr")))?;
        let name = name.trim().to_string();
        if !name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "-_.".contains(c))
            || name.starts_with('.')
        {
            return Err(BadInput(format!(
                "--image {spec}: the name may hold letters, digits, '-', '_' and '.' only"
            ))
            .into());
        }
        if out.iter().any(|(n, _)| *n == name) || nearfield_render::technique::find(&name).is_ok() {
            return Err(BadInput(format!(
                "--image {spec}: the name {name} is taken (by another image or a technique)"
            ))
            .into());
        }
        let img = read_exr(std::path::Path::new(path.trim()), size, "image")?;
        out.push((name, img.value));
    }
    Ok(out)
}

/// `--region X0,Y0,X1,Y1` inside an image of `size`.
fn parse_region(s: &str, size: (u32, u32)) -> Result<[u32; 4]> {
    let bad = || {
        BadInput(format!(
            "--region {s}: expected X0,Y0,X1,Y1 with 0 ≤ X0 < X1 ≤ {} and 0 ≤ Y0 < Y1 ≤ {}",
            size.0, size.1
        ))
    };
    let v: Vec<u32> = s
        .split(',')
        .map(|p| p.trim().parse::<u32>())
        .collect::<Result<_, _>>()
        .map_err(|_| bad())?;
    match v[..] {
        [x0, y0, x1, y1] if x0 < x1 && y0 < y1 && x1 <= size.0 && y1 <= size.1 => {
            Ok([x0, y0, x1, y1])
        }
        _ => Err(bad().into()),
    }
}

/// The one near-field radius of a comparison: `params.radius` (given, or auto from the far
/// field), else the techniques' own defaults, which must agree (`none` has none); inf when no
/// technique has a radius.
fn common_radius(methods: &[String], params: &nearfield_render::TechniqueParams) -> Result<f32> {
    if let Some(r) = params.radius {
        return Ok(r);
    }
    let mut radius: Option<(f32, &str)> = None;
    for m in methods {
        if let Some(r) = nearfield_render::technique::radius_of(m, params)? {
            match radius {
                Some((r0, m0)) if r0 != r => {
                    return Err(BadInput(format!(
                        "{m0} and {m} have different radii ({r0} and {r} m): give one with --radius"
                    ))
                    .into());
                }
                _ => radius = Some((r, m)),
            }
        }
    }
    Ok(radius.map_or(f32::INFINITY, |(r, _)| r))
}

/// What is known of a comparison before the scene loads: every argument checked.
struct Checked {
    ref_aov: ReferenceAov,
    gpu_aov: Aov,
    methods: Vec<String>,
    size: (u32, u32),
    border: u32,
    region: Option<[u32; 4]>,
    params: TechniqueParams,
    settings: RenderSettings,
    /// `--reference-file`: the image and its path.
    reference_file: Option<(ReferenceImage, PathBuf)>,
    /// `--image NAME=FILE`: images made elsewhere.
    images: Vec<(String, Vec<[f32; 4]>)>,
    /// `--path FILE`: the camera path, read.
    path_file: Option<nearfield_scene::CameraPath>,
}

impl Checked {
    fn new(args: &CompareArgs) -> Result<Self> {
        // The reference's radiance is Lambertian: it is the truth for the GPU's `lambertian`.
        let ref_name = if args.aov == "lambertian" {
            "radiance"
        } else {
            args.aov.as_str()
        };
        let ref_aov = parse_aov(ref_name)?;
        let gpu_aov = Aov::parse(&args.aov).expect("every reference AOV is a renderer AOV");
        let frames = args.frames.unwrap_or(1);
        let methods = crate::options::methods_and_frames(args.methods.as_deref(), frames)?;
        let path_file = args.motion.check(args.orbit)?;
        if args.every == 0 {
            return Err(BadInput("--every 0: must be at least 1".into()).into());
        }
        let size = crate::options::parse_size(&args.scene.size)?;
        let border = args.border.unwrap_or_else(|| default_border(size));
        if 2 * border >= size.0.min(size.1) {
            return Err(BadInput(format!(
                "--border {border}: leaves no pixel of a {}x{} image",
                size.0, size.1
            ))
            .into());
        }
        let region = args
            .region
            .as_deref()
            .map(|r| parse_region(r, size))
            .transpose()?;
        let params = args.technique.params()?;
        let settings = args.technique.settings(size)?;
        let reference_file = match &args.reference_file {
            Some(p) => Some((read_exr(p, size, "reference")?, p.clone())),
            None => None,
        };
        let images = read_images(&args.images, size)?;
        args.far.precheck()?;
        if let Some(p) = &args.strip {
            if p.extension().and_then(|e| e.to_str()) != Some("png") {
                return Err(
                    BadInput(format!("--strip {}: must be a .png file", p.display())).into(),
                );
            }
            crate::output::check_parent_dir(p)?;
        }
        Ok(Checked {
            ref_aov,
            gpu_aov,
            methods,
            size,
            border,
            region,
            params,
            settings,
            reference_file,
            images,
            path_file,
        })
    }
}

/// An EXR of the comparison's size (`what` names it in the error).
fn read_exr(p: &std::path::Path, size: (u32, u32), what: &str) -> Result<ReferenceImage> {
    let img = exr_io::read(p).map_err(|e| BadInput(e.to_string()))?;
    if (img.width, img.height) != size {
        return Err(BadInput(format!(
            "{}: {what} is {}x{}, the comparison is {}x{}",
            p.display(),
            img.width,
            img.height,
            size.0,
            size.1
        ))
        .into());
    }
    Ok(img)
}

pub fn run(args: CompareArgs) -> Result<()> {
    let Checked {
        ref_aov,
        gpu_aov,
        methods,
        size,
        border,
        region,
        mut params,
        settings,
        reference_file,
        images,
        path_file,
    } = Checked::new(&args)?;
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create {}", args.out.display()))?;
    let files = (path_file, reference_file);
    let t = Truths::new(&args, files, (&methods, &mut params), (ref_aov, size))?;
    let frames = methods.len() as u64 * u64::from(t.run.frames);
    let progress = nearfield_scene::progress::Progress::new("compare", frames, "frames", true);
    let mask_settings = MaskSettings {
        border,
        depth_tolerance: 0.01,
    };
    let judge = Judge::new(
        &args,
        &t.reference,
        size,
        &progress,
        (mask_settings, region),
    )?;
    for m in &t.along {
        judge.reference_png(m.frame + 1, &m.truth)?;
    }
    // One renderer of `method` over `scene`, with the far field every method shares.
    let renderer = |scene: &nearfield_scene::Scene, method: &str| -> Result<Renderer> {
        Ok(Renderer::new(
            &t.ctx,
            scene,
            &t.loaded.env,
            t.volume.as_ref(),
            t.run.camera(0),
            &nearfield_render::technique::Spec::resolve(method, &params)?,
            settings,
        )?)
    };
    let (run, along) = (&t.run, &t.along);
    let mut reports = Vec::new();
    let mut panels = Vec::new();
    let mut last_mask = None;
    for method in &methods {
        progress.set_message(method);
        let mut r = renderer(&t.loaded.scene, method)?;
        t.loaded.report_sun();
        let f = run.frames((method, &mut r), gpu_aov, &judge, along)?;
        let (value, mask) = (&f.value, &f.mask);
        let mut report = judge.measure(method, &value.pixels, mask, f.convergence, &mut panels)?;
        if !f.path.is_empty() {
            let make = || renderer(&t.loaded.scene, method);
            let path = (f.path, f.change, f.shown);
            run.figures(&mut report, path, &make, (gpu_aov, &judge, along))?;
            progress.suspend(|| println!("{}", frames::path_line(&report)));
        }
        if let Some((truth, without)) = &t.footprint {
            let mut without = renderer(&without.scene, method)?;
            let motion = (&run.motion, run.frames);
            let e = judge.footprint(method, truth, &mut r, &mut without, motion)?;
            report.footprint = Some(e);
        }
        reports.push(report);
        last_mask = Some(f.mask);
    }
    progress.finish();
    let mask = last_mask.expect("at least one method");
    // The volume alone: its radiance through the exact visibility V_R, on the CPU (a row named
    // `volume`), so that its error shows apart from any technique's estimate of V_R.
    if let (Some(v), Aov::FarIrradiance) = (&t.volume, gpu_aov) {
        let (scene, env, camera) = (&t.loaded.scene, &t.loaded.env, &t.loaded.camera);
        let img =
            nearfield_reference::render_volume_far(scene, env, camera, &t.ref_settings, v, false);
        reports.push(judge.measure("volume", &img.value, &mask, Vec::new(), &mut panels)?);
    }
    elsewhere(&judge, &images, &mask, (&mut reports, &mut panels))?;
    if let Some(path) = &args.strip {
        let far = t.volume.as_ref().map(|v| v.grid.spacing.max_element());
        judge.strip(path, panels, &t.ref_info, far, t.radius)?;
    }
    let reference = &t.reference;
    let report = Report {
        scene: args.scene.scene.clone(),
        aov: args.aov.clone(),
        size: [size.0, size.1],
        radius: t.radius.to_string(),
        adapter: nearfield_render::context::describe(&t.ctx.adapter_info()),
        reference: t.ref_info.clone(),
        mask: mask_settings,
        region,
        silhouette_pixels: mask.silhouette_pixels,
        depth_checked: mask.depth_checked,
        reference_noise: metrics::rms_stderr(&reference.stderr, &mask),
        reference_relative_noise: metrics::relative_stderr(
            &reference.stderr,
            &reference.value,
            &mask,
        ),
        methods: reports,
    };
    write_report(&args.out, &report, border)
}

/// Images made elsewhere (`--image`), measured with the last technique's mask (same scene,
/// camera and reference); in the strip before the techniques.
fn elsewhere(
    judge: &Judge,
    images: &[(String, Vec<[f32; 4]>)],
    mask: &Mask,
    (reports, panels): (
        &mut Vec<nearfield_eval::report::MethodReport>,
        &mut Vec<nearfield_eval::strip::Panel>,
    ),
) -> Result<()> {
    let mut first = Vec::new();
    for (name, pixels) in images {
        reports.push(judge.measure(name, pixels, mask, Vec::new(), &mut first)?);
    }
    panels.splice(0..0, first);
    Ok(())
}

/// Writes the report and says where.
fn write_report(out: &std::path::Path, report: &Report, border: u32) -> Result<()> {
    eprintln!(
        "nearfield: the reference's relative noise Σσ/Σref is {:.4}",
        report.reference_relative_noise
    );
    nearfield_eval::report::write(out, report)
        .with_context(|| format!("cannot write the report into {}", out.display()))?;
    eprintln!(
        "nearfield: wrote {}/report.html and metrics.json (border {border} px, {} silhouette pixels excluded)",
        out.display(),
        report.silhouette_pixels
    );
    Ok(())
}

/// The excluded band at the image edge without `--border`: 2 % of the smaller side, at least 2
/// pixels (also `fit`'s, so that both measure the same pixels).
pub(crate) fn default_border((w, h): (u32, u32)) -> u32 {
    ((w.min(h) as f32 * 0.02) as u32).max(2)
}

/// The last component of `p` (reports name no directories).
fn file_name(p: &std::path::Path) -> String {
    p.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| p.display().to_string())
}

/// The comparison mask: GPU and reference coverage and depth (silhouettes excluded), within
/// `region` if given.
pub(crate) fn gpu_mask(
    r: &mut Renderer,
    value: &nearfield_render::AovImage,
    ref_alpha: &[f32],
    ref_depth: &[f32],
    settings: MaskSettings,
    region: Option<[u32; 4]>,
) -> Mask {
    let depth = r.read_aov(Aov::Depth);
    let alpha: Vec<f32> = value.pixels.iter().map(|p| p[3]).collect();
    let gpu_depth: Vec<f32> = depth.pixels.iter().map(|p| p[0]).collect();
    let mut mask = Mask::new(
        (value.width, value.height),
        &alpha,
        &gpu_depth,
        ref_alpha,
        ref_depth,
        settings,
    );
    if let Some(rect) = region {
        mask.restrict(rect);
    }
    mask
}
