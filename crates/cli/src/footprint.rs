//! `nearfield compare --footprint`: how well a technique draws what an object the far field's
//! bake never saw does to the rest of the image (the book, "Near and far").
//!
//! The footprint of the scene's dynamic meshes is the change they make to the ambient light of
//! everything else: image with them − image without them, over the pixels near them but not on
//! them. The ambient light is the `lambertian` image less ρ × `light-irradiance`: the lights'
//! shadows are drawn alike by every technique (shadow maps), so only what the environment and
//! the bounces bring is measured, and `none`, which adds nothing, scores 1 by construction.
//! Both references use one seed, so their noise is the same where the object changes no path;
//! both differences are box-filtered over 3 × 3 pixels before they are compared:
//!
//!   error = Σ |blur(Δ technique) − blur(Δ truth)| / Σ |blur(Δ truth)|   over the region.

use crate::BadInput;
use crate::options::{Loaded, SceneOpts};
use crate::reference::{ReferenceOpts, compute};
use anyhow::Result;
use nearfield_reference::ReferenceAov;
use nearfield_render::{Aov, Renderer};

/// The reference's side of the footprint: its ambient light with and without the object, and
/// where the object is seen and what counts as near it.
pub struct Truth {
    delta: Vec<f32>,
    /// Pixels near the object but not on it.
    region: Vec<bool>,
    width: usize,
    height: usize,
}

/// The ambient light of one image: lambertian − ρ · light-irradiance (mean of RGB).
fn ambient(lambertian: &[[f32; 4]], albedo: &[[f32; 4]], light: &[[f32; 4]]) -> Vec<f32> {
    lambertian
        .iter()
        .zip(albedo)
        .zip(light)
        .map(|((l, a), e)| (0..3).map(|c| l[c] - a[c] * e[c]).sum::<f32>() / 3.0)
        .collect()
}

/// Box filter over 3 × 3 pixels (edges clamped).
fn blur(v: &[f32], w: usize, h: usize) -> Vec<f32> {
    let mut out = vec![0.0; v.len()];
    for y in 0..h {
        for x in 0..w {
            let mut sum = 0.0;
            let mut n = 0.0;
            for dy in -1i32..=1 {
                for dx in -1i32..=1 {
                    let (xx, yy) = (x as i32 + dx, y as i32 + dy);
                    if xx >= 0 && yy >= 0 && (xx as usize) < w && (yy as usize) < h {
                        sum += v[yy as usize * w + xx as usize];
                        n += 1.0;
                    }
                }
            }
            out[y * w + x] = sum / n;
        }
    }
    out
}

/// The pixels near the object but not on it: those whose surface differs between the two
/// depth images are on it; near is its screen bounding box grown by half its larger side.
fn region(with: &[f32], without: &[f32], w: usize, h: usize) -> Vec<bool> {
    let on: Vec<bool> = with
        .iter()
        .zip(without)
        .map(|(&a, &b)| (a - b).abs() > 1e-3 * a.abs().max(b.abs()).max(1e-3))
        .collect();
    let (mut x0, mut y0, mut x1, mut y1) = (usize::MAX, usize::MAX, 0, 0);
    for (i, _) in on.iter().enumerate().filter(|(_, o)| **o) {
        let (x, y) = (i % w, i / w);
        (x0, y0, x1, y1) = (x0.min(x), y0.min(y), x1.max(x), y1.max(y));
    }
    if x0 == usize::MAX {
        return vec![false; w * h];
    }
    let grow = (x1 - x0).max(y1 - y0) / 2 + 2;
    let (gx0, gy0) = (x0.saturating_sub(grow), y0.saturating_sub(grow));
    let (gx1, gy1) = ((x1 + grow).min(w - 1), (y1 + grow).min(h - 1));
    (0..w * h)
        .map(|i| {
            let (x, y) = (i % w, i / w);
            !on[i] && with[i] > 0.0 && (gx0..=gx1).contains(&x) && (gy0..=gy1).contains(&y)
        })
        .collect()
}

/// Refuses `--footprint` on a scene without dynamic meshes, before anything is baked or traced.
pub fn check(opts: &SceneOpts, loaded: &Loaded) -> Result<()> {
    if !loaded.scene.has_dynamic() {
        return Err(BadInput(format!(
            "--footprint: {} has no dynamic node (mark one with --dynamic NAME, add one with --add FILE@X,Y,Z, or use a *-dynamic built-in)",
            opts.scene
        ))
        .into());
    }
    Ok(())
}

/// The scene without its dynamic meshes, lit and seen as `loaded`.
pub fn without_object(loaded: &Loaded) -> Loaded {
    loaded.with_scene(loaded.scene.baked_part())
}

/// Traces the references of both sides (radiance, albedo, light-irradiance; each cached like
/// any reference) at `radius` and `seed`.
pub fn truth(
    opts: &SceneOpts,
    ref_opts: &ReferenceOpts,
    loaded: &Loaded,
    size: (u32, u32),
    radius: f32,
    seed: u32,
) -> Result<Truth> {
    let without = without_object(loaded);
    let side = |l: &Loaded| -> Result<(Vec<f32>, Vec<f32>)> {
        let image = |aov: ReferenceAov| -> Result<nearfield_reference::ReferenceImage> {
            let s = ref_opts.settings(aov, size, radius, seed)?;
            Ok(compute(opts, ref_opts, l, &s)?.0)
        };
        let radiance = image(ReferenceAov::Radiance)?;
        let albedo = image(ReferenceAov::Albedo)?;
        let light = image(ReferenceAov::LightIrradiance)?;
        Ok((
            ambient(&radiance.value, &albedo.value, &light.value),
            radiance.depth,
        ))
    };
    let (a_with, d_with) = side(loaded)?;
    let (a_without, d_without) = side(&without)?;
    let (w, h) = (size.0 as usize, size.1 as usize);
    Ok(Truth {
        delta: a_with.iter().zip(&a_without).map(|(a, b)| a - b).collect(),
        region: region(&d_with, &d_without, w, h),
        width: w,
        height: h,
    })
}

/// A renderer's ambient light of its last frame (lambertian − ρ · light-irradiance).
pub fn ambient_of(r: &mut Renderer) -> Vec<f32> {
    let l = r.read_aov(Aov::Lambertian).pixels;
    let a = r.read_aov(Aov::Albedo).pixels;
    let e = r.read_aov(Aov::LightIrradiance).pixels;
    ambient(&l, &a, &e)
}

impl Truth {
    /// The footprint error of a technique whose ambient light is `with` and `without` the object.
    pub fn error(&self, with: &[f32], without: &[f32]) -> f64 {
        let delta: Vec<f32> = with.iter().zip(without).map(|(a, b)| a - b).collect();
        let (t, r) = (
            blur(&delta, self.width, self.height),
            blur(&self.delta, self.width, self.height),
        );
        let (mut num, mut den) = (0.0f64, 0.0f64);
        for i in (0..t.len()).filter(|&i| self.region[i]) {
            num += f64::from((t[i] - r[i]).abs());
            den += f64::from(r[i].abs());
        }
        if den > 0.0 { num / den } else { 0.0 }
    }

    /// Heat maps of the truth's footprint and of a technique's (blurred, at the truth's range;
    /// grey outside the region).
    pub fn heatmaps(&self, with: &[f32], without: &[f32]) -> (image::RgbImage, image::RgbImage) {
        let delta: Vec<f32> = with.iter().zip(without).map(|(a, b)| a - b).collect();
        let (t, r) = (
            blur(&delta, self.width, self.height),
            blur(&self.delta, self.width, self.height),
        );
        let range = nearfield_eval::image_ops::error_range(&r, &self.region).max(1e-6);
        let map = |v: &[f32]| {
            nearfield_eval::image_ops::heatmap(
                v,
                &self.region,
                self.width as u32,
                self.height as u32,
                range,
            )
        };
        (map(&r), map(&t))
    }

    /// Pixels in the region.
    pub fn pixels(&self) -> usize {
        self.region.iter().filter(|&&r| r).count()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn adding_nothing_scores_one_and_the_truth_scores_zero() {
        let (w, h) = (16, 12);
        let without = vec![1.0f32; w * h];
        let mut with_depth = vec![5.0f32; w * h];
        // The object covers a 4 × 4 block; it darkens the pixels around it.
        let mut truth_with = without.clone();
        for y in 3..9 {
            for x in 5..11 {
                truth_with[y * w + x] = 0.6;
            }
        }
        for y in 4..8 {
            for x in 6..10 {
                with_depth[y * w + x] = 4.0;
            }
        }
        let t = Truth {
            delta: truth_with
                .iter()
                .zip(&without)
                .map(|(a, b)| a - b)
                .collect(),
            region: region(&with_depth, &vec![5.0; w * h], w, h),
            width: w,
            height: h,
        };
        assert!(t.pixels() > 0);
        assert!((t.error(&without, &without) - 1.0).abs() < 1e-9);
        assert!(t.error(&truth_with, &without) < 1e-9);
        // Twice the darkening is off by as much as the darkening itself.
        let twice: Vec<f32> = truth_with.iter().map(|v| 1.0 - 2.0 * (1.0 - v)).collect();
        assert!((t.error(&twice, &without) - 1.0).abs() < 1e-6);
    }
}
