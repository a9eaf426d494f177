//! The environment's sun, split out of the map into a disc light (`--sun auto|off`).
//!
//! A map's sun is a tiny, very bright region: folded into SH irradiance it lights everything
//! and shadows nothing. `--sun auto` (the default on every command) splits it into a
//! [`LightKind::Directional`] disc light of the same direction, angular radius and irradiance,
//! and leaves the residual map for SH, prefiltered mips and importance sampling. The GPU
//! renderer and the reference both light with the split pair, so the sun's share lands in
//! `light-irradiance` on both sides; `--sun off` keeps the whole map (and today's images).
//!
//! What counts as a sun:
//! - `builtin:sky`: its sun exactly — the disc [`crate::sky::Sky`] paints (direction, angular
//!   radius, irradiance known); the residual is the sky without the disc.
//! - A file map ([`find`]): the 8-connected region (wrapping in u) around the brightest texel of
//!   texels whose luminance is at least [`THRESHOLD`] × that texel's. It is a sun when its solid
//!   angle is at most [`MAX_SOLID_ANGLE`] sr and its flux above the surrounding sky is at least
//!   [`MIN_SHARE`] of the map's whole flux ∫ L dω (luminance). The light: the flux-weighted
//!   mean direction, the angular radius of a disc of the region's solid angle, the irradiance
//!   Σ (L − L_ring) dω with L_ring the mean radiance of the texels bordering the region; the
//!   residual holds L_ring in the region, so map + disc keep the map's flux exactly.
//! - `constant:…`: no sun.

use crate::{Environment, SceneError};
use glam::Vec3;
use std::f32::consts::PI;

/// Texels at least this fraction of the brightest texel's luminance belong to its region.
pub const THRESHOLD: f32 = 0.05;
/// Largest solid angle (sr) of a sun: a disc of 2° angular radius (the real sun is 0.27°;
/// 1k maps spread it over a few texels of 0.35°).
pub const MAX_SOLID_ANGLE: f32 = 3.83e-3;
/// Smallest share of the map's flux (∫ L dω, luminance) a sun carries.
pub const MIN_SHARE: f32 = 0.05;

use crate::environment::LUMINANCE;
pub use crate::environment::Sun;

/// `--sun`: split the environment's sun into a disc light, or keep the map whole.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Hash)]
pub enum SunMode {
    #[default]
    Auto,
    Off,
}

impl SunMode {
    pub const NAMES: [&'static str; 2] = ["auto", "off"];

    pub fn parse(s: &str) -> Result<Self, SceneError> {
        match s {
            "auto" => Ok(SunMode::Auto),
            "off" => Ok(SunMode::Off),
            _ => Err(SceneError::Argument(format!(
                "--sun {s}: expected auto or off"
            ))),
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            SunMode::Auto => "auto",
            SunMode::Off => "off",
        }
    }
}

/// A map's sun, found by the rule in the module documentation, and the residual texels; `None`
/// when the map holds no compact region bright enough.
pub fn find(env: &Environment) -> Option<(Sun, Vec<Vec3>)> {
    let (w, h) = (env.width, env.height);
    if w < 3 || h < 3 {
        return None;
    }
    let lum: Vec<f32> = env.texels.iter().map(|t| t.dot(LUMINANCE)).collect();
    let (peak_at, &peak) = lum.iter().enumerate().max_by(|a, b| a.1.total_cmp(b.1))?;
    if peak <= 0.0 {
        return None;
    }
    let total: f32 = (0..h)
        .map(|y| {
            env.texel_solid_angle(y)
                * lum[(y * w) as usize..((y + 1) * w) as usize]
                    .iter()
                    .sum::<f32>()
        })
        .sum();
    let threshold = THRESHOLD * peak;
    let index = |x: u32, y: u32| (y * w + x) as usize;
    let neighbours = |i: usize| {
        let (x, y) = ((i as u32) % w, (i as u32) / w);
        let mut out = Vec::with_capacity(8);
        for dy in -1i64..=1 {
            for dx in -1i64..=1 {
                let ny = y as i64 + dy;
                if (dx, dy) == (0, 0) || ny < 0 || ny >= h as i64 {
                    continue;
                }
                let nx = (x as i64 + dx).rem_euclid(w as i64) as u32;
                out.push(index(nx, ny as u32));
            }
        }
        out
    };
    // Flood fill, stopping as soon as the region is too large to be a sun.
    let mut inside = vec![false; lum.len()];
    let mut region = vec![peak_at];
    inside[peak_at] = true;
    let mut solid_angle = 0.0;
    let mut next = 0;
    while next < region.len() {
        let i = region[next];
        next += 1;
        solid_angle += env.texel_solid_angle(i as u32 / w);
        if solid_angle > MAX_SOLID_ANGLE {
            return None;
        }
        for n in neighbours(i) {
            if !inside[n] && lum[n] >= threshold {
                inside[n] = true;
                region.push(n);
            }
        }
    }
    // The sky around it: the texels bordering the region.
    let mut ring_sum = Vec3::ZERO;
    let mut ring_count = 0u32;
    let mut seen = vec![false; lum.len()];
    for &i in &region {
        for n in neighbours(i) {
            if !inside[n] && !seen[n] {
                seen[n] = true;
                ring_sum += env.texels[n];
                ring_count += 1;
            }
        }
    }
    let ring = if ring_count > 0 {
        ring_sum / ring_count as f32
    } else {
        Vec3::ZERO
    };
    let mut irradiance = Vec3::ZERO;
    let mut direction = Vec3::ZERO;
    let mut flux = 0.0;
    for &i in &region {
        let (x, y) = (i as u32 % w, i as u32 / w);
        let dw = env.texel_solid_angle(y);
        let excess = (env.texels[i] - ring).max(Vec3::ZERO);
        irradiance += excess * dw;
        let f = excess.dot(LUMINANCE) * dw;
        flux += f;
        direction += crate::environment::uv_to_dir(glam::Vec2::new(
            (x as f32 + 0.5) / w as f32,
            (y as f32 + 0.5) / h as f32,
        )) * f;
    }
    if total <= 0.0 || flux < MIN_SHARE * total {
        return None;
    }
    let direction = direction.try_normalize()?;
    let angular_radius = (1.0 - solid_angle / (2.0 * PI)).clamp(-1.0, 1.0).acos();
    let mut residual = env.texels.clone();
    for &i in &region {
        residual[i] = residual[i].min(ring.max(Vec3::ZERO));
    }
    // What the clamp removed beyond the excess (channels below the ring) stays in the map.
    let sun = Sun {
        direction,
        angular_radius,
        irradiance,
    };
    Some((sun, residual))
}

/// Applies `mode` to a loaded map: under `Auto` a sun found by [`find`] moves into
/// `env.sun` and the texels become the residual. Returns the log line (found or not).
pub fn split(env: &mut Environment, mode: SunMode) -> Option<String> {
    if mode == SunMode::Off || env.sun.is_some() {
        return None;
    }
    Some(match find(env) {
        Some((sun, residual)) => {
            env.texels = residual;
            env.sun = Some(sun);
            format!("{}: {}", env.name, sun.describe())
        }
        None => format!("{}: no compact sun found, the map stays whole", env.name),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::LightKind;

    fn map_with_disc(radius_deg: f32, boost: f32) -> (Environment, Vec3) {
        let dir = Vec3::new(0.3, 0.6, -0.7).normalize();
        let cos_r = radius_deg.to_radians().cos();
        let env = Environment::from_fn("disc", 512, 256, |d| {
            Vec3::new(0.4, 0.5, 0.8)
                + if d.dot(dir) >= cos_r {
                    Vec3::splat(boost)
                } else {
                    Vec3::ZERO
                }
        });
        (env, dir)
    }

    /// A disc painted on a uniform sky comes back as a light with its direction, radius and
    /// the flux it added; the residual is the uniform sky.
    #[test]
    fn finds_a_painted_disc() {
        let (env, dir) = map_with_disc(1.5, 2000.0);
        let (sun, residual) = find(&env).expect("a sun");
        assert!(sun.direction.dot(dir) > 0.9995, "{}", sun.direction);
        // Disc of 1.5° → 2.15e-3 sr; texels are 0.7°, so the count is within ~15 %.
        assert!(
            (sun.angular_radius.to_degrees() - 1.5).abs() < 0.3,
            "{}",
            sun.angular_radius.to_degrees()
        );
        let mut painted = 0.0;
        for y in 0..env.height {
            for x in 0..env.width {
                if env.texel_direction(x, y).dot(dir) >= 1.5f32.to_radians().cos() {
                    painted += 2000.0 * env.texel_solid_angle(y);
                }
            }
        }
        assert!(
            (sun.irradiance.x - painted).abs() < 1e-3 * painted,
            "{} vs {painted}",
            sun.irradiance.x
        );
        for t in residual {
            assert!((t - Vec3::new(0.4, 0.5, 0.8)).abs().max_element() < 1e-5);
        }
    }

    /// Too large (a window) or too faint (a lamp among bright walls): no sun.
    #[test]
    fn rejects_large_or_faint_regions() {
        assert!(find(&map_with_disc(8.0, 2000.0).0).is_none());
        assert!(find(&map_with_disc(1.0, 0.5).0).is_none());
        assert!(find(&Environment::constant(Vec3::ONE)).is_none());
    }

    #[test]
    fn light_follows_rotation_and_intensity() {
        let sun = Sun {
            direction: Vec3::X,
            angular_radius: 0.01,
            irradiance: Vec3::new(2.0, 1.0, 0.5),
        };
        let l = sun.light(90f32.to_radians(), 3.0);
        let LightKind::Directional {
            direction,
            angular_radius,
        } = l.kind
        else {
            panic!("a directional light");
        };
        assert!((direction - Vec3::Z).length() < 1e-6, "{direction}");
        assert_eq!(angular_radius, 0.01);
        assert!((l.color * l.intensity - Vec3::new(6.0, 3.0, 1.5)).length() < 1e-5);
    }

    #[test]
    fn mode_parse() {
        assert_eq!(SunMode::parse("auto").unwrap(), SunMode::Auto);
        assert_eq!(SunMode::parse("off").unwrap(), SunMode::Off);
        assert!(SunMode::parse("maybe").is_err());
    }
}
