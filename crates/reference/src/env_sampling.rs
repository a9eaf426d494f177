//! Importance sampling of the environment: a piecewise-constant distribution over the map's
//! texels with weight (largest luminance in the texel's 3×3 neighbourhood) × solid angle — the
//! neighbourhood because lookups are bilinear and spill a bright texel's radiance into its
//! neighbours — (marginal over rows, conditional within a row),
//! a uniform position inside the chosen texel, and its exact solid-angle density
//! pdf(ω) = p_texel · W · H / (2π² sin θ). Combined with cosine sampling by the balance
//! heuristic (Veach 1997) in `integrate`, this makes the environment terms converge under a
//! sun, where cosine sampling alone leaves fireflies.

use glam::{Vec2, Vec3};
use nearfield_scene::Environment;
use std::f32::consts::PI;

/// Maps whose brightest texel (energy) is below this multiple of the mean are not importance
/// sampled.
pub const PEAK_RATIO: f64 = 8.0;

pub struct EnvDistribution {
    width: u32,
    height: u32,
    /// Cumulative row weights, normalised to end at 1.
    row_cdf: Vec<f32>,
    /// Per row, cumulative texel weights normalised to end at 1 (width + 0 entries each).
    col_cdf: Vec<f32>,
    /// Probability of each texel.
    texel_p: Vec<f32>,
}

fn luminance(c: Vec3) -> f32 {
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}

/// Index of the first entry ≥ u in a non-decreasing slice.
fn search(cdf: &[f32], u: f32) -> usize {
    cdf.partition_point(|&c| c < u).min(cdf.len() - 1)
}

impl EnvDistribution {
    /// None when the map has no energy, or is so even (no texel carries more than
    /// [`PEAK_RATIO`] × the mean) that cosine sampling alone is the better estimator — it is
    /// exact for a constant map.
    pub fn new(env: &Environment) -> Option<Self> {
        let (w, h) = (env.width, env.height);
        let lum: Vec<f32> = env.texels.iter().map(|t| luminance(*t).max(0.0)).collect();
        let mut weights = vec![0f64; (w * h) as usize];
        for y in 0..h {
            let dw = env.texel_solid_angle(y) as f64;
            for x in 0..w {
                let mut m = 0f32;
                for dy in -1i64..=1 {
                    let yy = (y as i64 + dy).clamp(0, h as i64 - 1) as u32;
                    for dx in -1i64..=1 {
                        let xx = (x as i64 + dx).rem_euclid(w as i64) as u32;
                        m = m.max(lum[(yy * w + xx) as usize]);
                    }
                }
                weights[(y * w + x) as usize] = m as f64 * dw;
            }
        }
        let total: f64 = weights.iter().sum();
        if total <= 0.0 || !total.is_finite() {
            return None;
        }
        let peak = weights.iter().cloned().fold(0.0, f64::max);
        if peak * (weights.len() as f64) < PEAK_RATIO * total {
            return None;
        }
        let mut row_cdf = Vec::with_capacity(h as usize);
        let mut col_cdf = Vec::with_capacity((w * h) as usize);
        let mut acc = 0.0f64;
        for y in 0..h as usize {
            let row = &weights[y * w as usize..(y + 1) * w as usize];
            let row_sum: f64 = row.iter().sum();
            let mut c = 0.0f64;
            for (x, &v) in row.iter().enumerate() {
                c += v;
                col_cdf.push(if row_sum > 0.0 {
                    (c / row_sum) as f32
                } else {
                    (x + 1) as f32 / w as f32
                });
            }
            acc += row_sum;
            row_cdf.push((acc / total) as f32);
        }
        let texel_p = weights.iter().map(|v| (v / total) as f32).collect();
        Some(EnvDistribution {
            width: w,
            height: h,
            row_cdf,
            col_cdf,
            texel_p,
        })
    }

    /// A world direction distributed by the map's energy, and its solid-angle pdf.
    pub fn sample(&self, env: &Environment, u: Vec2) -> (Vec3, f32) {
        let y = search(&self.row_cdf, u.x);
        let row = &self.col_cdf[y * self.width as usize..(y + 1) * self.width as usize];
        let row_lo = if y == 0 { 0.0 } else { self.row_cdf[y - 1] };
        // Reuse the remainder of u.x for the position within the row (stratification kept).
        let span = (self.row_cdf[y] - row_lo).max(1e-12);
        let fy = ((u.x - row_lo) / span).clamp(0.0, 0.999_999);
        let x = search(row, u.y);
        let col_lo = if x == 0 { 0.0 } else { row[x - 1] };
        let fx = ((u.y - col_lo) / (row[x] - col_lo).max(1e-12)).clamp(0.0, 0.999_999);
        let uv = Vec2::new(
            (x as f32 + fx) / self.width as f32,
            (y as f32 + fy) / self.height as f32,
        );
        let d = env.direction(uv);
        (d, self.pdf_uv(uv))
    }

    fn pdf_uv(&self, uv: Vec2) -> f32 {
        let x = ((uv.x * self.width as f32) as u32).min(self.width - 1);
        let y = ((uv.y * self.height as f32) as u32).min(self.height - 1);
        let sin_theta = (uv.y * PI).sin();
        if sin_theta <= 0.0 {
            return 0.0;
        }
        self.texel_p[(y * self.width + x) as usize] * (self.width * self.height) as f32
            / (2.0 * PI * PI * sin_theta)
    }

    /// Solid-angle pdf of sampling world direction `d`.
    pub fn pdf(&self, env: &Environment, d: Vec3) -> f32 {
        self.pdf_uv(env.uv(d))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::{r2, r2_offset};

    #[test]
    fn importance_estimate_of_irradiance_is_unbiased() {
        // E(+Y)/π = (1/π) ∫ L cos⁺ dω estimated by sampling the map alone matches the texel sum.
        let sun = Vec3::new(0.3, 0.8, 0.5).normalize();
        let env = Environment::from_fn("t", 256, 128, |d| {
            Vec3::splat(0.1 + if d.dot(sun) > 0.995 { 200.0 } else { 0.0 })
        });
        let dist = EnvDistribution::new(&env).unwrap();
        let exact = crate::irradiance::exact_irradiance_over_pi(&env, Vec3::Y).x;
        let n = 20000;
        let off = r2_offset(3);
        let mut s = 0.0f64;
        for i in 0..n {
            let (d, pdf) = dist.sample(&env, r2(i, off));
            assert!(
                (pdf - dist.pdf(&env, d)).abs() <= 1e-3 * pdf.max(1e-3),
                "pdf mismatch"
            );
            if pdf > 0.0 {
                s += (env.radiance(d).x * d.y.max(0.0) / PI / pdf) as f64;
            }
        }
        let est = s / n as f64;
        assert!(
            ((est as f32) - exact).abs() < 0.01 * exact,
            "{est} vs {exact}"
        );
    }
}
