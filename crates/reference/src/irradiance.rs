//! Unoccluded diffuse irradiance of the environment, E(n)/π, for every normal: the exact
//! cosine-weighted integral of the map, tabulated on a lat-long grid and read bilinearly. Used for
//! the outgoing radiance of surfaces hit by indirect rays with `--senders unshadowed` (the L_o of
//! docs/src/aovs.md with full visibility, V ≡ 1 at x′).
//!
//! The map is first reduced by solid-angle-weighted box filtering to at most 256×128 texels (the
//! cosine lobe is smooth, so this keeps the integral to ~1e-4). The [`EXACT_TEXELS`] texels that
//! carry the most energy (a sun) are kept aside and evaluated exactly at every lookup, because
//! their clamped-cosine kink is what a table interpolates worst; the rest is integrated for each
//! of the 128×64 grid normals and read bilinearly. `tests::grid_matches_exact_integral` bounds
//! the error.

use glam::{Vec2, Vec3};
use nearfield_scene::Environment;
use nearfield_scene::environment::{dir_to_uv, uv_to_dir};
use rayon::prelude::*;

const GRID_W: u32 = 128;
const GRID_H: u32 = 64;
const MAX_W: u32 = 256;
/// Brightest reduced texels evaluated exactly at lookup time.
pub const EXACT_TEXELS: usize = 64;

pub struct IrradianceMap {
    values: Vec<Vec3>,
    /// (direction, radiance × solid angle / π) of the brightest texels.
    exact: Vec<(Vec3, Vec3)>,
}

/// (world direction, radiance × solid angle) of a reduced copy of the map.
fn reduced_texels(env: &Environment) -> Vec<(Vec3, Vec3)> {
    let factor = (env.width / MAX_W).max(1);
    let (w, h) = (env.width / factor, env.height / factor);
    let mut out = Vec::with_capacity((w * h) as usize);
    for y in 0..h {
        for x in 0..w {
            let mut sum = Vec3::ZERO;
            let mut dir = Vec3::ZERO;
            for dy in 0..factor {
                let row = y * factor + dy;
                let dw = env.texel_solid_angle(row);
                for dx in 0..factor {
                    let col = x * factor + dx;
                    sum += env.texels[(row * env.width + col) as usize] * dw;
                    dir += env.texel_direction(col, row) * dw;
                }
            }
            out.push((dir.normalize_or_zero(), sum * env.intensity));
        }
    }
    out
}

/// Exact (to the texel) E(n)/π of the whole map.
pub fn exact_irradiance_over_pi(env: &Environment, n: Vec3) -> Vec3 {
    let mut e = Vec3::ZERO;
    for y in 0..env.height {
        let dw = env.texel_solid_angle(y);
        for x in 0..env.width {
            let d = env.texel_direction(x, y);
            e += env.texels[(y * env.width + x) as usize] * (n.dot(d).max(0.0) * dw);
        }
    }
    e * env.intensity / std::f32::consts::PI
}

impl IrradianceMap {
    pub fn new(env: &Environment) -> Self {
        let mut texels = reduced_texels(env);
        texels.sort_by(|a, b| b.1.element_sum().total_cmp(&a.1.element_sum()));
        let split = EXACT_TEXELS.min(texels.len());
        let exact = texels[..split]
            .iter()
            .map(|(d, l)| (*d, *l / std::f32::consts::PI))
            .collect();
        let texels = texels.split_off(split);
        let values = (0..GRID_W * GRID_H)
            .into_par_iter()
            .map(|i| {
                let (x, y) = (i % GRID_W, i / GRID_W);
                let n = uv_to_dir(Vec2::new(
                    (x as f32 + 0.5) / GRID_W as f32,
                    (y as f32 + 0.5) / GRID_H as f32,
                ));
                let mut e = Vec3::ZERO;
                for (d, l) in &texels {
                    e += *l * n.dot(*d).max(0.0);
                }
                e / std::f32::consts::PI
            })
            .collect();
        IrradianceMap { values, exact }
    }

    /// E(n)/π for a unit world normal.
    pub fn lookup(&self, n: Vec3) -> Vec3 {
        let uv = dir_to_uv(n);
        let x = uv.x * GRID_W as f32 - 0.5;
        let y = (uv.y * GRID_H as f32 - 0.5).clamp(0.0, (GRID_H - 1) as f32);
        let x0 = x.floor();
        let y0 = y.floor().min((GRID_H - 1) as f32);
        let (fx, fy) = (x - x0, y - y0);
        let xi0 = (x0 as i64).rem_euclid(GRID_W as i64) as u32;
        let xi1 = (x0 as i64 + 1).rem_euclid(GRID_W as i64) as u32;
        let yi0 = y0 as u32;
        let yi1 = (yi0 + 1).min(GRID_H - 1);
        let t = |x: u32, y: u32| self.values[(y * GRID_W + x) as usize];
        let top = t(xi0, yi0).lerp(t(xi1, yi0), fx);
        let bottom = t(xi0, yi1).lerp(t(xi1, yi1), fx);
        let exact: Vec3 = self
            .exact
            .iter()
            .map(|(d, l)| *l * n.dot(*d).max(0.0))
            .sum();
        top.lerp(bottom, fy) + exact
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_matches_exact_integral() {
        // A map with a small bright "sun" and a gradient sky: the hardest smooth case.
        let sun = Vec3::new(0.4, 0.6, -0.69).normalize();
        let env = Environment::from_fn("t", 512, 256, |d| {
            Vec3::splat(0.2 + 0.3 * d.y.max(0.0))
                + Vec3::splat(if d.dot(sun) > 0.999 { 500.0 } else { 0.0 })
        });
        let map = IrradianceMap::new(&env);
        let mut worst: f32 = 0.0;
        for i in 0..64u32 {
            let n = crate::sampling::cosine_hemisphere(Vec3::Y, crate::sampling::r2(i, Vec2::ZERO));
            let n = if i % 2 == 0 { n } else { -n };
            let exact = exact_irradiance_over_pi(&env, n).x;
            worst = worst.max((map.lookup(n).x - exact).abs() / exact.max(0.05));
        }
        assert!(worst < 0.01, "worst relative error {worst}");
    }

    #[test]
    fn constant_environment_is_exact() {
        let env = Environment::constant(Vec3::splat(2.0));
        let map = IrradianceMap::new(&env);
        for n in [Vec3::Y, Vec3::X, Vec3::new(0.2, -0.9, 0.3).normalize()] {
            assert!((map.lookup(n).x - 2.0).abs() < 2e-3, "{}", map.lookup(n));
        }
    }
}
