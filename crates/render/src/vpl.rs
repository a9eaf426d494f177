//! Virtual point lights for the environment (SSDO paper Sec. 5, Fig. 10): the environment map as
//! `count` directional lights, each with its own shadow map (passes/shadow.rs), whose lost
//! small-scale shadows ssdo restores in screen space.
//!
//! Sampling: texels of the map box-filtered to at most 128 × 64 are drawn with probability
//! p_i ∝ luminance(L_i) · Ω_i (Ω_i the texel's solid angle) by stratified sampling of the
//! cumulative distribution (one uniform stratum per light, at its centre). Light k, drawn from
//! texel i, carries the irradiance at normal incidence E_k = L_i Ω_i / (count · p_i), so that
//! Σ_k E_k max(0, n·ω_k) V(ω_k) estimates ∫ L V cos dω (the estimator is unbiased for
//! stratified draws of the discrete distribution). Rotation and intensity are applied.

use glam::Vec3;
use nearfield_scene::{Environment, Light, LightKind, environment::rotate_y};

/// Most environment lights.
pub const MAX_VPLS: u32 = 256;

/// The environment as `count` directional lights (`Light::intensity` = 1, colour = E_k).
pub fn environment_lights(
    env: &Environment,
    rotation: f32,
    intensity: f32,
    count: u32,
) -> Vec<Light> {
    let (w, h, texels) = env.box_downsampled(128);
    let small = Environment {
        name: String::new(),
        width: w,
        height: h,
        texels: texels.clone(),
        rotation: 0.0,
        intensity: 1.0,
    };
    let luminance = |c: Vec3| c.dot(Vec3::new(0.2126, 0.7152, 0.0722)).max(0.0);
    let mut cdf = Vec::with_capacity(texels.len());
    let mut total = 0.0f64;
    for y in 0..h {
        let omega = small.texel_solid_angle(y);
        for x in 0..w {
            total += (luminance(texels[(y * w + x) as usize]) * omega) as f64;
            cdf.push(total);
        }
    }
    if total <= 0.0 || count == 0 {
        return Vec::new();
    }
    (0..count)
        .map(|k| {
            let u = (k as f64 + 0.5) / count as f64 * total;
            let i = cdf.partition_point(|&c| c < u).min(texels.len() - 1);
            let (x, y) = (i as u32 % w, i as u32 / w);
            let omega = small.texel_solid_angle(y);
            let radiance = texels[i];
            let p = (luminance(radiance) * omega) as f64 / total;
            let e = radiance * (omega / (count as f64 * p) as f32) * intensity;
            let towards = rotate_y(small.texel_direction(x, y), rotation);
            Light {
                kind: LightKind::Directional {
                    direction: -towards,
                },
                color: e,
                intensity: 1.0,
                range: None,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A constant environment L: Σ E_k max(0, n·ω_k) must approach π L (∫ L cos dω) for any n.
    #[test]
    fn constant_environment_gives_its_irradiance() {
        let env = Environment::constant(Vec3::splat(2.0));
        let lights = environment_lights(&env, 0.0, 1.0, 256);
        assert_eq!(lights.len(), 256);
        for n in [Vec3::Y, Vec3::X, Vec3::new(0.3, -0.8, 0.5).normalize()] {
            let e: f32 = lights
                .iter()
                .map(|l| match l.kind {
                    LightKind::Directional { direction } => {
                        l.color.x * (-direction).dot(n).max(0.0)
                    }
                    _ => 0.0,
                })
                .sum();
            let truth = std::f32::consts::PI * 2.0;
            assert!((e / truth - 1.0).abs() < 0.05, "n {n}: {e} vs {truth}");
        }
    }

    /// All power of a map lit only in one texel goes to that texel's direction.
    #[test]
    fn a_single_bright_texel_gets_every_light() {
        let env = Environment::from_fn("spot", 64, 32, |d| {
            if d.y > 0.99 {
                Vec3::splat(100.0)
            } else {
                Vec3::ZERO
            }
        });
        let lights = environment_lights(&env, 0.0, 1.0, 16);
        for l in &lights {
            let LightKind::Directional { direction } = l.kind else {
                panic!()
            };
            assert!(-direction.y > 0.95, "{direction}");
        }
    }
}
