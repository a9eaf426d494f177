//! Masks and error metrics.
//!
//! A pixel counts when both images see a surface there, it is not within `border` pixels of the
//! image edge, and it is not on a silhouette. Silhouette pixels are those where exactly one image
//! sees a surface or where the two view depths differ by more than `depth_tolerance` (relative);
//! the silhouette set is dilated by one pixel (8-neighbourhood). Errors are on the mean of the
//! RGB channels, e = test − reference:
//! bias = mean e, MAE = mean |e|, RMSE = √(mean e²), relative error = Σ|e| / Σ reference.

use serde::{Deserialize, Serialize};

/// How pixels are excluded.
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct MaskSettings {
    /// Width of the excluded band at the image edge (pixels).
    pub border: u32,
    /// Relative view-depth difference that marks a silhouette, e.g. 0.01.
    pub depth_tolerance: f32,
}

/// Which pixels are compared.
#[derive(Clone, Debug)]
pub struct Mask {
    pub width: u32,
    pub height: u32,
    pub valid: Vec<bool>,
    /// Pixels excluded as silhouettes (after dilation).
    pub silhouette_pixels: usize,
    /// False when the reference carried no depth, so silhouettes could not be found.
    pub depth_checked: bool,
}

impl Mask {
    /// Keeps only the pixels inside the rectangle [x0, y0, x1, y1) (pixel coordinates).
    pub fn restrict(&mut self, [x0, y0, x1, y1]: [u32; 4]) {
        for y in 0..self.height {
            for x in 0..self.width {
                if !(x >= x0 && x < x1 && y >= y0 && y < y1) {
                    self.valid[(y * self.width + x) as usize] = false;
                }
            }
        }
    }

    /// `*_alpha`: coverage (> 0 = surface); `*_depth`: view depth (reference depth all 0 = unknown).
    pub fn new(
        size: (u32, u32),
        test_alpha: &[f32],
        test_depth: &[f32],
        ref_alpha: &[f32],
        ref_depth: &[f32],
        settings: MaskSettings,
    ) -> Self {
        let (w, h) = size;
        let n = (w * h) as usize;
        let depth_checked = ref_depth.iter().any(|&d| d > 0.0);
        let mut silhouette = vec![false; n];
        for i in 0..n {
            let (ts, rs) = (test_alpha[i] > 0.0, ref_alpha[i] > 0.0);
            silhouette[i] = ts != rs
                || (ts
                    && depth_checked
                    && (test_depth[i] - ref_depth[i]).abs()
                        > settings.depth_tolerance * ref_depth[i].max(1e-6));
        }
        let mut dilated = silhouette.clone();
        for y in 0..h as i64 {
            for x in 0..w as i64 {
                if !silhouette[(y * w as i64 + x) as usize] {
                    continue;
                }
                for dy in -1..=1 {
                    for dx in -1..=1 {
                        let (nx, ny) = (x + dx, y + dy);
                        if nx >= 0 && ny >= 0 && nx < w as i64 && ny < h as i64 {
                            dilated[(ny * w as i64 + nx) as usize] = true;
                        }
                    }
                }
            }
        }
        let b = settings.border;
        let mut valid = vec![false; n];
        let mut silhouette_pixels = 0;
        for y in 0..h {
            for x in 0..w {
                let i = (y * w + x) as usize;
                let inside = x >= b && y >= b && x + b < w && y + b < h;
                let surface = test_alpha[i] > 0.0 && ref_alpha[i] > 0.0;
                if dilated[i] && inside {
                    silhouette_pixels += 1;
                }
                valid[i] = inside && surface && !dilated[i];
            }
        }
        Mask {
            width: w,
            height: h,
            valid,
            silhouette_pixels,
            depth_checked,
        }
    }

    pub fn count(&self) -> usize {
        self.valid.iter().filter(|&&v| v).count()
    }
}

/// Error metrics over the valid pixels.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
pub struct Metrics {
    pub pixels: usize,
    pub bias: f64,
    pub mae: f64,
    pub rmse: f64,
    pub relative_error: f64,
    /// The image mean over the reference's, Σ test / Σ reference (mean of RGB) over the valid
    /// pixels: 1 when the technique's light has the truth's total.
    #[serde(default)]
    pub mean_ratio: f64,
    /// Mean FLIP (0..1) over the valid pixels of the tonemapped images; None when not computed.
    pub flip: Option<f64>,
}

fn mean_rgb(p: &[f32; 4]) -> f64 {
    (p[0] as f64 + p[1] as f64 + p[2] as f64) / 3.0
}

/// Per-pixel signed error (mean of RGB), 0 where the mask excludes the pixel.
pub fn signed_errors(test: &[[f32; 4]], reference: &[[f32; 4]], mask: &Mask) -> Vec<f32> {
    test.iter()
        .zip(reference)
        .zip(&mask.valid)
        .map(|((t, r), &v)| {
            if v {
                (mean_rgb(t) - mean_rgb(r)) as f32
            } else {
                0.0
            }
        })
        .collect()
}

pub fn metrics(test: &[[f32; 4]], reference: &[[f32; 4]], mask: &Mask) -> Metrics {
    let (mut n, mut sum, mut abs, mut sq, mut refsum) = (0usize, 0.0, 0.0, 0.0, 0.0);
    let (mut test_sum, mut ref_signed) = (0.0, 0.0);
    for ((t, r), &v) in test.iter().zip(reference).zip(&mask.valid) {
        if !v {
            continue;
        }
        let e = mean_rgb(t) - mean_rgb(r);
        n += 1;
        sum += e;
        abs += e.abs();
        sq += e * e;
        refsum += mean_rgb(r).abs();
        test_sum += mean_rgb(t);
        ref_signed += mean_rgb(r);
    }
    let nf = n.max(1) as f64;
    Metrics {
        pixels: n,
        bias: sum / nf,
        mae: abs / nf,
        rmse: (sq / nf).sqrt(),
        relative_error: if refsum > 0.0 { abs / refsum } else { 0.0 },
        mean_ratio: if ref_signed != 0.0 {
            test_sum / ref_signed
        } else {
            1.0
        },
        flip: None,
    }
}

/// One frame of a sequence against the frame before it, motion-compensated: where the surface
/// point at pixel p was a frame earlier (p + `motion`(p), the `motion` AOV: previous − current,
/// pixels, rounded to the nearest pixel) and both frames' masks hold it, the squared change of the
/// value (mean of RGB). Summed over a sequence for a technique and for the reference, the ratio
/// of their roots is the instability figure (the book, "In motion").
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrameChange {
    /// Σ (X_t(p) − X_{t−1}(p + m))² over the compared pixels.
    pub sum_sq: f64,
    /// With a second, independent estimate of both frames given (the reference traced again with
    /// another seed, Y): Σ (X_t(p) − X_{t−1}(p + m)) · (Y_t(p) − Y_{t−1}(p + m)). The two
    /// changes' noises are independent, so its expectation is the noiseless change's Σ of
    /// squares, whatever the noise of each sequence and however it is correlated from frame to
    /// frame within a sequence (one seed for every frame: the same paths wherever nothing moved).
    pub cross: f64,
    pub pixels: usize,
}

impl std::ops::AddAssign for FrameChange {
    fn add_assign(&mut self, o: Self) {
        self.sum_sq += o.sum_sq;
        self.cross += o.cross;
        self.pixels += o.pixels;
    }
}

/// A second estimate of two frames (current, previous): the reference traced with another seed.
pub type FrameTwin<'a> = (&'a [[f32; 4]], &'a [[f32; 4]]);

/// The motion-compensated change from `prev` to `cur` ([`FrameChange`]); `twin`: the same two
/// frames estimated independently (current, previous), for the reference.
pub fn frame_change(
    (cur, cur_mask): (&[[f32; 4]], &Mask),
    (prev, prev_mask): (&[[f32; 4]], &Mask),
    motion: &[[f32; 4]],
    twin: Option<FrameTwin>,
) -> FrameChange {
    let (w, h) = (cur_mask.width as i64, cur_mask.height as i64);
    let mut out = FrameChange::default();
    for y in 0..h {
        for x in 0..w {
            let i = (y * w + x) as usize;
            if !cur_mask.valid[i] {
                continue;
            }
            let px = x + motion[i][0].round() as i64;
            let py = y + motion[i][1].round() as i64;
            if !(0..w).contains(&px) || !(0..h).contains(&py) {
                continue;
            }
            let j = (py * w + px) as usize;
            if !prev_mask.valid[j] {
                continue;
            }
            let d = mean_rgb(&cur[i]) - mean_rgb(&prev[j]);
            out.sum_sq += d * d;
            if let Some((tc, tp)) = twin {
                out.cross += d * (mean_rgb(&tc[i]) - mean_rgb(&tp[j]));
            }
            out.pixels += 1;
        }
    }
    out
}

/// The instability figure: the technique's motion-compensated change over the reference's, each
/// the root of its summed squared change, the reference's estimated free of its noise by the
/// cross product of two independent traces ([`FrameChange::cross`]; at least a tenth of its
/// squared change is kept, so that a noise-dominated reference gives a finite ratio).
pub fn instability(technique: FrameChange, reference: FrameChange) -> f64 {
    let truth = reference.cross.max(0.1 * reference.sum_sq);
    if truth <= 0.0 {
        return if technique.sum_sq > 0.0 {
            f64::INFINITY
        } else {
            1.0
        };
    }
    (technique.sum_sq / truth).sqrt()
}

/// The amplitude of the `period`-periodic part of the error (mean of RGB) against `reference`:
/// the masked mean error of each of the period² pixel phases (x mod period, y mod period), and
/// the RMS of those means about their overall mean. A technique's 4×4 interleaving pattern left
/// in its result shows here at period 4; noise, the reference's included, averages out over the
/// pixels of a phase. 0 with fewer than two phases covered.
pub fn periodic_residue(
    test: &[[f32; 4]],
    reference: &[[f32; 4]],
    mask: &Mask,
    period: u32,
) -> f64 {
    let p = period.max(1) as usize;
    let mut sums = vec![(0.0f64, 0usize); p * p];
    for (i, ((t, r), &v)) in test.iter().zip(reference).zip(&mask.valid).enumerate() {
        if !v {
            continue;
        }
        let (x, y) = (i % mask.width as usize, i / mask.width as usize);
        let phase = &mut sums[(y % p) * p + x % p];
        phase.0 += mean_rgb(t) - mean_rgb(r);
        phase.1 += 1;
    }
    let means: Vec<f64> = sums
        .iter()
        .filter(|(_, n)| *n > 0)
        .map(|(s, n)| s / *n as f64)
        .collect();
    if means.len() < 2 {
        return 0.0;
    }
    let mean = means.iter().sum::<f64>() / means.len() as f64;
    (means.iter().map(|m| (m - mean).powi(2)).sum::<f64>() / means.len() as f64).sqrt()
}

/// RMS over the mask of a per-pixel standard error (mean of RGB).
pub fn rms_stderr(stderr: &[[f32; 3]], mask: &Mask) -> f64 {
    let (mut s, mut n) = (0.0f64, 0usize);
    for (e, &v) in stderr.iter().zip(&mask.valid) {
        if v {
            let m = (e[0] as f64 + e[1] as f64 + e[2] as f64) / 3.0;
            s += m * m;
            n += 1;
        }
    }
    (s / n.max(1) as f64).sqrt()
}

/// The reference's relative noise over the mask: Σ σ / Σ |reference| (mean of RGB), on the scale
/// of the relative error. A perfect estimate would show a relative error of about 0.8 × this
/// (the mean absolute deviation of a normal distribution is √(2/π) σ).
pub fn relative_stderr(stderr: &[[f32; 3]], reference: &[[f32; 4]], mask: &Mask) -> f64 {
    let (mut s, mut r) = (0.0f64, 0.0f64);
    for ((e, v), &ok) in stderr.iter().zip(reference).zip(&mask.valid) {
        if ok {
            s += (e[0] as f64 + e[1] as f64 + e[2] as f64) / 3.0;
            r += mean_rgb(v).abs();
        }
    }
    if r > 0.0 { s / r } else { 0.0 }
}

/// Mean FLIP over the mask, from two sRGB images of the same size (nv-flip, default viewing
/// conditions: 67 pixels per degree).
pub fn flip_mean(test: &image::RgbImage, reference: &image::RgbImage, mask: &Mask) -> f64 {
    let (w, h) = test.dimensions();
    let t = nv_flip::FlipImageRgb8::with_data(w, h, test.as_raw());
    let r = nv_flip::FlipImageRgb8::with_data(w, h, reference.as_raw());
    let err = nv_flip::flip(r, t, nv_flip::DEFAULT_PIXELS_PER_DEGREE).to_vec();
    let (mut s, mut n) = (0.0f64, 0usize);
    for (e, &v) in err.iter().zip(&mask.valid) {
        if v {
            s += *e as f64;
            n += 1;
        }
    }
    s / n.max(1) as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flat(v: f32, n: usize) -> Vec<[f32; 4]> {
        vec![[v, v, v, 1.0]; n]
    }

    /// A ±a checkerboard of 4×4 phases has periodic residue a; a constant offset and a pattern
    /// of another period (8 × 1 stripes of period 8 seen at period 4 average out) have none.
    #[test]
    fn periodic_residue_finds_a_4x4_pattern() {
        let size = (32, 32);
        let n = 32 * 32;
        let ones = vec![1.0; n];
        let depth = vec![2.0; n];
        let mask = Mask::new(
            size,
            &ones,
            &depth,
            &ones,
            &depth,
            MaskSettings {
                border: 0,
                depth_tolerance: 0.01,
            },
        );
        let a = 0.03f32;
        let pattern: Vec<[f32; 4]> = (0..n)
            .map(|i| {
                let (x, y) = (i % 32, i / 32);
                let v = 0.5 + if (x % 4 + y % 4) % 2 == 0 { a } else { -a };
                [v, v, v, 1.0]
            })
            .collect();
        let reference = flat(0.5, n);
        let r = periodic_residue(&pattern, &reference, &mask, 4);
        assert!((r - a as f64).abs() < 1e-6, "{r}");
        assert!(periodic_residue(&flat(0.6, n), &reference, &mask, 4) < 1e-9);
        let stripes: Vec<[f32; 4]> = (0..n)
            .map(|i| {
                let v = 0.5 + if (i % 32) % 8 < 4 { a } else { -a };
                [v, v, v, 1.0]
            })
            .collect();
        assert!(periodic_residue(&stripes, &reference, &mask, 4) < 1e-6);
    }

    #[test]
    fn metrics_of_a_constant_offset() {
        let size = (10, 8);
        let n = 80;
        let ones = vec![1.0; n];
        let depth = vec![2.0; n];
        let mask = Mask::new(
            size,
            &ones,
            &depth,
            &ones,
            &depth,
            MaskSettings {
                border: 1,
                depth_tolerance: 0.01,
            },
        );
        // Border 1 leaves 8 × 6.
        assert_eq!(mask.count(), 48);
        let m = metrics(&flat(0.6, n), &flat(0.5, n), &mask);
        assert!(
            (m.bias - 0.1).abs() < 1e-6
                && (m.mae - 0.1).abs() < 1e-6
                && (m.rmse - 0.1).abs() < 1e-6
        );
        assert!((m.relative_error - 0.2).abs() < 1e-6);
    }

    #[test]
    fn silhouettes_are_dilated() {
        let size = (7, 7);
        let n = 49;
        let ones = vec![1.0; n];
        let mut test_depth = vec![2.0; n];
        test_depth[24] = 3.0; // centre pixel disagrees
        let mask = Mask::new(
            size,
            &ones,
            &test_depth,
            &ones,
            &vec![2.0; n],
            MaskSettings {
                border: 0,
                depth_tolerance: 0.01,
            },
        );
        assert_eq!(mask.silhouette_pixels, 9);
        assert_eq!(mask.count(), 40);
    }

    #[test]
    fn identical_images_have_zero_flip() {
        let img = image::RgbImage::from_fn(16, 16, |x, y| {
            image::Rgb([(x * 16) as u8, (y * 16) as u8, 90])
        });
        let ones = vec![1.0; 256];
        let mask = Mask::new(
            (16, 16),
            &ones,
            &ones,
            &ones,
            &ones,
            MaskSettings {
                border: 0,
                depth_tolerance: 0.01,
            },
        );
        assert_eq!(flip_mean(&img, &img, &mask), 0.0);
        let mut other = img.clone();
        for p in other.pixels_mut() {
            p.0[0] = 255 - p.0[0];
        }
        assert!(flip_mean(&other, &img, &mask) > 0.1);
    }

    #[test]
    fn motion_compensated_change_follows_the_motion_and_cancels_independent_noise() {
        // A ramp moved one pixel to the right: with the motion vectors there is no change.
        let (w, h) = (8u32, 4u32);
        let ramp = |shift: i32| -> Vec<[f32; 4]> {
            (0..w * h)
                .map(|i| {
                    let v = ((i % w) as i32 - shift) as f32;
                    [v, v, v, 1.0]
                })
                .collect()
        };
        let mask = Mask {
            width: w,
            height: h,
            valid: vec![true; (w * h) as usize],
            silhouette_pixels: 0,
            depth_checked: true,
        };
        let (prev, cur) = (ramp(0), ramp(1));
        let motion = vec![[-1.0, 0.0, 0.0, 0.0]; (w * h) as usize];
        let c = frame_change((&cur, &mask), (&prev, &mask), &motion, None);
        assert_eq!((c.sum_sq, c.pixels), (0.0, ((w - 1) * h) as usize));
        // Without them every pixel changes by 1.
        let still = vec![[0.0; 4]; (w * h) as usize];
        let c = frame_change((&cur, &mask), (&prev, &mask), &still, None);
        assert_eq!((c.sum_sq, c.pixels), ((w * h) as f64, (w * h) as usize));
        // Noise: two independent traces of the same frames, each frame ±0.5 off in a pattern
        // that changes sign from frame to frame and that the two traces do not share (columns,
        // rows). Each trace's change is the truth's 1 ± 1, its square 2 a pixel on average;
        // their cross product reads the truth's 1.
        // ±0.5 × `sign` by the parity of `key(i)`: the column (trace a) or the row (trace b).
        let with_noise = |base: &[[f32; 4]], key: &dyn Fn(usize) -> usize, sign: f32| {
            base.iter()
                .enumerate()
                .map(|(i, v)| {
                    let n = if key(i).is_multiple_of(2) { 0.5 } else { -0.5 } * sign;
                    [v[0] + n, v[1] + n, v[2] + n, 1.0]
                })
                .collect::<Vec<[f32; 4]>>()
        };
        let column = |i: usize| i;
        let row = |i: usize| i / w as usize;
        let noisy = |base: &[[f32; 4]], sign: f32| with_noise(base, &column, sign);
        let odd = |base: &[[f32; 4]], sign: f32| with_noise(base, &row, sign);
        let (a_cur, a_prev) = (noisy(&cur, 1.0), noisy(&prev, -1.0));
        let (b_cur, b_prev) = (odd(&cur, 1.0), odd(&prev, -1.0));
        let r = frame_change(
            (&a_cur, &mask),
            (&a_prev, &mask),
            &still,
            Some((&b_cur, &b_prev)),
        );
        let px = (w * h) as f64;
        assert!((r.sum_sq - 2.0 * px).abs() < 1e-6, "sum_sq {}", r.sum_sq);
        assert!((r.cross - px).abs() < 1e-6, "cross {}", r.cross);
        assert!((instability(c, r) - 1.0).abs() < 1e-9);
        // One seed for both frames: noise that does not change from frame to frame cancels in
        // each trace's change, and the figure is the truth's again.
        let (s_cur, s_prev) = (noisy(&cur, 1.0), noisy(&prev, 1.0));
        let (t_cur, t_prev) = (odd(&cur, 1.0), odd(&prev, 1.0));
        let r = frame_change(
            (&s_cur, &mask),
            (&s_prev, &mask),
            &still,
            Some((&t_cur, &t_prev)),
        );
        assert!((r.sum_sq - px).abs() < 1e-6 && (r.cross - px).abs() < 1e-6);
        assert!((instability(c, r) - 1.0).abs() < 1e-9);
    }
}
