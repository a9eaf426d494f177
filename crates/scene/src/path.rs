//! Camera paths: cameras at keyframe times, played at a frame rate, as an application moves its
//! camera (docs/src/conventions.md, "Camera paths").
//!
//! The file: `{"fps": 30, "keyframes": [{"t": 0, "eye": [x,y,z], "target": [x,y,z], "yfov_deg":
//! 60}, …]}`, each keyframe a camera file's fields (`up` optional) with its time `t` in seconds;
//! `"cut": true` on a keyframe makes the camera jump to it (holding the previous keyframe's view
//! until then).
//! Between keyframes the eye and the target follow a Catmull-Rom spline through them (the path
//! passes through every keyframe, with no corner at one), the field of view and up are
//! interpolated linearly. Frame `i` is the camera at `t₀ + i / fps`; the path has
//! ⌊duration · fps⌋ + 1 frames.

use crate::camera::{Camera, CameraFile};
use crate::{Aabb, SceneError};
use glam::Vec3;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The most frames a path may hold (at 60 fps, about 28 minutes).
pub const MAX_FRAMES: u32 = 100_000;

/// A camera path: keyframes with increasing times, and a frame rate.
#[derive(Clone, Debug, PartialEq)]
pub struct CameraPath {
    /// Frames per second.
    pub fps: f32,
    keys: Vec<Keyframe>,
}

/// A keyframe: the camera at time `t` (seconds); `cut`: the camera jumps here from the previous
/// keyframe's view, which it holds until `t`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Keyframe {
    pub t: f32,
    pub camera: Camera,
    pub cut: bool,
}

impl From<(f32, Camera)> for Keyframe {
    /// The camera at `t`, reached smoothly.
    fn from((t, camera): (f32, Camera)) -> Self {
        Keyframe {
            t,
            camera,
            cut: false,
        }
    }
}

/// One keyframe of the file: its time and a camera file's fields.
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct KeyframeFile {
    pub t: f32,
    #[serde(flatten)]
    pub camera: CameraFile,
    /// The camera jumps to this keyframe.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub cut: bool,
}

/// The camera path file.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PathFile {
    pub fps: f32,
    pub keyframes: Vec<KeyframeFile>,
}

impl CameraPath {
    /// A path through `keys` (time in seconds, camera) at `fps` frames per second, checked:
    /// at least one keyframe, finite times that increase, cameras that form an image, a frame
    /// rate in (0, 1000] and at most [`MAX_FRAMES`] frames.
    pub fn new(
        fps: f32,
        keys: impl IntoIterator<Item = impl Into<Keyframe>>,
    ) -> Result<Self, String> {
        let keys: Vec<Keyframe> = keys.into_iter().map(Into::into).collect();
        if !(fps.is_finite() && fps > 0.0 && fps <= 1000.0) {
            return Err(format!("fps {fps}: must be a number in (0, 1000]"));
        }
        if keys.is_empty() {
            return Err("no keyframes".into());
        }
        for (i, k) in keys.iter().enumerate() {
            let t = k.t;
            if !t.is_finite() {
                return Err(format!("keyframe {i}: time {t} is not a finite number"));
            }
            if i > 0 && t <= keys[i - 1].t {
                return Err(format!(
                    "keyframe {i}: time {t} s does not come after the previous keyframe's {} s",
                    keys[i - 1].t
                ));
            }
            k.camera
                .validate()
                .map_err(|e| format!("keyframe {i}: {e}"))?;
        }
        let path = CameraPath { fps, keys };
        let frames = (path.duration() as f64 * fps as f64).floor() + 1.0;
        if frames > MAX_FRAMES as f64 {
            return Err(format!(
                "{frames} frames at {fps} fps: at most {MAX_FRAMES}"
            ));
        }
        Ok(path)
    }

    /// Reads and checks a camera path file.
    pub fn load(path: &Path) -> Result<Self, SceneError> {
        let bad = |msg: String| SceneError::PathFile {
            path: path.to_path_buf(),
            msg,
        };
        if crate::limits::check_regular_file(path)? > 16 << 20 {
            return Err(bad("larger than 16 MiB".into()));
        }
        let text = std::fs::read_to_string(path).map_err(|e| {
            if e.kind() == std::io::ErrorKind::NotFound {
                SceneError::Missing {
                    path: path.to_path_buf(),
                }
            } else {
                bad(e.to_string())
            }
        })?;
        Self::parse(&text).map_err(bad)
    }

    /// Parses and checks camera path JSON.
    pub fn parse(text: &str) -> Result<Self, String> {
        let f: PathFile = serde_json::from_str(text).map_err(|e| e.to_string())?;
        let keys: Vec<Keyframe> = f
            .keyframes
            .iter()
            .map(|k| {
                let c = k.camera;
                let camera = Camera {
                    eye: c.eye.into(),
                    target: c.target.into(),
                    up: c.up.into(),
                    yfov: c.yfov_deg.to_radians(),
                };
                Keyframe {
                    t: k.t,
                    camera,
                    cut: k.cut,
                }
            })
            .collect();
        Self::new(f.fps, keys)
    }

    /// The file of this path (what the viewer records).
    pub fn file(&self) -> PathFile {
        PathFile {
            fps: self.fps,
            keyframes: self
                .keys
                .iter()
                .map(|k| KeyframeFile {
                    t: k.t,
                    camera: CameraFile::from_camera(&k.camera),
                    cut: k.cut,
                })
                .collect(),
        }
    }

    /// Seconds from the first keyframe to the last.
    pub fn duration(&self) -> f32 {
        self.keys[self.keys.len() - 1].t - self.keys[0].t
    }

    /// Frames on the path: ⌊duration · fps⌋ + 1.
    pub fn frames(&self) -> u32 {
        (self.duration() as f64 * self.fps as f64).floor() as u32 + 1
    }

    /// The camera of frame `index` (clamped to the last keyframe after the path's end).
    pub fn camera(&self, index: u32) -> Camera {
        self.camera_at(self.keys[0].t + index as f32 / self.fps)
    }

    /// The camera at time `t` (seconds; clamped to the keyframes' span).
    pub fn camera_at(&self, t: f32) -> Camera {
        let k = &self.keys;
        let last = k.len() - 1;
        if t <= k[0].t || last == 0 {
            return k[0].camera;
        }
        if t >= k[last].t {
            return k[last].camera;
        }
        let i = k.partition_point(|key| key.t <= t) - 1;
        let (a, b) = (&k[i].camera, &k[i + 1].camera);
        if k[i + 1].cut {
            return *a;
        }
        let s = (t - k[i].t) / (k[i + 1].t - k[i].t);
        // A missing neighbour (at either end, or across a cut) is the next keyframe mirrored (a
        // straight start).
        let spline = |p: fn(&Camera) -> Vec3| {
            let before = if i == 0 || k[i].cut {
                2.0 * p(a) - p(b)
            } else {
                p(&k[i - 1].camera)
            };
            let after = if i + 1 == last || k[i + 2].cut {
                2.0 * p(b) - p(a)
            } else {
                p(&k[i + 2].camera)
            };
            catmull_rom(before, p(a), p(b), after, s)
        };
        Camera {
            eye: spline(|c| c.eye),
            target: spline(|c| c.target),
            up: a.up.lerp(b.up, s).normalize_or(Vec3::Y),
            yfov: a.yfov + (b.yfov - a.yfov) * s,
        }
    }

    /// A camera standing at `camera` for `seconds` at `fps` (how `compare` plays a moving
    /// scene's animation without a path).
    pub fn standing(camera: Camera, seconds: f32, fps: f32) -> Result<Self, String> {
        Self::new(fps, vec![(0.0, camera), (seconds.max(1.0 / fps), camera)])
    }

    /// `frames` frames at `fps` turning `degrees` per frame about the target from `start`
    /// (what `--orbit DEG` means), one keyframe per frame.
    pub fn orbit(start: Camera, degrees: f32, frames: u32, fps: f32) -> Result<Self, String> {
        let keys: Vec<(f32, Camera)> = (0..frames.max(1))
            .map(|i| (i as f32 / fps, start.orbit(degrees * i as f32)))
            .collect();
        Self::new(fps, keys)
    }

    /// The walk of a scene seen from `start` (`--walk`): four seconds at `fps` in which the eye
    /// steps forward a third of the way to the target and sways sideways by a tenth of that
    /// distance and back, while the gaze turns by about 10° and back: a walk past the scene, no
    /// cut, each frame's disocclusions small. `bounds` keeps the eye inside the scene's box
    /// grown by the distance, or by as much as the start lies outside it: a camera outside the
    /// scene walks from where it stands, never out beyond it nor thrown into the box.
    pub fn walk(start: Camera, bounds: Aabb, fps: f32) -> Result<Self, String> {
        let to_target = start.target - start.eye;
        let distance = to_target.length();
        let forward = to_target / distance.max(1e-6);
        let side = forward.cross(start.up).normalize_or(Vec3::X);
        let key = |t: f32, ahead: f32, sway: f32, turn: f32| {
            let eye = start.eye + forward * (ahead * distance) + side * (sway * distance);
            let eye = if bounds.is_empty() {
                eye
            } else {
                let lo = (bounds.min - distance).min(start.eye);
                let hi = (bounds.max + distance).max(start.eye);
                eye.clamp(lo, hi)
            };
            let target = start.target + side * (turn * distance);
            Keyframe::from((
                t,
                Camera {
                    eye,
                    target,
                    ..start
                },
            ))
        };
        Self::new(
            fps,
            vec![
                key(0.0, 0.0, 0.0, 0.0),
                key(1.0, 0.08, 0.05, 0.09),
                key(2.0, 0.17, 0.1, 0.18),
                key(3.0, 0.25, 0.05, 0.09),
                key(4.0, 0.33, 0.0, 0.0),
            ],
        )
    }
}

/// The uniform Catmull-Rom spline through `p1` (s = 0) and `p2` (s = 1), with `p0` and `p3` the
/// neighbouring keyframes.
fn catmull_rom(p0: Vec3, p1: Vec3, p2: Vec3, p3: Vec3, s: f32) -> Vec3 {
    let (s2, s3) = (s * s, s * s * s);
    0.5 * ((2.0 * p1)
        + (p2 - p0) * s
        + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * s2
        + (3.0 * p1 - p0 - 3.0 * p2 + p3) * s3)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cam(x: f32) -> Camera {
        Camera::new(Vec3::new(x, 1.0, 4.0), Vec3::new(0.0, 1.0, 0.0), 45.0)
    }

    #[test]
    fn the_path_passes_through_its_keyframes_and_counts_its_frames() {
        let p = CameraPath::new(
            30.0,
            vec![(0.0, cam(0.0)), (1.0, cam(1.0)), (3.0, cam(2.0))],
        )
        .unwrap();
        assert_eq!(p.frames(), 91);
        for (t, c) in [(0.0, cam(0.0)), (1.0, cam(1.0)), (3.0, cam(2.0))] {
            assert!((p.camera_at(t).eye - c.eye).length() < 1e-5, "t = {t}");
        }
        // Frame 30 is the keyframe at 1 s; the last frame is the last keyframe.
        assert!((p.camera(30).eye - cam(1.0).eye).length() < 1e-5);
        assert!((p.camera(90).eye - cam(2.0).eye).length() < 1e-5);
        // Equally spaced collinear keyframes are crossed at constant speed.
        let line = CameraPath::new(10.0, (0..4).map(|i| (i as f32, cam(i as f32)))).unwrap();
        for i in 0..=30 {
            let x = line.camera(i).eye.x;
            assert!((x - i as f32 / 10.0).abs() < 1e-4, "frame {i}: x {x}");
        }
    }

    #[test]
    fn orbit_and_walk_are_paths_without_cuts() {
        let start = cam(0.0);
        let o = CameraPath::orbit(start, 2.0, 120, 30.0).unwrap();
        assert_eq!(o.frames(), 120);
        assert!((o.camera(45).eye - start.orbit(90.0).eye).length() < 1e-4);
        let bounds = Aabb {
            min: Vec3::splat(-1.0),
            max: Vec3::splat(1.0),
        };
        let w = CameraPath::walk(start, bounds, 30.0).unwrap();
        assert_eq!(w.frames(), 121);
        for i in 1..w.frames() {
            assert!(!w.camera(i - 1).is_cut_to(&w.camera(i)), "frame {i}");
        }
        let end = w.camera(120);
        assert!(
            (end.eye - start.eye).length() > 1.0,
            "the walk moves: {}",
            end.eye
        );
    }

    /// A camera outside the scene's box by more than its target distance (a glTF camera's
    /// target is 1 m ahead) walks from where it stands: it is not thrown into the box, where
    /// it would face away from the scene.
    #[test]
    fn a_walk_from_outside_the_scene_starts_where_the_camera_stands() {
        let start = Camera::new(Vec3::new(0.0, 1.0, 3.9), Vec3::new(0.0, 1.0, 2.9), 38.0);
        let bounds = Aabb {
            min: Vec3::new(-1.0, 0.0, -1.0),
            max: Vec3::new(1.0, 2.0, 1.0),
        };
        let w = CameraPath::walk(start, bounds, 30.0).unwrap();
        assert_eq!(w.camera(0).eye, start.eye);
        for i in 0..w.frames() {
            let c = w.camera(i);
            assert!(c.eye.z <= start.eye.z + 1e-5, "frame {i}: {}", c.eye);
            assert!(
                c.forward().z < -0.9,
                "frame {i} looks away: {}",
                c.forward()
            );
        }
        assert!((w.camera(120).eye.z - (start.eye.z - 0.33)).abs() < 1e-3);
    }

    #[test]
    fn bad_paths_are_refused_with_one_line() {
        let key = r#"{"t": 0, "eye": [0, 1, 4], "target": [0, 1, 0], "yfov_deg": 45}"#;
        let later = r#"{"t": 1, "eye": [1, 1, 4], "target": [0, 1, 0], "yfov_deg": 45}"#;
        assert!(
            CameraPath::parse(&format!(r#"{{"fps": 30, "keyframes": [{key}, {later}]}}"#)).is_ok()
        );
        for (text, want) in [
            (r#"{"fps": 30, "keyframes": []}"#.to_string(), "no keyframes"),
            (
                format!(r#"{{"fps": 30, "keyframes": [{later}, {key}]}}"#),
                "does not come after",
            ),
            (
                format!(r#"{{"fps": 0, "keyframes": [{key}]}}"#),
                "fps 0",
            ),
            (
                r#"{"fps": 30, "keyframes": [{"t": 0, "eye": [0, 1, 4], "target": [0, 1, 4], "yfov_deg": 45}]}"#.into(),
                "coincide",
            ),
            ("not json".into(), "expected"),
            (format!(r#"{{"fps": 30, "keyframes": [{key}], "speed": 2}}"#), "unknown field"),
            (
                format!(r#"{{"fps": 1000, "keyframes": [{key}, {{"t": 1e6, "eye": [1, 1, 4], "target": [0, 1, 0], "yfov_deg": 45}}]}}"#),
                "at most",
            ),
        ] {
            let e = CameraPath::parse(&text).unwrap_err();
            assert!(e.contains(want), "{text}: {e}");
            assert!(!e.contains('\n'), "{e}");
        }
        // NaN is not JSON; a time that overflows to infinity is refused as not finite.
        let inf = r#"{"fps": 30, "keyframes": [{"t": 1e39, "eye": [0, 1, 4], "target": [0, 1, 0], "yfov_deg": 45}]}"#;
        assert!(CameraPath::parse(inf).is_err());
    }

    #[test]
    fn a_cut_holds_the_view_then_jumps() {
        let text = r#"{"fps": 10, "keyframes": [
            {"t": 0, "eye": [0, 1, 4], "target": [0, 1, 0], "yfov_deg": 45},
            {"t": 1, "eye": [0, 1, 4], "target": [0, 1, 0], "yfov_deg": 45},
            {"t": 2, "eye": [4, 1, 0], "target": [0, 1, 0], "yfov_deg": 45, "cut": true},
            {"t": 3, "eye": [4, 1, 0], "target": [0, 1, 0], "yfov_deg": 45}]}"#;
        let p = CameraPath::parse(text).unwrap();
        // Still, with no overshoot, until the jump at frame 20; still after it.
        for i in 0..20 {
            assert_eq!(p.camera(i).eye, Vec3::new(0.0, 1.0, 4.0), "frame {i}");
        }
        for i in 20..=30 {
            assert!(
                (p.camera(i).eye - Vec3::new(4.0, 1.0, 0.0)).length() < 1e-5,
                "frame {i}"
            );
        }
        assert!(p.camera(19).is_cut_to(&p.camera(20)));
        let back = CameraPath::parse(&serde_json::to_string(&p.file()).unwrap()).unwrap();
        assert_eq!(back, p);
    }

    #[test]
    fn a_path_file_round_trips() {
        let p = CameraPath::new(24.0, vec![(0.5, cam(0.0)), (2.0, cam(3.0))]).unwrap();
        let text = serde_json::to_string(&p.file()).unwrap();
        let q = CameraPath::parse(&text).unwrap();
        assert_eq!(q.frames(), p.frames());
        assert!((q.camera(10).eye - p.camera(10).eye).length() < 1e-5);
    }
}
