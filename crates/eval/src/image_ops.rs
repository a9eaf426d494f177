//! Turning float AOVs into pictures: the renderer's tonemapper on the CPU, and a signed error
//! heat map.

use image::{Rgb, RgbImage};

/// Narkowicz' ACES fit at exposure 0, then sRGB — the same curve as tonemap.wgsl's `aces`, so
/// that FLIP sees what the renderer would show. Background (alpha 0) is black.
pub fn tonemap(values: &[[f32; 4]], width: u32, height: u32) -> RgbImage {
    tonemap_exposed(values, width, height, 1.0)
}

/// [`tonemap`] of the values times `gain` (2^EV of an exposure).
pub fn tonemap_exposed(values: &[[f32; 4]], width: u32, height: u32, gain: f32) -> RgbImage {
    let aces = |x: f32| {
        let v = x.max(0.0) * gain * 0.6;
        ((v * (2.51 * v + 0.03)) / (v * (2.43 * v + 0.59) + 0.14)).clamp(0.0, 1.0)
    };
    let encode = |c: f32| {
        let s = if c <= 0.0031308 {
            c * 12.92
        } else {
            1.055 * c.powf(1.0 / 2.4) - 0.055
        };
        (s.clamp(0.0, 1.0) * 255.0 + 0.5) as u8
    };
    RgbImage::from_fn(width, height, |x, y| {
        let p = values[(y * width + x) as usize];
        if p[3] <= 0.0 {
            Rgb([0, 0, 0])
        } else {
            Rgb([encode(aces(p[0])), encode(aces(p[1])), encode(aces(p[2]))])
        }
    })
}

/// A diverging colour for t in [−1, 1]: blue (negative) – white (0) – red (positive).
pub fn diverging(t: f32) -> [u8; 3] {
    let t = t.clamp(-1.0, 1.0);
    let (r, g, b) = if t < 0.0 {
        let s = -t;
        (1.0 - 0.8 * s, 1.0 - 0.6 * s, 1.0 - 0.1 * s)
    } else {
        (1.0 - 0.1 * t, 1.0 - 0.75 * t, 1.0 - 0.8 * t)
    };
    [(r * 255.0) as u8, (g * 255.0) as u8, (b * 255.0) as u8]
}

/// Signed error heat map: `errors / range` through [`diverging`]; excluded pixels dark grey.
pub fn heatmap(errors: &[f32], valid: &[bool], width: u32, height: u32, range: f32) -> RgbImage {
    RgbImage::from_fn(width, height, |x, y| {
        let i = (y * width + x) as usize;
        if valid[i] {
            Rgb(diverging(errors[i] / range.max(1e-12)))
        } else {
            Rgb([48, 48, 48])
        }
    })
}

/// Symmetric heat-map range: the 99th percentile of |error| over valid pixels (so that a few
/// outliers do not wash the map out), at least 1e-6.
pub fn error_range(errors: &[f32], valid: &[bool]) -> f32 {
    let mut a: Vec<f32> = errors
        .iter()
        .zip(valid)
        .filter(|(_, v)| **v)
        .map(|(e, _)| e.abs())
        .collect();
    if a.is_empty() {
        return 1e-6;
    }
    a.sort_by(|x, y| x.total_cmp(y));
    a[((a.len() - 1) as f32 * 0.99) as usize].max(1e-6)
}
