//! Objects that move: glTF node animation (translation, rotation and scale channels) and the
//! built-in moving variants, played on the scene's clock (seconds from the first frame).
//!
//! A moving mesh keeps its rest pose (the node transforms without animation, what a loader
//! flattens to world space) and is posed at time `t` by the node's world transform at `t` times
//! the inverse of its world transform at rest. A moving object is dynamic: the far field's bake
//! never holds it (the book, "In motion").

use crate::{Mesh, Scene};
use glam::{Mat4, Quat, Vec3};

/// How a track interpolates between its keys (glTF's sampler interpolation).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interpolation {
    Step,
    Linear,
    /// Cubic Hermite with a tangent in and out per key (values hold `[in, value, out]`).
    CubicSpline,
}

/// Keyed values of one channel. Before the first key the first value holds, after the last the
/// last (glTF's clamping).
#[derive(Clone, Debug, PartialEq)]
pub struct Track<T> {
    /// Key times (s), strictly increasing, finite and ≥ 0.
    pub times: Vec<f32>,
    /// One value per key; three (`in`, `value`, `out`) per key for [`Interpolation::CubicSpline`].
    pub values: Vec<T>,
    pub interpolation: Interpolation,
}

/// What a track's values can be.
pub trait Keyed: Copy {
    fn mix(a: Self, b: Self, s: f32) -> Self;
    fn hermite(v0: Self, out0: Self, v1: Self, in1: Self, dt: f32, s: f32) -> Self;
    fn finite(&self) -> bool;
}

impl Keyed for Vec3 {
    fn mix(a: Self, b: Self, s: f32) -> Self {
        a.lerp(b, s)
    }
    fn hermite(v0: Self, out0: Self, v1: Self, in1: Self, dt: f32, s: f32) -> Self {
        let (s2, s3) = (s * s, s * s * s);
        (2.0 * s3 - 3.0 * s2 + 1.0) * v0
            + (s3 - 2.0 * s2 + s) * dt * out0
            + (-2.0 * s3 + 3.0 * s2) * v1
            + (s3 - s2) * dt * in1
    }
    fn finite(&self) -> bool {
        self.is_finite()
    }
}

impl Keyed for Quat {
    fn mix(a: Self, b: Self, s: f32) -> Self {
        a.normalize().slerp(b.normalize(), s)
    }
    fn hermite(v0: Self, out0: Self, v1: Self, in1: Self, dt: f32, s: f32) -> Self {
        let v = Vec3::hermite;
        let xyz = v(v0.xyz(), out0.xyz(), v1.xyz(), in1.xyz(), dt, s);
        let (s2, s3) = (s * s, s * s * s);
        let w = (2.0 * s3 - 3.0 * s2 + 1.0) * v0.w
            + (s3 - 2.0 * s2 + s) * dt * out0.w
            + (-2.0 * s3 + 3.0 * s2) * v1.w
            + (s3 - s2) * dt * in1.w;
        Quat::from_xyzw(xyz.x, xyz.y, xyz.z, w).normalize()
    }
    fn finite(&self) -> bool {
        self.is_finite() && self.length_squared() > 1e-12
    }
}

impl<T: Keyed> Track<T> {
    /// A linear track through `keys` (time, value).
    pub fn linear(keys: &[(f32, T)]) -> Self {
        Track {
            times: keys.iter().map(|k| k.0).collect(),
            values: keys.iter().map(|k| k.1).collect(),
            interpolation: Interpolation::Linear,
        }
    }

    /// Why the track cannot be played, if it cannot: no keys, times not finite, negative or not
    /// increasing, a value count that does not match, a value not finite.
    pub fn check(&self) -> Result<(), String> {
        if self.times.is_empty() {
            return Err("no keyframes".into());
        }
        if let Some(t) = self.times.iter().find(|t| !(t.is_finite() && **t >= 0.0)) {
            return Err(format!("key time {t} is not a finite time ≥ 0"));
        }
        if let Some(w) = self.times.windows(2).find(|w| w[1] <= w[0]) {
            return Err(format!(
                "key times are not increasing ({} then {})",
                w[0], w[1]
            ));
        }
        let per_key = if self.interpolation == Interpolation::CubicSpline {
            3
        } else {
            1
        };
        if self.values.len() != per_key * self.times.len() {
            return Err(format!(
                "{} key times but {} values",
                self.times.len(),
                self.values.len()
            ));
        }
        if !self.values.iter().all(Keyed::finite) {
            return Err("a key value is not finite".into());
        }
        Ok(())
    }

    /// The value at time `t` (s).
    pub fn sample(&self, t: f32) -> T {
        let cubic = self.interpolation == Interpolation::CubicSpline;
        let value = |k: usize| {
            if cubic {
                self.values[3 * k + 1]
            } else {
                self.values[k]
            }
        };
        let n = self.times.len();
        if t <= self.times[0] || n == 1 {
            return value(0);
        }
        if t >= self.times[n - 1] {
            return value(n - 1);
        }
        let k = self.times.partition_point(|&x| x <= t) - 1;
        let (t0, t1) = (self.times[k], self.times[k + 1]);
        let s = (t - t0) / (t1 - t0);
        match self.interpolation {
            Interpolation::Step => value(k),
            Interpolation::Linear => T::mix(value(k), value(k + 1), s),
            Interpolation::CubicSpline => T::hermite(
                value(k),
                self.values[3 * k + 2],
                value(k + 1),
                self.values[3 * (k + 1)],
                t1 - t0,
                s,
            ),
        }
    }

    fn end(&self) -> f32 {
        self.times.last().copied().unwrap_or(0.0)
    }
}

/// A node of the animated hierarchy: its parent, its rest transform and its channels.
#[derive(Clone, Debug, PartialEq)]
pub struct Node {
    pub name: String,
    /// Index into [`Animation::nodes`].
    pub parent: Option<u32>,
    pub translation: Vec3,
    pub rotation: Quat,
    pub scale: Vec3,
    pub translations: Option<Track<Vec3>>,
    pub rotations: Option<Track<Quat>>,
    pub scales: Option<Track<Vec3>>,
}

impl Node {
    /// A root node at rest at `translation`, with no channels yet.
    pub fn at(name: &str, translation: Vec3) -> Self {
        Node {
            name: name.into(),
            parent: None,
            translation,
            rotation: Quat::IDENTITY,
            scale: Vec3::ONE,
            translations: None,
            rotations: None,
            scales: None,
        }
    }

    /// Its transform relative to its parent at time `t` (`None`: at rest).
    fn local(&self, t: Option<f32>) -> Mat4 {
        Mat4::from_scale_rotation_translation(
            play(&self.scales, self.scale, t),
            play(&self.rotations, self.rotation, t),
            play(&self.translations, self.translation, t),
        )
    }

    fn animated(&self) -> bool {
        self.translations.is_some() || self.rotations.is_some() || self.scales.is_some()
    }
}

/// A channel's value at `t`, or the rest value without the channel or at rest (`t` = `None`).
fn play<T: Keyed>(track: &Option<Track<T>>, rest: T, t: Option<f32>) -> T {
    match (track, t) {
        (Some(track), Some(t)) => track.sample(t),
        _ => rest,
    }
}

/// Frames per second of the clock that plays a moving scene in a loop where no rate is given
/// (the viewer, `bench`): frame-locked, so that a run replays alike.
pub const LOOP_FPS: f32 = 30.0;

/// The animated node hierarchy of a scene (empty: nothing moves).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Animation {
    pub nodes: Vec<Node>,
}

impl Animation {
    pub fn is_empty(&self) -> bool {
        !self.nodes.iter().any(Node::animated)
    }

    /// The time of frame `frame` of a clock at `fps` that plays the animation in a loop (what the
    /// viewer and `bench` show; 0 when nothing moves).
    pub fn looped(&self, frame: u32, fps: f32) -> f32 {
        let period = self.duration();
        if period > 0.0 {
            (frame as f32 / fps) % period
        } else {
            0.0
        }
    }

    /// When the last key of any channel is played (s); 0 when nothing moves.
    pub fn duration(&self) -> f32 {
        let ends = self.nodes.iter().flat_map(|n| {
            [
                n.translations.as_ref().map(Track::end),
                n.rotations.as_ref().map(Track::end),
                n.scales.as_ref().map(Track::end),
            ]
        });
        ends.flatten().fold(0.0, f32::max)
    }

    /// The world transform of `node` at time `t` (`None`: at rest).
    pub fn world(&self, node: u32, t: Option<f32>) -> Mat4 {
        let mut m = Mat4::IDENTITY;
        let mut at = Some(node);
        let mut depth = 0;
        while let Some(n) = at
            .filter(|_| depth <= self.nodes.len())
            .and_then(|i| self.nodes.get(i as usize))
        {
            m = n.local(t) * m;
            at = n.parent;
            depth += 1;
        }
        m
    }

    /// How `node` is moved at time `t` from its rest pose (world from rest).
    pub fn motion_at(&self, node: u32, t: f32) -> Mat4 {
        self.world(node, Some(t)) * self.world(node, None).inverse()
    }

    /// Whether `node` or one of its ancestors has a channel.
    pub fn moves(&self, node: u32) -> bool {
        let mut at = Some(node);
        let mut depth = 0;
        while let Some(n) = at
            .filter(|_| depth <= self.nodes.len())
            .and_then(|i| self.nodes.get(i as usize))
        {
            if n.animated() {
                return true;
            }
            at = n.parent;
            depth += 1;
        }
        false
    }

    /// Whether any node's world transform at `t1` differs from that at `t0`.
    pub fn moved_between(&self, t0: f32, t1: f32) -> bool {
        (0..self.nodes.len() as u32).any(|n| self.world(n, Some(t0)) != self.world(n, Some(t1)))
    }

    /// Why the animation cannot be played, naming the node and channel: a parent out of range
    /// or a track [`Track::check`] refuses.
    pub fn check(&self) -> Result<(), String> {
        for n in &self.nodes {
            if n.parent.is_some_and(|p| p as usize >= self.nodes.len()) {
                return Err(format!("{}: its parent is out of range", n.name));
            }
            let checks = [
                ("translation", n.translations.as_ref().map(Track::check)),
                ("rotation", n.rotations.as_ref().map(Track::check)),
                ("scale", n.scales.as_ref().map(Track::check)),
            ];
            for (path, check) in checks {
                if let Some(Err(e)) = check {
                    return Err(format!("{}, {path} channel: {e}", n.name));
                }
            }
        }
        Ok(())
    }
}

/// How a mesh moves: the animated node it hangs from and its rest pose in world space.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshMotion {
    /// Index into [`Animation::nodes`].
    pub node: u32,
    pub rest_positions: Vec<glam::Vec3>,
    pub rest_normals: Vec<glam::Vec3>,
}

impl MeshMotion {
    /// Positions and normals at rest moved by `world` (world from rest).
    pub fn posed(&self, world: Mat4) -> (Vec<Vec3>, Vec<Vec3>) {
        let normal = world.inverse().transpose();
        let positions = self
            .rest_positions
            .iter()
            .map(|p| world.transform_point3(*p))
            .collect();
        let normals = self
            .rest_normals
            .iter()
            .map(|n| normal.transform_vector3(*n).try_normalize().unwrap_or(*n))
            .collect();
        (positions, normals)
    }
}

impl Mesh {
    /// Makes this mesh follow `node` from its current pose, taken as the rest pose; it becomes
    /// dynamic (the far field's bake never holds a moving object).
    pub fn follow(&mut self, node: u32) {
        self.motion = Some(MeshMotion {
            node,
            rest_positions: self.positions.clone(),
            rest_normals: self.normals.clone(),
        });
        self.dynamic = true;
    }
}

impl Scene {
    /// The bounds of the scene over its whole animation (sampled 64 times over its duration).
    pub fn bounds_in_motion(&self) -> crate::Aabb {
        let mut b = self.bounds();
        if !self.moves() {
            return b;
        }
        let end = self.animation.duration();
        for k in 0..=64 {
            let t = end * k as f32 / 64.0;
            for m in &self.meshes {
                if let Some(mm) = &m.motion {
                    let world = self.motion_at(mm.node, t);
                    for p in &mm.rest_positions {
                        b.grow(world.transform_point3(*p));
                    }
                }
            }
        }
        b
    }

    /// Whether anything in the scene moves.
    pub fn moves(&self) -> bool {
        !self.animation.is_empty() && self.meshes.iter().any(|m| m.motion.is_some())
    }

    /// How `node` is moved at time `t` from its rest pose (world from rest).
    pub fn motion_at(&self, node: u32, t: f32) -> Mat4 {
        self.animation.motion_at(node, t)
    }

    /// Poses every moving mesh at time `t` (s), from its rest pose: the same `t` gives the same
    /// positions to the bit whatever was posed before.
    pub fn pose(&mut self, t: f32) {
        let moves: Vec<Option<Mat4>> = self
            .meshes
            .iter()
            .map(|m| m.motion.as_ref().map(|mm| self.motion_at(mm.node, t)))
            .collect();
        for (m, world) in self.meshes.iter_mut().zip(moves) {
            if let (Some(world), Some(mm)) = (world, m.motion.as_ref()) {
                (m.positions, m.normals) = mm.posed(world);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tracks_interpolate_and_clamp_as_gltf_says() {
        let t = Track::linear(&[(1.0, Vec3::ZERO), (3.0, Vec3::new(2.0, 0.0, 0.0))]);
        t.check().unwrap();
        assert_eq!(t.sample(0.0), Vec3::ZERO);
        assert_eq!(t.sample(2.0), Vec3::new(1.0, 0.0, 0.0));
        assert_eq!(t.sample(9.0), Vec3::new(2.0, 0.0, 0.0));
        let step = Track {
            interpolation: Interpolation::Step,
            ..t.clone()
        };
        assert_eq!(step.sample(2.9), Vec3::ZERO);
        // Cubic with zero tangents: smoothstep between the values.
        let cubic = Track {
            times: vec![0.0, 1.0],
            values: vec![
                Vec3::ZERO,
                Vec3::ZERO,
                Vec3::ZERO,
                Vec3::ZERO,
                Vec3::X,
                Vec3::ZERO,
            ],
            interpolation: Interpolation::CubicSpline,
        };
        cubic.check().unwrap();
        assert!((cubic.sample(0.25).x - 0.15625).abs() < 1e-6);
        let q = Track::linear(&[(0.0, Quat::IDENTITY), (1.0, Quat::from_rotation_y(1.0))]);
        assert!(q.sample(0.5).angle_between(Quat::from_rotation_y(0.5)) < 1e-5);
    }

    #[test]
    fn broken_tracks_are_refused() {
        let ok = Track::linear(&[(0.0, Vec3::ZERO), (1.0, Vec3::X)]);
        let cases = [
            (
                Track {
                    times: vec![],
                    values: vec![],
                    ..ok.clone()
                },
                "no keyframes",
            ),
            (
                Track {
                    times: vec![1.0, 0.5],
                    ..ok.clone()
                },
                "not increasing",
            ),
            (
                Track {
                    times: vec![0.0, f32::NAN],
                    ..ok.clone()
                },
                "not a finite",
            ),
            (
                Track {
                    values: vec![Vec3::ZERO],
                    ..ok.clone()
                },
                "values",
            ),
            (
                Track {
                    values: vec![Vec3::ZERO, Vec3::NAN],
                    ..ok.clone()
                },
                "not finite",
            ),
        ];
        for (track, what) in cases {
            let e = track.check().unwrap_err();
            assert!(e.contains(what), "{e}");
        }
    }

    #[test]
    fn a_posed_mesh_follows_its_node_and_its_parent_from_rest() {
        let mut parent = Node::at("parent", Vec3::new(0.0, 1.0, 0.0));
        parent.rotations = Some(Track::linear(&[
            (0.0, Quat::IDENTITY),
            (1.0, Quat::from_rotation_y(std::f32::consts::FRAC_PI_2)),
        ]));
        let mut child = Node::at("child", Vec3::new(1.0, 0.0, 0.0));
        child.parent = Some(0);
        let mut s = crate::builtin::scene("plane").unwrap();
        s.animation = Animation {
            nodes: vec![parent, child],
        };
        // A mesh at the child's rest place (1, 1, 0).
        s.meshes[0].positions = vec![Vec3::new(1.0, 1.0, 0.0); s.meshes[0].positions.len()];
        s.meshes[0].follow(1);
        assert!(s.moves() && s.meshes[0].dynamic);
        s.pose(1.0);
        // A quarter turn about +Y of the parent carries (1, 0, 0) to (0, 0, −1).
        assert!((s.meshes[0].positions[0] - Vec3::new(0.0, 1.0, -1.0)).length() < 1e-5);
        s.pose(0.0);
        assert_eq!(s.meshes[0].positions[0], Vec3::new(1.0, 1.0, 0.0));
        assert_eq!(s.animation.duration(), 1.0);
    }
}
