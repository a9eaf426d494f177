//! Environment lighting: equirectangular (lat-long) radiance maps.
//!
//! The convention (docs/src/conventions.md; other tools depend on this exact formula): for a
//! world direction d, `v = acos(d.y) / π` (row 0 = zenith) and `u = atan2(d.x, −d.z) / (2π)`
//! wrapped to [0, 1), so u = 0 is −Z, u = 0.25 is +X and the image centre (u = 0.5) is +Z.
//! `--env-rotation DEG` turns the map about +Y: a feature seen in direction d₀ of the unrotated
//! map is seen in direction R_y(DEG)·d₀. Lookups are bilinear between texel centres, wrapping in
//! u and clamping in v; the GPU sampler (repeat in u, clamp-to-edge in v) does the same.

use crate::SceneError;
use crate::light::{Light, LightKind};
use glam::{Vec2, Vec3};
use std::f32::consts::PI;
use std::path::Path;

/// An equirectangular radiance map (linear RGB), with its rotation about +Y and intensity.
#[derive(Clone, Debug)]
pub struct Environment {
    pub name: String,
    pub width: u32,
    pub height: u32,
    /// Row-major, row 0 = zenith, in file units (before `intensity`).
    pub texels: Vec<Vec3>,
    /// Rotation of the map about +Y (radians).
    pub rotation: f32,
    /// Radiance scale applied on lookup.
    pub intensity: f32,
    /// The sun split out of the map (`--sun auto`, [`crate::sun`]); `texels` are then the
    /// residual. `None`: the map is whole.
    pub sun: Option<Sun>,
}

impl Environment {
    /// A uniform environment. Every lookup returns `radiance` exactly; the map is 256×128 so that
    /// its discrete SH projection is within 1e-4 of the exact one.
    pub fn constant(radiance: Vec3) -> Self {
        Environment {
            name: format!("constant:{},{},{}", radiance.x, radiance.y, radiance.z),
            width: 256,
            height: 128,
            texels: vec![radiance; 256 * 128],
            rotation: 0.0,
            intensity: 1.0,
            sun: None,
        }
    }

    /// Builds a map by evaluating `f` at every texel centre's direction (unrotated).
    pub fn from_fn(name: &str, width: u32, height: u32, f: impl Fn(Vec3) -> Vec3) -> Self {
        let mut texels = Vec::with_capacity((width * height) as usize);
        for y in 0..height {
            for x in 0..width {
                let uv = Vec2::new(
                    (x as f32 + 0.5) / width as f32,
                    (y as f32 + 0.5) / height as f32,
                );
                texels.push(f(uv_to_dir(uv)));
            }
        }
        Environment {
            name: name.into(),
            width,
            height,
            texels,
            rotation: 0.0,
            intensity: 1.0,
            sun: None,
        }
    }

    /// Loads a Radiance `.hdr` or OpenEXR `.exr` lat-long map. Rejects empty maps and maps with
    /// NaN, infinite or negative texels; warns when the aspect ratio is not 2:1.
    pub fn load(path: &Path) -> Result<Self, SceneError> {
        let err = |msg: String| SceneError::Environment {
            path: path.to_path_buf(),
            msg,
        };
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(|e| e.to_ascii_lowercase())
            .unwrap_or_default();
        if ext != "hdr" && ext != "exr" {
            return Err(err(
                "unknown format (expected .hdr or .exr, or sky, or constant:R,G,B)".into(),
            ));
        }
        if !path.is_file() {
            return Err(SceneError::Missing {
                path: path.to_path_buf(),
            });
        }
        crate::limits::check_regular_file(path)?;
        let open = || {
            image::ImageReader::open(path)
                .and_then(|r| r.with_guessed_format())
                .map_err(|e| err(e.to_string()))
        };
        // The header's size is checked before anything the size implies is allocated.
        let (w, h) = open()?.into_dimensions().map_err(|e| err(e.to_string()))?;
        use crate::limits::{MAX_ENVIRONMENT_PIXELS, MAX_ENVIRONMENT_SIDE};
        crate::limits::check_image_size(
            w,
            h,
            MAX_ENVIRONMENT_SIDE,
            MAX_ENVIRONMENT_PIXELS,
            "environment map",
        )
        .map_err(err)?;
        let mut reader = open()?;
        reader.limits(crate::limits::decoder_limits(
            MAX_ENVIRONMENT_SIDE,
            MAX_ENVIRONMENT_PIXELS,
            16,
        ));
        let img = reader
            .decode()
            .map_err(|e| err(e.to_string()))?
            .into_rgb32f();
        let (width, height) = img.dimensions();
        if width == 0 || height == 0 {
            return Err(err("the image is empty".into()));
        }
        let mut texels = Vec::with_capacity((width * height) as usize);
        for (x, y, p) in img.enumerate_pixels() {
            let c = Vec3::from(p.0);
            if !c.is_finite() {
                return Err(err(format!(
                    "texel ({x}, {y}) is not finite ({}, {}, {})",
                    c.x, c.y, c.z
                )));
            }
            if c.min_element() < 0.0 {
                return Err(err(format!("texel ({x}, {y}) is negative")));
            }
            texels.push(c);
        }
        if width != 2 * height {
            log::warn!(
                "{}: {width}×{height} is not 2:1; reading it as a lat-long map anyway",
                path.display()
            );
        }
        Ok(Environment {
            name: path
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default(),
            width,
            height,
            texels,
            rotation: 0.0,
            intensity: 1.0,
            sun: None,
        })
    }

    /// Texture coordinates of a world direction, including the map's rotation.
    pub fn uv(&self, d: Vec3) -> Vec2 {
        dir_to_uv(rotate_y(d, -self.rotation))
    }

    /// World direction of a texture coordinate, including the map's rotation.
    pub fn direction(&self, uv: Vec2) -> Vec3 {
        rotate_y(uv_to_dir(uv), self.rotation)
    }

    /// Radiance arriving from world direction `d` (bilinear, scaled by `intensity`).
    pub fn radiance(&self, d: Vec3) -> Vec3 {
        let uv = self.uv(d);
        let x = uv.x * self.width as f32 - 0.5;
        let y = (uv.y * self.height as f32 - 0.5).clamp(0.0, (self.height - 1) as f32);
        let x0 = x.floor();
        let y0 = y.floor().min((self.height - 1) as f32);
        let (fx, fy) = (x - x0, y - y0);
        let w = self.width as i64;
        let xi0 = (x0 as i64).rem_euclid(w) as u32;
        let xi1 = (x0 as i64 + 1).rem_euclid(w) as u32;
        let yi0 = y0 as u32;
        let yi1 = (yi0 + 1).min(self.height - 1);
        let t = |x: u32, y: u32| self.texels[(y * self.width + x) as usize];
        let top = t(xi0, yi0).lerp(t(xi1, yi0), fx);
        let bottom = t(xi0, yi1).lerp(t(xi1, yi1), fx);
        top.lerp(bottom, fy) * self.intensity
    }

    /// The sun's disc light in world space (rotation and intensity applied), if split out.
    pub fn sun_light(&self) -> Option<crate::Light> {
        self.sun.map(|s| s.light(self.rotation, self.intensity))
    }

    /// Solid angle (sr) of a texel in row `y`.
    pub fn texel_solid_angle(&self, y: u32) -> f32 {
        let theta0 = PI * y as f32 / self.height as f32;
        let theta1 = PI * (y + 1) as f32 / self.height as f32;
        2.0 * PI / self.width as f32 * (theta0.cos() - theta1.cos())
    }

    /// World direction of texel (x, y)'s centre, including rotation.
    pub fn texel_direction(&self, x: u32, y: u32) -> Vec3 {
        self.direction(Vec2::new(
            (x as f32 + 0.5) / self.width as f32,
            (y as f32 + 0.5) / self.height as f32,
        ))
    }
}

impl Environment {
    /// The texels (unrotated, without intensity) halved by 2×2 box filtering until the width is at
    /// most `max_width` (or the height reaches 1): (width, height, texels). Odd sides drop their
    /// last row or column.
    pub fn box_downsampled(&self, max_width: u32) -> (u32, u32, Vec<Vec3>) {
        let (mut w, mut h, mut t) = (self.width, self.height, self.texels.clone());
        while w > max_width && h >= 2 {
            let (nw, nh) = (w / 2, h / 2);
            let mut next = Vec::with_capacity((nw * nh) as usize);
            for y in 0..nh {
                for x in 0..nw {
                    let at = |dx: u32, dy: u32| t[((2 * y + dy) * w + 2 * x + dx) as usize];
                    next.push(0.25 * (at(0, 0) + at(1, 0) + at(0, 1) + at(1, 1)));
                }
            }
            (w, h, t) = (nw, nh, next);
        }
        (w, h, t)
    }

    /// The pre-convolved diffuse map: a `width`×`height` lat-long image (unrotated, without
    /// `intensity`, like `texels`) whose texel in direction n holds E(n)/π = (1/π) ∫ L(ω)
    /// max(0, n·ω) dω, summed over the map box-filtered to at most 128×64 texels (2.8° texels:
    /// E is smooth, and a sun in the map moves by at most half a texel).
    /// Row y holds the polar angle π y / (height − 1): rows 0 and height − 1 are the poles
    /// themselves (every texel of them the same direction), so that a bilinear lookup at
    /// [`irradiance_map_v`] has no azimuth-dependent value there. (With rows at texel centres,
    /// a normal at the pole read row 0 at whatever azimuth its u came out as: up to 7 % off
    /// under the built-in sky with its sun in the map.)
    pub fn irradiance_map(&self, width: u32, height: u32) -> Vec<Vec3> {
        let (w, h, t) = self.box_downsampled(128);
        let small = Environment {
            name: String::new(),
            width: w,
            height: h,
            texels: t,
            rotation: 0.0,
            intensity: 1.0,
            sun: None,
        };
        let sources: Vec<(Vec3, Vec3)> = (0..h)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .map(|(x, y)| {
                let l = small.texels[(y * w + x) as usize] * small.texel_solid_angle(y);
                (small.texel_direction(x, y), l)
            })
            .collect();
        let mut out = Vec::with_capacity((width * height) as usize);
        for y in 0..height {
            for x in 0..width {
                let n = uv_to_dir(Vec2::new(
                    (x as f32 + 0.5) / width as f32,
                    y as f32 / (height.max(2) - 1) as f32,
                ));
                let e: Vec3 = sources.iter().map(|(d, l)| *l * n.dot(*d).max(0.0)).sum();
                out.push(e / PI);
            }
        }
        out
    }
}

/// Texture v of polar coordinate `v` (0 at +Y, 1 at −Y) in an [`Environment::irradiance_map`]
/// of `height` rows, whose rows lie at v = y / (height − 1).
pub fn irradiance_map_v(v: f32, height: u32) -> f32 {
    (v * (height.max(2) - 1) as f32 + 0.5) / height as f32
}

/// The convention of docs/src/conventions.md, unrotated: direction → (u, v).
pub fn dir_to_uv(d: Vec3) -> Vec2 {
    let d = d.normalize();
    let v = d.y.clamp(-1.0, 1.0).acos() / PI;
    let mut u = d.x.atan2(-d.z) / (2.0 * PI);
    if u < 0.0 {
        u += 1.0;
    }
    if u >= 1.0 {
        u -= 1.0;
    }
    Vec2::new(u, v)
}

/// The inverse of [`dir_to_uv`].
pub fn uv_to_dir(uv: Vec2) -> Vec3 {
    let theta = uv.y * PI;
    let phi = uv.x * 2.0 * PI;
    let s = theta.sin();
    Vec3::new(s * phi.sin(), theta.cos(), -s * phi.cos())
}

/// Rotates `d` by `angle` radians about +Y (counter-clockwise seen from above, +X towards −Z).
pub fn rotate_y(d: Vec3, angle: f32) -> Vec3 {
    let (s, c) = angle.sin_cos();
    Vec3::new(c * d.x + s * d.z, d.y, -s * d.x + c * d.z)
}

/// Rec. 709 luminance weights.
pub const LUMINANCE: Vec3 = Vec3::new(0.2126, 0.7152, 0.0722);

/// A sun in the map's own frame (unrotated, without the environment's `intensity`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sun {
    /// Unit direction towards the sun's centre.
    pub direction: Vec3,
    /// Angular radius of the disc (radians).
    pub angular_radius: f32,
    /// Irradiance at normal incidence from the whole disc (linear RGB, W/m² in map units).
    pub irradiance: Vec3,
}

impl Sun {
    /// The disc light of this sun for a map turned by `rotation` and scaled by `intensity`.
    pub fn light(&self, rotation: f32, intensity: f32) -> Light {
        let towards = rotate_y(self.direction, rotation);
        let lux = self.irradiance.max_element().max(0.0);
        Light {
            kind: LightKind::Directional {
                direction: -towards,
                angular_radius: self.angular_radius,
            },
            color: if lux > 0.0 {
                self.irradiance / lux
            } else {
                Vec3::ONE
            },
            intensity: lux * intensity,
            range: None,
        }
    }

    /// One line for the log: what was found.
    pub fn describe(&self) -> String {
        let d = self.direction;
        let elevation = d.y.clamp(-1.0, 1.0).asin().to_degrees();
        let azimuth = d.x.atan2(-d.z).to_degrees().rem_euclid(360.0);
        format!(
            "sun at elevation {elevation:.1}°, azimuth {azimuth:.1}°, radius {:.2}°, irradiance {:.3} (luminance, map units)",
            self.angular_radius.to_degrees(),
            self.irradiance.dot(LUMINANCE)
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A constant sky gives E/π = L everywhere; a sky bright only above the horizon gives
    /// (1 + n_y)/2 (the cosine lobe's share of the upper hemisphere), within the 2.8° texels.
    #[test]
    fn irradiance_map_matches_closed_forms() {
        let constant = Environment::constant(Vec3::splat(2.0));
        for e in constant.irradiance_map(16, 8) {
            assert!((e - Vec3::splat(2.0)).abs().max_element() < 0.01, "{e}");
        }
        let upper = Environment::from_fn("upper", 128, 64, |d| {
            Vec3::splat(if d.y > 0.0 { 1.0 } else { 0.0 })
        });
        let (w, h) = (16, 8);
        let map = upper.irradiance_map(w, h);
        for y in 0..h {
            let n = uv_to_dir(Vec2::new(0.5 / w as f32, y as f32 / (h - 1) as f32));
            let want = 0.5 * (1.0 + n.y);
            assert!(
                (map[(y * w) as usize].x - want).abs() < 0.02,
                "row {y}: {} vs {want}",
                map[(y * w) as usize].x
            );
        }
    }

    /// The poles' rows hold the poles: under a map bright towards +X only, the up-facing row is
    /// the same at every azimuth (and equals the exact E(+Y)).
    #[test]
    fn irradiance_map_poles_do_not_depend_on_azimuth() {
        let env = Environment::from_fn("lobe", 128, 64, |d| {
            Vec3::splat(d.x.max(0.0).powi(8) * 10.0)
        });
        let (w, h) = (64, 32);
        let map = env.irradiance_map(w, h);
        let row0: Vec<f32> = map[..w as usize].iter().map(|e| e.x).collect();
        let spread = row0.iter().fold(0.0f32, |a, &b| a.max(b))
            - row0.iter().fold(f32::MAX, |a, &b| a.min(b));
        assert!(
            spread < 1e-5 * row0[0].abs().max(1.0),
            "row 0 varies by {spread}"
        );
        assert!((irradiance_map_v(0.0, h) - 0.5 / h as f32).abs() < 1e-7);
        assert!((irradiance_map_v(1.0, h) - (h as f32 - 0.5) / h as f32).abs() < 1e-7);
    }

    #[test]
    fn convention_axes() {
        let cases = [
            (Vec3::NEG_Z, 0.0, 0.5),
            (Vec3::X, 0.25, 0.5),
            (Vec3::Z, 0.5, 0.5),
            (Vec3::NEG_X, 0.75, 0.5),
            (Vec3::Y, 0.0, 0.0), // u is undefined at the poles
            (Vec3::NEG_Y, 0.0, 1.0),
        ];
        for (d, u, v) in cases {
            let uv = dir_to_uv(d);
            assert!((uv.y - v).abs() < 1e-6, "{d}: v {}", uv.y);
            if v > 0.0 && v < 1.0 {
                assert!((uv.x - u).abs() < 1e-6, "{d}: u {}", uv.x);
                assert!((uv_to_dir(uv) - d).length() < 1e-6);
            }
        }
    }

    #[test]
    fn rotation_moves_features() {
        // A map bright only near +X, rotated by 90°: +X turns to −Z, so the feature is seen there.
        let mut env = Environment::from_fn("x", 64, 32, |d| Vec3::splat(d.x.max(0.0)));
        env.rotation = 90f32.to_radians();
        let feature = rotate_y(Vec3::X, env.rotation);
        assert!((feature - Vec3::NEG_Z).length() < 1e-6);
        assert!(env.radiance(Vec3::NEG_Z).x > 0.95);
        assert!(env.radiance(Vec3::X).x < 0.05);
    }

    #[test]
    fn solid_angles_sum_to_sphere() {
        let env = Environment::constant(Vec3::ONE);
        let total: f32 = (0..env.height)
            .map(|y| env.texel_solid_angle(y) * env.width as f32)
            .sum();
        assert!((total - 4.0 * PI).abs() < 1e-4);
    }
}
