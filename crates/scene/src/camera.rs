//! Pinhole cameras, the camera JSON file format and auto-framing.
//!
//! Conventions (docs/src/conventions.md): right-handed world, +Y up; view space looks down −Z;
//! wgpu clip depth 0..1; pixel centres at (x+0.5, y+0.5) with row 0 at the top.

use crate::{Aabb, SceneError};
use glam::{Mat4, Vec2, Vec3};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// A perspective pinhole camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub eye: Vec3,
    pub target: Vec3,
    pub up: Vec3,
    /// Vertical field of view (radians), in (0, π).
    pub yfov: f32,
}

impl Camera {
    pub fn new(eye: Vec3, target: Vec3, yfov_deg: f32) -> Self {
        Camera {
            eye,
            target,
            up: Vec3::Y,
            yfov: yfov_deg.to_radians(),
        }
    }

    /// A view of `bounds` from the front (+Z), slightly above, with the whole bounding sphere
    /// inside the vertical field of view.
    pub fn framing(bounds: Aabb, yfov: f32) -> Self {
        let (center, radius) = if bounds.is_empty() {
            (Vec3::ZERO, 1.0)
        } else {
            (bounds.center(), bounds.radius().max(1e-4))
        };
        let dist = radius / (0.5 * yfov).sin() * 1.05;
        let dir = Vec3::new(0.0, 0.35, 1.0).normalize();
        Camera {
            eye: center + dir * dist,
            target: center,
            up: Vec3::Y,
            yfov,
        }
    }

    /// Unit view direction.
    pub fn forward(&self) -> Vec3 {
        (self.target - self.eye).normalize()
    }

    /// World → view (camera at the origin looking down −Z).
    /// The camera turned by `degrees` about the axis through `target` along `up` (positive =
    /// counter-clockwise seen from above); target, up and field of view stay.
    pub fn orbit(&self, degrees: f32) -> Camera {
        let axis = self.up.normalize();
        let rotation = glam::Quat::from_axis_angle(axis, degrees.to_radians());
        Camera {
            eye: self.target + rotation * (self.eye - self.target),
            ..*self
        }
    }

    /// Whether going from `self` to `next` is a cut: the view direction turns by more than 30°,
    /// the eye moves by more than half its distance to the target, or the field of view
    /// changes by more than 10 %. Reprojected history is discarded across a cut.
    pub fn is_cut_to(&self, next: &Camera) -> bool {
        let turn = self.forward().dot(next.forward()).clamp(-1.0, 1.0).acos();
        let distance = (self.target - self.eye).length().max(1e-6);
        turn > 30f32.to_radians()
            || (next.eye - self.eye).length() > 0.5 * distance
            || (next.yfov / self.yfov - 1.0).abs() > 0.1
    }

    pub fn view_from_world(&self) -> Mat4 {
        glam::camera::rh::view::look_at_mat4(self.eye, self.target, self.up)
    }

    /// View → clip with wgpu's depth range 0..1.
    pub fn clip_from_view(&self, aspect: f32, near: f32, far: f32) -> Mat4 {
        glam::camera::rh::proj::directx::perspective(self.yfov, aspect, near, far)
    }

    /// Near and far planes that enclose `bounds` as seen from this camera: far just beyond the
    /// farthest corner, near at 1/10000 of far or the nearest corner's depth, whichever is larger.
    pub fn depth_range(&self, bounds: Aabb) -> (f32, f32) {
        if bounds.is_empty() {
            return (0.01, 100.0);
        }
        let view = self.view_from_world();
        let mut zmin = f32::INFINITY;
        let mut zmax: f32 = 0.0;
        for c in bounds.corners() {
            let z = -view.transform_point3(c).z;
            zmin = zmin.min(z);
            zmax = zmax.max(z);
        }
        let far = (zmax * 1.01).max(1e-3);
        let near = (zmin * 0.99).max(far * 1e-4);
        (near, far)
    }

    /// World-space unit direction of the primary ray through the centre of pixel (x, y) of a
    /// `size` image: pixel centres at (x+0.5, y+0.5), row 0 at the top. The GPU rasterizer
    /// samples the same points.
    pub fn primary_ray(&self, x: u32, y: u32, size: (u32, u32)) -> Vec3 {
        self.ray_through(Vec2::new(x as f32 + 0.5, y as f32 + 0.5), size)
    }

    /// World-space unit direction through a point in pixel coordinates.
    pub fn ray_through(&self, pixel: Vec2, size: (u32, u32)) -> Vec3 {
        let aspect = size.0 as f32 / size.1 as f32;
        let t = (0.5 * self.yfov).tan();
        let ndc_x = 2.0 * pixel.x / size.0 as f32 - 1.0;
        let ndc_y = 1.0 - 2.0 * pixel.y / size.1 as f32;
        let dir_view = Vec3::new(ndc_x * t * aspect, ndc_y * t, -1.0);
        let world_from_view = self.view_from_world().inverse();
        world_from_view.transform_vector3(dir_view).normalize()
    }

    /// Checks that the camera can form an image.
    pub fn validate(&self) -> Result<(), String> {
        if !(self.eye.is_finite() && self.target.is_finite() && self.up.is_finite()) {
            return Err("eye, target and up must be finite".into());
        }
        if (self.target - self.eye).length() < 1e-9 {
            return Err("eye and target coincide".into());
        }
        if !(self.yfov > 0.0 && self.yfov < std::f32::consts::PI) {
            return Err(format!(
                "field of view {}° is outside (0°, 180°)",
                self.yfov.to_degrees()
            ));
        }
        if self.forward().cross(self.up.normalize_or_zero()).length() < 1e-6 {
            return Err("up is parallel to the view direction".into());
        }
        Ok(())
    }
}

/// The camera JSON file: `{"eye":[x,y,z],"target":[x,y,z],"up":[0,1,0],"yfov_deg":45}`.
/// `up` may be omitted (default +Y); the other fields are required.
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct CameraFile {
    pub eye: [f32; 3],
    pub target: [f32; 3],
    #[serde(default = "default_up")]
    pub up: [f32; 3],
    pub yfov_deg: f32,
}

fn default_up() -> [f32; 3] {
    [0.0, 1.0, 0.0]
}

impl CameraFile {
    /// Reads and validates a camera JSON file.
    pub fn load(path: &Path) -> Result<Camera, SceneError> {
        if crate::limits::check_regular_file(path)? > 1 << 20 {
            return Err(SceneError::CameraFile {
                path: path.to_path_buf(),
                msg: "larger than 1 MiB; a camera file is a few lines of JSON".into(),
            });
        }
        let text = std::fs::read_to_string(path).map_err(|e| {
            if e.kind() == std::io::ErrorKind::NotFound {
                SceneError::Missing {
                    path: path.to_path_buf(),
                }
            } else {
                SceneError::Io {
                    path: path.to_path_buf(),
                    source: e,
                }
            }
        })?;
        Self::parse(&text).map_err(|msg| SceneError::CameraFile {
            path: path.to_path_buf(),
            msg,
        })
    }

    /// Parses and validates camera JSON text.
    pub fn parse(text: &str) -> Result<Camera, String> {
        let f: CameraFile = serde_json::from_str(text).map_err(|e| e.to_string())?;
        let cam = Camera {
            eye: f.eye.into(),
            target: f.target.into(),
            up: f.up.into(),
            yfov: f.yfov_deg.to_radians(),
        };
        cam.validate()?;
        Ok(cam)
    }

    pub fn from_camera(c: &Camera) -> Self {
        CameraFile {
            eye: c.eye.into(),
            target: c.target.into(),
            up: c.up.into(),
            yfov_deg: c.yfov.to_degrees(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn orbit_turns_about_the_target_and_small_moves_are_not_cuts() {
        let c = Camera::new(Vec3::new(0.0, 1.0, 4.0), Vec3::new(0.0, 1.0, 0.0), 45.0);
        let o = c.orbit(90.0);
        assert!(
            (o.eye - Vec3::new(4.0, 1.0, 0.0)).length() < 1e-5,
            "{}",
            o.eye
        );
        assert_eq!(o.target, c.target);
        assert!(((o.eye - o.target).length() - 4.0).abs() < 1e-5);
        assert!(!c.is_cut_to(&c.orbit(10.0)));
        assert!(c.is_cut_to(&c.orbit(45.0)));
        assert!(c.is_cut_to(&Camera {
            yfov: c.yfov * 1.5,
            ..c
        }));
    }

    #[test]
    fn centre_pixel_looks_at_target() {
        let c = Camera::new(Vec3::new(1.0, 2.0, 3.0), Vec3::new(0.0, 0.5, 0.0), 45.0);
        // 2x2 image: the centre is the corner shared by all four pixels.
        let d = c.ray_through(Vec2::new(1.0, 1.0), (2, 2));
        assert!((d - c.forward()).length() < 1e-6);
        // Row 0 is the top: its ray points more upward than the last row's.
        assert!(c.primary_ray(0, 0, (4, 4)).y > c.primary_ray(0, 3, (4, 4)).y);
    }

    #[test]
    fn projection_maps_pixel_rays_back_to_pixels() {
        let c = Camera::new(Vec3::new(0.3, 1.0, 4.0), Vec3::ZERO, 50.0);
        let size = (64u32, 32u32);
        let clip_from_world = c.clip_from_view(2.0, 0.1, 100.0) * c.view_from_world();
        let d = c.primary_ray(10, 20, size);
        let p = clip_from_world.project_point3(c.eye + 3.0 * d);
        let px = (p.x * 0.5 + 0.5) * size.0 as f32;
        let py = (0.5 - p.y * 0.5) * size.1 as f32;
        assert!(
            (px - 10.5).abs() < 1e-3 && (py - 20.5).abs() < 1e-3,
            "{px} {py}"
        );
        assert!(p.z > 0.0 && p.z < 1.0);
    }

    #[test]
    fn camera_json_requires_fields() {
        let err = CameraFile::parse(r#"{"target":[0,0,0],"yfov_deg":45}"#).unwrap_err();
        assert!(err.contains("missing field `eye`"), "{err}");
        let ok = CameraFile::parse(r#"{"eye":[0,0,5],"target":[0,0,0],"yfov_deg":45}"#).unwrap();
        assert_eq!(ok.up, Vec3::Y);
        assert!(CameraFile::parse(r#"{"eye":[0,0,5],"target":[0,0,5],"yfov_deg":45}"#).is_err());
        assert!(CameraFile::parse(r#"{"eye":[0,0,5],"target":[0,0,0],"yfov_deg":0}"#).is_err());
    }
}
