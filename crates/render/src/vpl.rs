//! Virtual point lights (SSDO paper Sec. 5), each with its own shadow map (passes/shadow.rs),
//! whose lost small-scale shadows ssdo restores in screen space:
//! - [`environment_lights`] (`ssdo-vpl`, Fig. 10): the environment map as `count` directional
//!   lights. Texels of the map box-filtered to at most 128 × 64 are drawn with probability
//!   p_i ∝ luminance(L_i) · Ω_i (Ω_i the texel's solid angle); light k, drawn from texel i,
//!   carries the irradiance at normal incidence E_k = L_i Ω_i / (count · p_i), so that
//!   Σ_k E_k max(0, n·ω_k) V(ω_k) estimates ∫ L V cos dω. Rotation and intensity are applied.
//! - [`radiosity_lights`] (`instant-radiosity`, Fig. 11–12; Keller 1997): lit texels of the
//!   lights' reflective shadow maps (passes/rsm.rs) drawn with p_i ∝ luminance(Φ_i); light k,
//!   drawn from texel i, emits Φ_k = Φ_i / (count · p_i) as a cosine lobe about the texel's
//!   normal (intensity Φ_k cos θ / π), so that Σ_k Φ_k cos θ_k cos θ_x V_k / (π d_k²) estimates
//!   the irradiance of one diffuse bounce. Draws of the same texel are merged.
//!
//! Both draw from their discrete distribution by stratified sampling of its cumulative
//! distribution (one uniform stratum per light, at its centre), which is unbiased.

use crate::passes::rsm::RsmTexel;
use glam::Vec3;
use nearfield_scene::{Environment, Light, LightKind, environment::rotate_y};

/// Most virtual point lights.
/// Virtual point lights at most (ssdo-vpl, instant-radiosity).
pub const MAX_VPLS: u32 = 256;

fn luminance(c: Vec3) -> f32 {
    c.dot(Vec3::new(0.2126, 0.7152, 0.0722)).max(0.0)
}

/// `count` stratified draws from the discrete distribution with the given non-negative
/// weights: (index, p_index) per draw; empty when every weight is 0.
fn stratified_draws(weights: impl Iterator<Item = f64>, count: u32) -> Vec<(usize, f64)> {
    let mut cdf = Vec::new();
    let mut total = 0.0f64;
    for w in weights {
        total += w;
        cdf.push(total);
    }
    if total <= 0.0 || count == 0 {
        return Vec::new();
    }
    (0..count)
        .map(|k| {
            let u = (k as f64 + 0.5) / count as f64 * total;
            let i = cdf.partition_point(|&c| c < u).min(cdf.len() - 1);
            let below = if i == 0 { 0.0 } else { cdf[i - 1] };
            (i, (cdf[i] - below) / total)
        })
        .collect()
}

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
        sun: None,
    };
    let weights = (0..texels.len()).map(|i| {
        let y = i as u32 / w;
        (luminance(texels[i]) * small.texel_solid_angle(y)) as f64
    });
    stratified_draws(weights, count)
        .into_iter()
        .map(|(i, p)| {
            let (x, y) = (i as u32 % w, i as u32 / w);
            let omega = small.texel_solid_angle(y);
            let e = texels[i] * (omega / (count as f64 * p) as f32) * intensity;
            let towards = rotate_y(small.texel_direction(x, y), rotation);
            Light {
                kind: LightKind::Directional {
                    direction: -towards,
                    angular_radius: 0.0,
                },
                color: e,
                intensity: 1.0,
                range: None,
            }
        })
        .collect()
}

/// A virtual point light of Instant Radiosity: a cosine emitter of flux `flux` at `position`
/// about `normal`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RadiosityLight {
    pub position: Vec3,
    pub normal: Vec3,
    pub flux: Vec3,
}

/// At most `count` virtual point lights drawn from reflective-shadow-map texels (fewer where
/// draws of one texel merge).
pub fn radiosity_lights(texels: &[RsmTexel], count: u32) -> Vec<RadiosityLight> {
    let mut lights: Vec<(usize, RadiosityLight)> = Vec::new();
    for (i, p) in stratified_draws(texels.iter().map(|t| luminance(t.flux) as f64), count) {
        let t = &texels[i];
        let flux = t.flux / (count as f64 * p) as f32;
        match lights.last_mut() {
            // Draws come in index order, so repeats of a texel are adjacent.
            Some((last, l)) if *last == i => l.flux += flux,
            _ => lights.push((
                i,
                RadiosityLight {
                    position: t.position,
                    normal: t.normal,
                    flux,
                },
            )),
        }
    }
    lights.into_iter().map(|(_, l)| l).collect()
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
                    LightKind::Directional { direction, .. } => {
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
            let LightKind::Directional { direction, .. } = l.kind else {
                panic!()
            };
            assert!(-direction.y > 0.95, "{direction}");
        }
    }

    /// Every draw carries the total luminance / count, so the lights' luminance sums to the
    /// texels'; repeated draws of a texel merge into one light with that texel's flux here.
    #[test]
    fn radiosity_lights_keep_the_flux_and_merge_repeats() {
        let texel = |x: f32, flux: Vec3| RsmTexel {
            position: Vec3::new(x, 0.0, 0.0),
            normal: Vec3::Y,
            flux,
        };
        let texels = [
            texel(0.0, Vec3::splat(1.0)),
            texel(1.0, Vec3::splat(3.0)),
            texel(2.0, Vec3::ZERO),
        ];
        let lights = radiosity_lights(&texels, 8);
        // p = 1/4 and 3/4: strata 0–1 draw texel 0, strata 2–7 texel 1.
        assert_eq!(lights.len(), 2);
        for (l, t) in lights.iter().zip(&texels) {
            assert_eq!(l.position, t.position);
            assert!((l.flux - t.flux).abs().max_element() < 1e-5, "{l:?}");
        }
        assert!(radiosity_lights(&texels[2..], 8).is_empty());
    }
}
