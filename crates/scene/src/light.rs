//! Punctual lights (`KHR_lights_punctual`), the environment's sun as a directional disc light,
//! and their unshadowed irradiance, shared by the GPU renderer (mirrored in
//! `direct_lighting.wgsl`) and the reference tracer.

use glam::Vec3;

/// What kind of punctual light, with its geometry in world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightKind {
    /// Light travelling along `direction` (unit, world space) from a distant disc of
    /// `angular_radius` (radians; 0 = a parallel, punctual light). Intensity in lux: the
    /// irradiance at normal incidence from the whole disc. The environment's sun
    /// ([`crate::sun`]) is such a disc.
    Directional {
        direction: Vec3,
        angular_radius: f32,
    },
    /// Omnidirectional light at `position`. Intensity in candela.
    Point { position: Vec3 },
    /// Cone light at `position` shining along `direction`, full intensity inside
    /// `inner_cone` and none outside `outer_cone` (half-angles, radians). Intensity in candela.
    Spot {
        position: Vec3,
        direction: Vec3,
        inner_cone: f32,
        outer_cone: f32,
    },
}

/// A punctual light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Light {
    pub kind: LightKind,
    /// Linear RGB colour.
    pub color: Vec3,
    /// Lux for directional lights, candela for point and spot lights.
    pub intensity: f32,
    /// Distance (m) at which point/spot lights fade to zero; `None` = inverse-square forever.
    pub range: Option<f32>,
}

impl Light {
    /// The unit vector from `p` towards the light, and the distance to it (infinite for
    /// directional lights).
    pub fn direction_from(&self, p: Vec3) -> (Vec3, f32) {
        match self.kind {
            LightKind::Directional { direction, .. } => (-direction, f32::INFINITY),
            LightKind::Point { position } | LightKind::Spot { position, .. } => {
                let d = position - p;
                let dist = d.length();
                (d / dist.max(1e-12), dist)
            }
        }
    }

    /// Irradiance arriving at a point from the light along `to_light`, on a surface facing the
    /// light (no cosine, no shadowing), RGB. Point and spot lights fall off with the inverse square
    /// of the distance, windowed by `range` as recommended by `KHR_lights_punctual`:
    /// `clamp(1 − (d/range)⁴, 0, 1)² / d²`. Spot lights fade between the cones with
    /// `t² ` where `t = clamp((cos θ − cos outer) / (cos inner − cos outer), 0, 1)` (the
    /// extension's sample implementation).
    pub fn normal_irradiance(&self, p: Vec3) -> Vec3 {
        let (to_light, dist) = self.direction_from(p);
        let mut e = self.color * self.intensity;
        match self.kind {
            LightKind::Directional { .. } => return e,
            LightKind::Point { .. } => {}
            LightKind::Spot {
                direction,
                inner_cone,
                outer_cone,
                ..
            } => {
                let cos_outer = outer_cone.cos();
                let cos_inner = inner_cone.cos();
                let t = ((direction.dot(-to_light) - cos_outer)
                    / (cos_inner - cos_outer).max(1e-4))
                .clamp(0.0, 1.0);
                e *= t * t;
            }
        }
        let window = match self.range {
            Some(r) if r > 0.0 => (1.0 - (dist / r).powi(4)).clamp(0.0, 1.0).powi(2),
            _ => 1.0,
        };
        e * window / (dist * dist).max(1e-8)
    }

    /// Unshadowed irradiance E_l(P) on a surface at `p` with unit normal `n` (RGB). The
    /// `light-irradiance` AOV is (1/π) Σ E_l with shadows. For a disc of uniform radiance
    /// wholly above the surface's horizon, ∫_disc ω·n dω is exactly (c·n) times its normal
    /// irradiance (c its centre), so a disc light uses the centre's cosine too.
    pub fn irradiance(&self, p: Vec3, n: Vec3) -> Vec3 {
        let (l, _) = self.direction_from(p);
        self.normal_irradiance(p) * n.dot(l).max(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn point_light_inverse_square_and_cosine() {
        let l = Light {
            kind: LightKind::Point {
                position: Vec3::new(0.0, 2.0, 0.0),
            },
            color: Vec3::ONE,
            intensity: 8.0,
            range: None,
        };
        // Straight below at distance 2: 8 / 4 = 2.
        assert!((l.irradiance(Vec3::ZERO, Vec3::Y).x - 2.0).abs() < 1e-6);
        // At (2,0,0): distance sqrt(8), cosine 2/sqrt(8).
        let e = l.irradiance(Vec3::new(2.0, 0.0, 0.0), Vec3::Y).x;
        assert!((e - 8.0 / 8.0 * (2.0 / 8f32.sqrt())).abs() < 1e-6);
    }

    #[test]
    fn spot_cone_falloff() {
        let l = Light {
            kind: LightKind::Spot {
                position: Vec3::new(0.0, 1.0, 0.0),
                direction: -Vec3::Y,
                inner_cone: 0.2,
                outer_cone: 0.4,
            },
            color: Vec3::ONE,
            intensity: 1.0,
            range: None,
        };
        assert!((l.normal_irradiance(Vec3::ZERO).x - 1.0).abs() < 1e-6);
        // Outside the outer cone: dark.
        assert_eq!(l.normal_irradiance(Vec3::new(1.0, 0.0, 0.0)).x, 0.0);
    }
}
