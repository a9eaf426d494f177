//! ColorVideoVDP (Mantiuk et al. 2024, the `colorvideovdp` crate, a Rust port of `cvvdp`
//! 0.5.7): a perceptual quality score of a technique's frames along a camera path against the
//! reference's frames, in JOD (10: no visible difference; one JOD less: 75 % of viewers prefer
//! the other). Both sequences are the frames as the report shows them (exposed, tone-mapped,
//! 8-bit sRGB), each at its native size on the `standard_fhd` display of the metric (a 24-inch
//! 1920 × 1080 monitor, 200 cd/m², seen from 0.6 m), played at the path's frame rate. The book,
//! "In motion", has its check against the authors' PyTorch implementation.

use colorvideovdp::{Color, Cvvdp, DisplayModel, Image, Options};
use image::RgbImage;

/// The display the frames are judged on.
pub const DISPLAY: &str = "standard_fhd";

/// The JOD of `test` against `reference` (equal lengths, at least two frames of one size) played
/// at `fps`; an error names what the metric refused (too short, sizes differ, over its memory
/// budget).
pub fn jod(test: &[RgbImage], reference: &[RgbImage], fps: f32) -> Result<f64, String> {
    if test.len() != reference.len() || test.len() < 2 {
        return Err(format!(
            "{} test and {} reference frames: need two or more of each, as many",
            test.len(),
            reference.len()
        ));
    }
    let frames = |images: &[RgbImage]| -> Result<Vec<Image>, String> {
        images
            .iter()
            .map(|im| {
                let data = im.as_raw().iter().map(|&v| f32::from(v) / 255.0).collect();
                Image::new(im.width() as usize, im.height() as usize, 3, data)
                    .map_err(|e| e.to_string())
            })
            .collect()
    };
    let (t, r) = (frames(test)?, frames(reference)?);
    let display = DisplayModel::from_name(DISPLAY).map_err(|e| e.to_string())?;
    let metric = Cvvdp::new(display, Options::default()).map_err(|e| e.to_string())?;
    let p = metric
        .predict_video(&t, &r, fps, Color::Srgb)
        .map_err(|e| e.to_string())?;
    Ok(f64::from(p.jod))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(f: impl Fn(u32, u32) -> u8) -> RgbImage {
        RgbImage::from_fn(32, 24, |x, y| {
            let v = f(x, y);
            image::Rgb([v, v, v])
        })
    }

    /// Identical sequences score 10 JOD; a flicker of the test's brightness on alternate frames
    /// scores lower, and a larger flicker lower still.
    #[test]
    fn flicker_lowers_the_score_and_identity_scores_ten() {
        let base: Vec<RgbImage> = (0..8)
            .map(|k| frame(|x, y| (64 + (x * 3 + y * 2 + k) % 96) as u8))
            .collect();
        let flicker = |a: i32| -> Vec<RgbImage> {
            base.iter()
                .enumerate()
                .map(|(k, im)| {
                    let d = if k % 2 == 0 { a } else { -a };
                    let mut out = im.clone();
                    for p in out.pixels_mut() {
                        for c in p.0.iter_mut() {
                            *c = (i32::from(*c) + d).clamp(0, 255) as u8;
                        }
                    }
                    out
                })
                .collect()
        };
        let same = jod(&base, &base, 30.0).unwrap();
        let small = jod(&flicker(4), &base, 30.0).unwrap();
        let large = jod(&flicker(16), &base, 30.0).unwrap();
        assert!((same - 10.0).abs() < 1e-4, "identity: {same}");
        assert!(small < same - 0.05, "small flicker {small}");
        assert!(large < small - 0.5, "large flicker {large} against {small}");
        assert!(jod(&base[..1], &base[..1], 30.0).is_err());
    }
}
