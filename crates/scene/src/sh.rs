//! Real spherical harmonics up to band 3 (16 coefficients) and diffuse irradiance from them.
//!
//! Basis: the real SH in Cartesian form on unit world directions (x, y, z), index l·(l+1)+m, without
//! the Condon–Shortley phase (the common graphics form, e.g. Sloan, "Stupid Spherical Harmonics
//! Tricks", 2008, with the polar axis along world z). Order 2 = bands 0..2 = 9 coefficients,
//! order 3 = bands 0..3 = 16. `env_sh.wgsl` evaluates the same polynomials.
//!
//! Irradiance (Ramamoorthi & Hanrahan 2001): convolving radiance with the clamped cosine scales
//! band l by Â_l = π, 2π/3, π/4, 0 for l = 0..3, so E(n)/π = Σ_l (Â_l/π) Σ_m L_lm Y_lm(n). Band 3
//! contributes nothing to irradiance; its coefficients matter for SH occlusion (S3HO).

use crate::Environment;
use glam::Vec3;

/// Number of coefficients for bands 0..=l_max.
pub const fn coefficient_count(l_max: usize) -> usize {
    (l_max + 1) * (l_max + 1)
}

/// Evaluates the 16 basis functions at the unit direction `d`.
pub fn basis16(d: Vec3) -> [f32; 16] {
    let (x, y, z) = (d.x, d.y, d.z);
    [
        0.282_094_8,
        0.488_602_5 * y,
        0.488_602_5 * z,
        0.488_602_5 * x,
        1.092_548_4 * x * y,
        1.092_548_4 * y * z,
        0.315_391_57 * (3.0 * z * z - 1.0),
        1.092_548_4 * x * z,
        0.546_274_2 * (x * x - y * y),
        0.590_043_6 * y * (3.0 * x * x - y * y),
        2.890_611_4 * x * y * z,
        0.457_045_8 * y * (5.0 * z * z - 1.0),
        0.373_176_33 * z * (5.0 * z * z - 3.0),
        0.457_045_8 * x * (5.0 * z * z - 1.0),
        1.445_305_7 * z * (x * x - y * y),
        0.590_043_6 * x * (x * x - 3.0 * y * y),
    ]
}

/// Clamped-cosine convolution factors Â_l / π for bands 0..3.
pub const COSINE_LOBE_OVER_PI: [f32; 4] = [1.0, 2.0 / 3.0, 0.25, 0.0];

/// Band of coefficient index i.
pub fn band(i: usize) -> usize {
    (i as f32).sqrt() as usize
}

/// Projects an environment onto the first `count` (9 or 16) SH basis functions:
/// L_lm = Σ_texels L(d) Y_lm(d) Δω, with the map's rotation and intensity applied.
pub fn project_environment(env: &Environment, count: usize) -> Vec<Vec3> {
    assert!(count == 9 || count == 16, "SH order 2 (9) or 3 (16)");
    let mut acc = vec![glam::DVec3::ZERO; count];
    for y in 0..env.height {
        let dw = env.texel_solid_angle(y) as f64;
        for x in 0..env.width {
            let d = env.texel_direction(x, y);
            let l = env.texels[(y * env.width + x) as usize].as_dvec3() * dw;
            let b = basis16(d);
            for i in 0..count {
                acc[i] += l * b[i] as f64;
            }
        }
    }
    acc.into_iter()
        .map(|c| (c * env.intensity as f64).as_vec3())
        .collect()
}

/// Diffuse irradiance divided by π, E(n)/π, from SH radiance coefficients (9 or 16).
pub fn irradiance_over_pi(coeffs: &[Vec3], n: Vec3) -> Vec3 {
    let b = basis16(n);
    coeffs
        .iter()
        .enumerate()
        .map(|(i, c)| *c * b[i] * COSINE_LOBE_OVER_PI[band(i)])
        .sum()
}

/// Radiance reconstructed from SH coefficients in direction `d`.
pub fn evaluate(coeffs: &[Vec3], d: Vec3) -> Vec3 {
    let b = basis16(d);
    coeffs.iter().enumerate().map(|(i, c)| *c * b[i]).sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f32::consts::PI;

    /// Largest deviation of the discretised ∫ Y_i Y_j dω from δ_ij.
    fn orthonormality_error(samples_per_axis: u32) -> f32 {
        let env = Environment::from_fn("unit", 2 * samples_per_axis, samples_per_axis, |_| {
            Vec3::ONE
        });
        let mut worst: f32 = 0.0;
        for i in 0..16 {
            for j in 0..16 {
                let mut s = 0.0f64;
                for y in 0..env.height {
                    let dw = env.texel_solid_angle(y) as f64;
                    for x in 0..env.width {
                        let b = basis16(env.texel_direction(x, y));
                        s += (b[i] * b[j]) as f64 * dw;
                    }
                }
                let expect = if i == j { 1.0 } else { 0.0 };
                worst = worst.max((s as f32 - expect).abs());
            }
        }
        worst
    }

    #[test]
    fn basis_is_orthonormal() {
        assert!(orthonormality_error(128) < 2e-3);
    }

    /// The SH truth: radiance max(0, d·x). Exact irradiance/π is 2/3 for n = +x and
    /// 2/(3π) for n = +y. Order-2 SH (bands 0..2) gives, by Funk–Hecke,
    /// E(n)/π = Σ_l (Â_l²/π)(2l+1)/(4π) P_l(n·x) = 127/192 for n = +x and 27/128 for n = +y:
    /// the known truncation errors are −0.78 % and −0.61 %.
    #[test]
    fn clamped_cosine_irradiance() {
        let env = Environment::from_fn("x", 512, 256, |d| Vec3::splat(d.x.max(0.0)));
        for count in [9, 16] {
            let c = project_environment(&env, count);
            let ex = irradiance_over_pi(&c, Vec3::X).x;
            let ey = irradiance_over_pi(&c, Vec3::Y).x;
            assert!((ex - 127.0 / 192.0).abs() < 2e-4, "{ex}");
            assert!((ey - 27.0 / 128.0).abs() < 2e-4, "{ey}");
            assert!(((ex - 2.0 / 3.0) / (2.0 / 3.0)).abs() < 0.0079);
            assert!(((ey - 2.0 / (3.0 * PI)) / (2.0 / (3.0 * PI))).abs() < 0.0062);
        }
    }

    #[test]
    fn constant_environment_irradiance_is_exact() {
        let env = Environment::constant(Vec3::new(1.0, 2.0, 0.5));
        let c = project_environment(&env, 16);
        for n in [Vec3::Y, Vec3::X, Vec3::new(0.3, -0.8, 0.52).normalize()] {
            let e = irradiance_over_pi(&c, n);
            assert!(
                (e - Vec3::new(1.0, 2.0, 0.5)).abs().max_element() < 1e-4,
                "{e}"
            );
        }
    }
}
