//! How `compare` judges an image against the reference: its metrics, its PNGs and heat map, its
//! strip panels, a technique's footprint, and the strip.

use super::CompareArgs;
use anyhow::Result;
use nearfield_eval::image_ops;
use nearfield_eval::metrics::{self, Mask};
use nearfield_eval::report::{ConvergencePoint, MethodReport, ReferenceInfo};
use nearfield_eval::strip::{Panel, strip};
use nearfield_reference::ReferenceImage;
use nearfield_render::Renderer;
use nearfield_scene::progress::Progress;
use std::path::{Path, PathBuf};

/// The reference as every image is judged against it, and where the judgement goes.
pub(super) struct Judge<'a> {
    pub reference: &'a ReferenceImage,
    /// The reference's coverage.
    pub ref_alpha: Vec<f32>,
    /// The reference as the PNGs, the strip and FLIP see it (at `--exposure`).
    ref_srgb: image::RgbImage,
    gain: f32,
    size: (u32, u32),
    out: PathBuf,
    strip: bool,
    strip_errors: bool,
    pub progress: &'a Progress,
    /// The comparison mask's settings and `--region`.
    mask: (metrics::MaskSettings, Option<[u32; 4]>),
}

/// The report's line for a reference read from a file.
pub(super) fn file_info(name: &str) -> ReferenceInfo {
    ReferenceInfo {
        path: format!("file {name}"),
        spp: None,
        seed: None,
        image: "reference.png".into(),
    }
}

/// The report's line for a reference traced here (`path`: where it was cached).
pub(super) fn traced_info(
    path: String,
    settings: &nearfield_reference::ReferenceSettings,
) -> ReferenceInfo {
    ReferenceInfo {
        path,
        spp: Some(settings.spp),
        seed: Some(settings.seed),
        image: "reference.png".into(),
    }
}

/// Writes `img` as a PNG, whole or not at all.
pub(super) fn png(img: &image::RgbImage, path: &Path) -> Result<()> {
    crate::output::save_atomically(path, |tmp| {
        img.save_with_format(tmp, image::ImageFormat::Png)
            .map_err(anyhow::Error::from)
    })
}

impl<'a> Judge<'a> {
    /// Writes the reference's PNG.
    pub fn new(
        args: &CompareArgs,
        reference: &'a ReferenceImage,
        size: (u32, u32),
        progress: &'a Progress,
        mask: (metrics::MaskSettings, Option<[u32; 4]>),
    ) -> Result<Self> {
        let gain = 2f32.powf(args.technique.exposure);
        let ref_srgb = image_ops::tonemap_exposed(&reference.value, size.0, size.1, gain);
        png(&ref_srgb, &args.out.join("reference.png"))?;
        Ok(Judge {
            reference,
            ref_alpha: reference.value.iter().map(|p| p[3]).collect(),
            ref_srgb,
            gain,
            size,
            out: args.out.clone(),
            strip: args.strip.is_some(),
            strip_errors: args.strip_errors,
            mask,
            progress,
        })
    }

    /// Along a path: frame `n`'s image of `method` and its signed error against `truth` (the
    /// reference of that frame) as `frames/METHOD-NNNN.png` and `frames/METHOD-NNNN-error.png`,
    /// for the report's sequence; returns the first (the frame as the report shows it).
    pub fn frame_pngs(
        &self,
        method: &str,
        n: u32,
        pixels: &[[f32; 4]],
        truth: &ReferenceImage,
        mask: &Mask,
    ) -> Result<image::RgbImage> {
        let (w, h) = self.size;
        let dir = self.out.join("frames");
        std::fs::create_dir_all(&dir)?;
        let srgb = self.srgb(pixels);
        png(&srgb, &dir.join(format!("{method}-{n:04}.png")))?;
        let errors = metrics::signed_errors(pixels, &truth.value, mask);
        let range = image_ops::error_range(&errors, &mask.valid);
        let heat = image_ops::heatmap(&errors, &mask.valid, w, h, range);
        png(&heat, &dir.join(format!("{method}-{n:04}-error.png")))?;
        Ok(srgb)
    }

    /// An image as the report shows it: exposed, tone-mapped, 8-bit sRGB.
    pub fn srgb(&self, pixels: &[[f32; 4]]) -> image::RgbImage {
        let (w, h) = self.size;
        image_ops::tonemap_exposed(pixels, w, h, self.gain)
    }

    /// Along a path: the reference of frame `n` as `frames/reference-NNNN.png`.
    pub fn reference_png(&self, n: u32, truth: &ReferenceImage) -> Result<()> {
        let dir = self.out.join("frames");
        std::fs::create_dir_all(&dir)?;
        png(
            &self.srgb(&truth.value),
            &dir.join(format!("reference-{n:04}.png")),
        )
    }

    /// The comparison mask of a technique's image `value` against the reference.
    pub fn mask_of(&self, r: &mut Renderer, value: &nearfield_render::AovImage) -> Mask {
        let (settings, region) = self.mask;
        super::gpu_mask(
            r,
            value,
            &self.ref_alpha,
            &self.reference.depth,
            settings,
            region,
        )
    }

    /// The comparison mask of a technique's image `value` against `truth` (a path's frame).
    pub fn mask_against(
        &self,
        r: &mut Renderer,
        value: &nearfield_render::AovImage,
        truth: &ReferenceImage,
    ) -> Mask {
        let (settings, region) = self.mask;
        let alpha: Vec<f32> = truth.value.iter().map(|p| p[3]).collect();
        super::gpu_mask(r, value, &alpha, &truth.depth, settings, region)
    }

    /// One image's metrics, PNGs and strip panels: a technique's AOV or an `--image`.
    pub fn measure(
        &self,
        method: &str,
        pixels: &[[f32; 4]],
        mask: &Mask,
        convergence: Vec<ConvergencePoint>,
        panels: &mut Vec<Panel>,
    ) -> Result<MethodReport> {
        let (w, h) = self.size;
        let reference = &self.reference.value;
        let mut m = metrics::metrics(pixels, reference, mask);
        let srgb = image_ops::tonemap_exposed(pixels, w, h, self.gain);
        m.flip = Some(metrics::flip_mean(&srgb, &self.ref_srgb, mask));
        if self.strip {
            panels.push(Panel {
                image: srgb.clone(),
                title: method.to_string(),
                subtitle: format!("relative error {:.3}", m.relative_error),
            });
        }
        let errors = metrics::signed_errors(pixels, reference, mask);
        let range = image_ops::error_range(&errors, &mask.valid);
        let image = format!("{method}.png");
        let heat = format!("{method}-error.png");
        png(&srgb, &self.out.join(&image))?;
        let heatmap = image_ops::heatmap(&errors, &mask.valid, w, h, range);
        if self.strip_errors {
            panels.push(Panel {
                image: heatmap.clone(),
                title: format!("{method} − reference"),
                subtitle: format!("blue −{range:.3} … red +{range:.3}"),
            });
        }
        png(&heatmap, &self.out.join(&heat))?;
        self.progress.suspend(|| println!(
            "{method:<10} pixels {:>8}  bias {:+.5}  mean {:.3}x  MAE {:.5}  RMSE {:.5}  rel {:.4}  FLIP {:.4}",
            m.pixels,
            m.bias,
            m.mean_ratio,
            m.mae,
            m.rmse,
            m.relative_error,
            m.flip.unwrap_or(0.0)
        ));
        Ok(MethodReport {
            name: method.to_string(),
            metrics: m,
            error_range: range,
            image,
            heatmap: heat,
            convergence,
            footprint: None,
            path: Vec::new(),
            path_still: None,
            instability: None,
            video_jod: None,
            video_frames: None,
            settle: Vec::new(),
            settle_stops: Vec::new(),
        })
    }

    /// The footprint error of a technique (`with`, after its frames) against the truth's: the
    /// same frames over the scene without its dynamic objects (`without`), and both heat maps.
    pub fn footprint(
        &self,
        method: &str,
        truth: &crate::footprint::Truth,
        with: &mut Renderer,
        without: &mut Renderer,
        (motion, frames): (&crate::options::Motion, u32),
    ) -> Result<f64> {
        let with = crate::footprint::ambient_of(with);
        for i in 0..frames {
            motion.frame(without, i);
        }
        let without_ambient = crate::footprint::ambient_of(without);
        let e = truth.error(&with, &without_ambient);
        let (truth_map, map) = truth.heatmaps(&with, &without_ambient);
        png(&map, &self.out.join(format!("{method}-footprint.png")))?;
        png(&truth_map, &self.out.join("reference-footprint.png"))?;
        self.progress.suspend(|| {
            println!(
                "{method:<10} footprint {e:.4} over {} pixels",
                truth.pixels()
            )
        });
        Ok(e)
    }

    /// Writes the strip: `panels`, then the reference's, which also names the far field the
    /// techniques had (`spacing`: the volume's, `None` for the sky) and R, to the centimetre.
    pub fn strip(
        &self,
        path: &Path,
        mut panels: Vec<Panel>,
        info: &ReferenceInfo,
        spacing: Option<f32>,
        radius: f32,
    ) -> Result<()> {
        let cm = |x: f32| {
            let s = format!("{x:.2}");
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        };
        let far = match spacing {
            Some(s) => format!("volume every {} m", cm(s)),
            None => "sky".into(),
        };
        let radius = cm(radius);
        panels.push(Panel {
            image: self.ref_srgb.clone(),
            title: "reference".into(),
            subtitle: match info.spp {
                Some(spp) => format!("ray traced, {spp} spp; {far}, R {radius} m"),
                None => format!("ray traced; {far}, R {radius} m"),
            },
        });
        png(&strip(&panels), path)?;
        eprintln!("nearfield: wrote {}", path.display());
        Ok(())
    }
}
