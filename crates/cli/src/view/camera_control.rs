//! Camera moves of the viewer: orbit about the target, pan, zoom (dolly), fly (WASD + mouse
//! look) and framing the scene. Pure functions on [`Camera`]; the window maps input to them.

use glam::{Quat, Vec3};
use nearfield_scene::Camera;

/// Radians of turn per pixel of mouse drag.
pub const TURN_PER_PIXEL: f32 = 0.006;

/// Turns the eye about the target: `dx` about the up axis, `dy` about the camera's right axis
/// (pixels of drag; dragging down raises the eye). The pitch stops 1° short of the poles so the
/// view never flips.
pub fn orbit(c: &Camera, dx: f32, dy: f32) -> Camera {
    let up = c.up.normalize();
    let offset = c.eye - c.target;
    let yaw = Quat::from_axis_angle(up, -dx * TURN_PER_PIXEL);
    let offset = yaw * offset;
    let right = offset.cross(up).normalize_or_zero();
    let elevation = (offset.normalize().dot(up)).clamp(-1.0, 1.0).asin();
    let limit = 89f32.to_radians();
    let pitch = (elevation + dy * TURN_PER_PIXEL).clamp(-limit, limit) - elevation;
    let offset = if right == Vec3::ZERO {
        offset
    } else {
        Quat::from_axis_angle(right, pitch) * offset
    };
    Camera {
        eye: c.target + offset,
        ..*c
    }
}

/// Moves eye and target together in the view plane by `dx`, `dy` pixels of an image `height`
/// pixels tall (the point under the cursor at the target's depth follows the cursor).
pub fn pan(c: &Camera, dx: f32, dy: f32, height: f32) -> Camera {
    let forward = c.forward();
    let right = forward.cross(c.up).normalize_or_zero();
    let up = right.cross(forward);
    let distance = (c.target - c.eye).length();
    let metres_per_pixel = 2.0 * distance * (0.5 * c.yfov).tan() / height.max(1.0);
    let shift = (-dx * right + dy * up) * metres_per_pixel;
    Camera {
        eye: c.eye + shift,
        target: c.target + shift,
        ..*c
    }
}

/// Dollies towards the target: each unit of `steps` (one wheel notch) covers 10 % of the
/// distance; the eye never reaches the target.
pub fn zoom(c: &Camera, steps: f32) -> Camera {
    let offset = c.eye - c.target;
    let factor = 0.9f32.powf(steps).clamp(0.01, 100.0);
    let new = offset * factor;
    let new = if new.length() < 1e-4 {
        offset.normalize() * 1e-4
    } else {
        new
    };
    Camera {
        eye: c.target + new,
        ..*c
    }
}

/// Fly mode: `look` (pixels of drag) turns the view about the eye; `mv` moves along
/// (right, up, forward) by `speed` × `dt` metres. The target stays at the same distance in front.
pub fn fly(c: &Camera, look: (f32, f32), mv: Vec3, speed: f32, dt: f32) -> Camera {
    let up = c.up.normalize();
    let distance = (c.target - c.eye).length().max(1e-3);
    let mut forward = c.forward();
    forward = Quat::from_axis_angle(up, -look.0 * TURN_PER_PIXEL) * forward;
    let right = forward.cross(up).normalize_or_zero();
    let elevation = forward.dot(up).clamp(-1.0, 1.0).asin();
    let limit = 89f32.to_radians();
    let pitch = (elevation - look.1 * TURN_PER_PIXEL).clamp(-limit, limit) - elevation;
    if right != Vec3::ZERO {
        forward = Quat::from_axis_angle(right, pitch) * forward;
    }
    let right = forward.cross(up).normalize_or_zero();
    let eye = c.eye + (mv.x * right + mv.y * up + mv.z * forward) * speed * dt;
    Camera {
        eye,
        target: eye + forward * distance,
        ..*c
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cam() -> Camera {
        Camera::new(Vec3::new(0.0, 1.0, 4.0), Vec3::new(0.0, 1.0, 0.0), 45.0)
    }

    #[test]
    fn orbit_keeps_the_distance_and_stops_before_the_pole() {
        let c = cam();
        let o = orbit(&c, 100.0, 0.0);
        assert!(((o.eye - o.target).length() - 4.0).abs() < 1e-4);
        assert!((o.eye.y - 1.0).abs() < 1e-4, "yaw keeps the height");
        let top = orbit(&c, 0.0, 10_000.0);
        let elevation = (top.eye - top.target).normalize().y.asin().to_degrees();
        assert!((elevation - 89.0).abs() < 1e-2, "{elevation}");
        assert!(top.validate().is_ok());
    }

    #[test]
    fn pan_moves_eye_and_target_together_by_the_pixel_footprint() {
        let c = cam();
        let p = pan(&c, 100.0, 0.0, 720.0);
        let footprint = 2.0 * 4.0 * (22.5f32.to_radians()).tan() / 720.0;
        assert!(((p.eye - c.eye).length() - 100.0 * footprint).abs() < 1e-4);
        assert!((p.eye - c.eye - (p.target - c.target)).length() < 1e-6);
        // Dragging right moves the camera left (the scene follows the cursor).
        assert!(p.eye.x < 0.0);
    }

    #[test]
    fn zoom_covers_ten_percent_per_notch_and_never_reaches_the_target() {
        let z = zoom(&cam(), 1.0);
        assert!(((z.eye - z.target).length() - 3.6).abs() < 1e-4);
        let z = zoom(&cam(), 1e6);
        assert!((z.eye - z.target).length() > 0.0);
        assert!(z.validate().is_ok());
    }

    #[test]
    fn fly_moves_forward_and_keeps_the_target_ahead() {
        let c = cam();
        let f = fly(&c, (0.0, 0.0), Vec3::Z, 2.0, 0.5);
        assert!(
            (f.eye - Vec3::new(0.0, 1.0, 3.0)).length() < 1e-5,
            "{}",
            f.eye
        );
        assert!((f.forward() - c.forward()).length() < 1e-5);
        let turned = fly(&c, (50.0, 0.0), Vec3::ZERO, 1.0, 0.0);
        assert_eq!(turned.eye, c.eye);
        assert!(turned.forward().dot(c.forward()) < 0.99);
    }
}
