//! The built-in analytic sky (`--env sky`): the Preetham, Shirley & Smits (1999) clear-sky model
//! ("A Practical Analytic Model for Daylight", Eq. 3 and Appendix A.2) plus a sun disc.
//!
//! - Sky: Perez luminance and chromaticity distributions with coefficients linear in turbidity T,
//!   zenith luminance and chromaticity from the paper's fits; xyY → XYZ → linear Rec.709.
//! - Sun: a disc of uniform radiance around the sun direction, of angular radius
//!   [`Sky::sun_radius_deg`] (the real sun's 0.27° is enlarged to 1° so that the 1024×512 map
//!   resolves it over several texels). Its radiance is set so that the sun's irradiance at normal
//!   incidence is [`Sky::sun_to_sky_ratio`] × the sky's irradiance on a horizontal surface.
//! - Ground (below the horizon): a uniform grey of 0.3 × the sky's horizontal irradiance / π,
//!   i.e. a 30 % albedo ground lit by the sky.
//! - Scale: the whole map is normalised so that an unoccluded upward surface receives
//!   env-irradiance (E/π) = 1 from sky and sun together; exposure 0 shows it at a pleasant level.

use crate::Environment;
use glam::{Mat3, Vec3};
use std::f32::consts::PI;

/// Parameters of the analytic sky.
#[derive(Clone, Copy, Debug)]
pub struct Sky {
    /// Atmospheric turbidity, 2 (very clear) ..= 10 (hazy). Default 3.
    pub turbidity: f32,
    /// Sun elevation above the horizon (degrees), 1..=90. Default 35.
    pub sun_elevation_deg: f32,
    /// Sun azimuth (degrees) measured like the map's u: 0 = −Z, 90 = +X. Default 150 (behind a camera on +Z looking at the origin, to its right).
    pub sun_azimuth_deg: f32,
    /// Apparent sun radius (degrees). Default 1.
    pub sun_radius_deg: f32,
    /// Sun normal irradiance over sky horizontal irradiance. Default 4.
    pub sun_to_sky_ratio: f32,
    /// Map size (width = 2 × height). Default 1024.
    pub width: u32,
}

impl Default for Sky {
    fn default() -> Self {
        Sky {
            turbidity: 3.0,
            sun_elevation_deg: 35.0,
            sun_azimuth_deg: 150.0,
            sun_radius_deg: 1.0,
            sun_to_sky_ratio: 4.0,
            width: 1024,
        }
    }
}

fn perez(theta: f32, gamma: f32, c: [f32; 5]) -> f32 {
    let [a, b, cc, d, e] = c;
    (1.0 + a * (b / theta.cos().max(0.01)).exp())
        * (1.0 + cc * (d * gamma).exp() + e * gamma.cos().powi(2))
}

impl Sky {
    /// Unit direction towards the sun.
    pub fn sun_direction(&self) -> Vec3 {
        let el = self.sun_elevation_deg.to_radians();
        let az = self.sun_azimuth_deg.to_radians();
        Vec3::new(el.cos() * az.sin(), el.sin(), -el.cos() * az.cos())
    }

    /// Sky radiance (un-normalised, linear Rec.709) for a direction above the horizon.
    fn sky_radiance(&self, d: Vec3) -> Vec3 {
        let t = self.turbidity;
        let s = self.sun_direction();
        let theta_s = s.y.clamp(-1.0, 1.0).acos();
        let theta = d.y.clamp(0.0, 1.0).acos();
        let gamma = d.dot(s).clamp(-1.0, 1.0).acos();
        let cy = [
            0.1787 * t - 1.4630,
            -0.3554 * t + 0.4275,
            -0.0227 * t + 5.3251,
            0.1206 * t - 2.5771,
            -0.0670 * t + 0.3703,
        ];
        let cx = [
            -0.0193 * t - 0.2592,
            -0.0665 * t + 0.0008,
            -0.0004 * t + 0.2125,
            -0.0641 * t - 0.8989,
            -0.0033 * t + 0.0452,
        ];
        let cyy = [
            -0.0167 * t - 0.2608,
            -0.0950 * t + 0.0092,
            -0.0079 * t + 0.2102,
            -0.0441 * t - 1.6537,
            -0.0109 * t + 0.0529,
        ];
        let chi = (4.0 / 9.0 - t / 120.0) * (PI - 2.0 * theta_s);
        let yz = (4.0453 * t - 4.9710) * chi.tan() - 0.2155 * t + 2.4192;
        let ts = [theta_s * theta_s * theta_s, theta_s * theta_s, theta_s, 1.0];
        let zen = |m: [[f32; 4]; 3]| {
            let row = |r: [f32; 4]| r.iter().zip(ts).map(|(a, b)| a * b).sum::<f32>();
            t * t * row(m[0]) + t * row(m[1]) + row(m[2])
        };
        let xz = zen([
            [0.00166, -0.00375, 0.00209, 0.0],
            [-0.02903, 0.06377, -0.03202, 0.00394],
            [0.11693, -0.21196, 0.06052, 0.25886],
        ]);
        let yzc = zen([
            [0.00275, -0.00610, 0.00317, 0.0],
            [-0.04214, 0.08970, -0.04153, 0.00516],
            [0.15346, -0.26756, 0.06670, 0.26688],
        ]);
        let big_y = yz * perez(theta, gamma, cy) / perez(0.0, theta_s, cy);
        let x = xz * perez(theta, gamma, cx) / perez(0.0, theta_s, cx);
        let y = yzc * perez(theta, gamma, cyy) / perez(0.0, theta_s, cyy);
        // xyY → XYZ → linear Rec.709 (sRGB primaries, D65).
        let xyz = Vec3::new(x / y * big_y, big_y, (1.0 - x - y) / y * big_y);
        let to_rgb = Mat3::from_cols(
            Vec3::new(3.2404542, -0.969266, 0.0556434),
            Vec3::new(-1.5371385, 1.8760108, -0.2040259),
            Vec3::new(-0.4985314, 0.0415560, 1.0572252),
        );
        (to_rgb * xyz).max(Vec3::ZERO)
    }

    /// Builds the normalised lat-long map, sun disc included.
    pub fn to_environment(&self) -> Environment {
        self.build(false)
    }

    /// The same map with its sun split out exactly (`--sun auto`, [`crate::sun`]): the texels
    /// without the disc, and `sun` with the disc's direction, angular radius and irradiance
    /// (the painted disc texels' radiance × solid angle). Same normalisation as
    /// [`Self::to_environment`]: residual + disc deliver the same irradiance.
    pub fn to_split_environment(&self) -> Environment {
        self.build(true)
    }

    fn build(&self, split: bool) -> Environment {
        let (w, h) = (self.width, self.width / 2);
        let sky = Environment::from_fn("sky", w, h, |d| {
            if d.y >= 0.0 {
                self.sky_radiance(d)
            } else {
                Vec3::ZERO
            }
        });
        // Horizontal irradiance from the sky dome.
        let mut e_sky = Vec3::ZERO;
        for y in 0..h {
            let dw = sky.texel_solid_angle(y);
            for x in 0..w {
                let d = sky.texel_direction(x, y);
                e_sky += sky.texels[(y * w + x) as usize] * d.y.max(0.0) * dw;
            }
        }
        let sun = self.sun_direction();
        let cos_r = self.sun_radius_deg.to_radians().cos();
        // Count the disc's actual texel solid angle so that the discrete sun delivers exactly the
        // intended irradiance.
        let mut disc_solid_angle = 0.0;
        for y in 0..h {
            for x in 0..w {
                if sky.texel_direction(x, y).dot(sun) >= cos_r {
                    disc_solid_angle += sky.texel_solid_angle(y);
                }
            }
        }
        let e_sky_lum = e_sky.dot(Vec3::new(0.2126, 0.7152, 0.0722));
        let sun_color = Vec3::new(1.0, 0.93, 0.84);
        let sun_radiance = sun_color * (self.sun_to_sky_ratio * e_sky_lum / disc_solid_angle);
        let ground = Vec3::splat(0.3 * e_sky_lum / PI);
        let mut env = sky;
        let whole = if split { Some(env.clone()) } else { None };
        for y in 0..h {
            for x in 0..w {
                let d = env.texel_direction(x, y);
                let t = &mut env.texels[(y * w + x) as usize];
                if d.y < 0.0 {
                    *t = ground;
                } else if d.dot(sun) >= cos_r {
                    *t += sun_radiance;
                }
            }
        }
        // Normalise: unoccluded upward E/π = 1 (luminance).
        let mut e_up = 0.0;
        for y in 0..h {
            let dw = env.texel_solid_angle(y);
            for x in 0..w {
                let d = env.texel_direction(x, y);
                e_up += env.texels[(y * w + x) as usize].dot(Vec3::new(0.2126, 0.7152, 0.0722))
                    * d.y.max(0.0)
                    * dw;
            }
        }
        let scale = PI / e_up;
        for t in &mut env.texels {
            *t *= scale;
        }
        let Some(mut residual) = whole else {
            return env;
        };
        for y in 0..h {
            for x in 0..w {
                let d = residual.texel_direction(x, y);
                let t = &mut residual.texels[(y * w + x) as usize];
                *t = if d.y < 0.0 { ground } else { *t } * scale;
            }
        }
        residual.sun = Some(crate::sun::Sun {
            direction: sun,
            angular_radius: self.sun_radius_deg.to_radians(),
            irradiance: sun_radiance * disc_solid_angle * scale,
        });
        residual
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sky_is_normalised_and_bluer_than_sun() {
        let sky = Sky {
            width: 256,
            ..Default::default()
        };
        let env = sky.to_environment();
        let c = crate::sh::project_environment(&env, 9);
        let e = crate::sh::irradiance_over_pi(&c, Vec3::Y);
        let lum = e.dot(Vec3::new(0.2126, 0.7152, 0.0722));
        // SH order 2 on a map with a sun: within a few percent of the exact normalisation.
        assert!((lum - 1.0).abs() < 0.05, "{lum}");
        // Zenith sky is blue.
        let z = env.radiance(Vec3::Y);
        assert!(z.z > z.x, "{z}");
        // The sun is far brighter than the sky beside it.
        let s = env.radiance(sky.sun_direction());
        assert!(s.x > 50.0 * z.x);
    }

    /// The split map is the whole map without the disc, and the disc's light carries exactly
    /// the flux the disc texels held (cosine ≈ 1 over a 1° disc).
    #[test]
    fn split_keeps_the_flux() {
        let sky = Sky {
            width: 256,
            ..Default::default()
        };
        let whole = sky.to_environment();
        let split = sky.to_split_environment();
        let sun = split.sun.expect("the sky has a sun");
        assert!((sun.direction - sky.sun_direction()).length() < 1e-6);
        let mut removed = Vec3::ZERO;
        for y in 0..whole.height {
            for x in 0..whole.width {
                let i = (y * whole.width + x) as usize;
                let d = whole.texels[i] - split.texels[i];
                assert!(d.min_element() >= -1e-4, "texel {x},{y} grew");
                removed += d * whole.texel_solid_angle(y);
            }
        }
        assert!(
            (removed - sun.irradiance).abs().max_element() < 1e-3 * sun.irradiance.max_element()
        );
        // 4× the sky's horizontal irradiance at normal incidence, in a sky normalised to E/π = 1
        // upwards: E_sun · sin 35° + E_sky = π with E_sun = 4 c E_sky, c the luminance of the
        // sun's colour (1, 0.93, 0.84).
        let luminance = Vec3::new(0.2126, 0.7152, 0.0722);
        let lum = sun.irradiance.dot(luminance);
        let c = Vec3::new(1.0, 0.93, 0.84).dot(luminance);
        let want = 4.0 * c * PI / (4.0 * c * 35f32.to_radians().sin() + 1.0);
        assert!((lum - want).abs() < 0.02 * want, "{lum} vs {want}");
    }
}
