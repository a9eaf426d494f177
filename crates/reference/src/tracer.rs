//! Ray casting against the scene: a compressed wide BVH (obvhs CWBVH) over every triangle, closest
//! hit with the G-buffer's culling rules for primary rays, and occlusion queries.
//!
//! Rules shared with the rasterizer (gbuffer.wgsl):
//! - primary rays skip back faces of single-sided materials (the rasterizer culls them);
//! - alpha-masked materials are transparent where base alpha < cutoff, for every ray;
//! - the shading normal is the barycentric interpolation of the vertex normals, flipped with the
//!   geometric normal on back faces (double-sided materials). Shading normals that face away
//!   from the viewer on a front face are kept as they are, like the G-buffer does.
//!
//! The BVH works in a uniformly scaled copy of the scene whose bounding radius is 1e5: obvhs
//! skips box hits closer than 1e-4 (its absolute traversal epsilon), which in world units would
//! hide geometry within 0.1 mm of a ray's origin (contact occlusion, seams). Scaled, that blind
//! zone is 1e-9 of the scene's size, far below the origin offsets.
//!
//! Secondary rays start at `offset_origin`: the hit point moved along the geometric normal to the
//! side the ray leaves on, and towards the camera, by a scale-aware epsilon. A pixel centre on a
//! floor/wall seam then starts in front of both planes and cannot leak under either.

use glam::{Vec2, Vec3, Vec3A};
use nearfield_scene::{AlphaMode, Scene};
use obvhs::{
    BvhBuildParams,
    cwbvh::{CwBvh, builder::build_cwbvh_from_tris},
    ray::{Ray, RayHit},
    triangle::Triangle,
};
use std::time::Duration;

/// Which triangle a BVH primitive is.
#[derive(Clone, Copy, Debug)]
struct TriRef {
    mesh: u32,
    tri: u32,
}

/// A ray–surface intersection.
#[derive(Clone, Copy, Debug)]
pub struct Hit {
    pub t: f32,
    pub p: Vec3,
    /// Unit geometric normal facing the ray's origin side.
    pub ng: Vec3,
    /// Unit shading normal, flipped like `ng` on back faces.
    pub ns: Vec3,
    pub uv: Vec2,
    pub material: u32,
    /// The ray hit the triangle's front (counter-clockwise) side.
    pub front: bool,
}

pub struct Tracer<'s> {
    pub scene: &'s Scene,
    bvh: CwBvh,
    /// Triangles in BVH primitive order.
    tris: Vec<Triangle>,
    refs: Vec<TriRef>,
    /// Per primitive: material is alpha-masked.
    masked: Vec<bool>,
    /// Per primitive: material is single-sided (culled for primary rays).
    single_sided: Vec<bool>,
    /// BVH space = world × scale.
    scale: f32,
}

/// Bounding radius of the BVH's scaled copy of the scene.
const BVH_RADIUS: f32 = 1e5;

impl<'s> Tracer<'s> {
    pub fn new(scene: &'s Scene) -> Self {
        let bounds = scene.bounds();
        let scale = if bounds.is_empty() {
            1.0
        } else {
            BVH_RADIUS
                / bounds
                    .min
                    .abs()
                    .max(bounds.max.abs())
                    .max_element()
                    .max(1e-6)
        };
        let mut tris = Vec::with_capacity(scene.triangle_count());
        let mut refs = Vec::with_capacity(scene.triangle_count());
        for (mi, m) in scene.meshes.iter().enumerate() {
            for (ti, t) in m.indices.iter().enumerate() {
                let [a, b, c] = t.map(|i| Vec3A::from(m.positions[i as usize] * scale));
                tris.push(Triangle {
                    v0: a,
                    v1: b,
                    v2: c,
                });
                refs.push(TriRef {
                    mesh: mi as u32,
                    tri: ti as u32,
                });
            }
        }
        let bvh = build_cwbvh_from_tris(
            &tris,
            BvhBuildParams::medium_build(),
            &mut Duration::default(),
        );
        // Lay the triangles out in the BVH's primitive order so that traversal indexes directly.
        let tris: Vec<Triangle> = bvh
            .primitive_indices
            .iter()
            .map(|&i| tris[i as usize])
            .collect();
        let refs: Vec<TriRef> = bvh
            .primitive_indices
            .iter()
            .map(|&i| refs[i as usize])
            .collect();
        let material =
            |r: &TriRef| &scene.materials[scene.meshes[r.mesh as usize].material as usize];
        let masked = refs
            .iter()
            .map(|r| matches!(material(r).alpha_mode, AlphaMode::Mask { .. }))
            .collect();
        let single_sided = refs.iter().map(|r| !material(r).double_sided).collect();
        Tracer {
            scene,
            bvh,
            tris,
            refs,
            masked,
            single_sided,
            scale,
        }
    }

    /// Barycentric (u, v) of the ray's hit on triangle `id` (weights of v1 and v2).
    fn barycentrics(&self, id: usize, o: Vec3A, d: Vec3A) -> (f32, f32) {
        let t = &self.tris[id];
        let e1 = t.v1 - t.v0;
        let e2 = t.v2 - t.v0;
        let pvec = d.cross(e2);
        let inv = 1.0 / e1.dot(pvec);
        let tvec = o - t.v0;
        let u = tvec.dot(pvec) * inv;
        let v = d.dot(tvec.cross(e1)) * inv;
        (u, v)
    }

    fn uv_at(&self, id: usize, u: f32, v: f32) -> Vec2 {
        let r = self.refs[id];
        let m = &self.scene.meshes[r.mesh as usize];
        let [a, b, c] = m.indices[r.tri as usize].map(|i| m.uvs[i as usize]);
        a * (1.0 - u - v) + b * u + c * v
    }

    /// Alpha test of a candidate hit: false where a masked material is cut out.
    fn opaque_at(&self, id: usize, ray: &Ray) -> bool {
        if !self.masked[id] {
            return true;
        }
        let (u, v) = self.barycentrics(id, ray.origin, ray.direction);
        let uv = self.uv_at(id, u, v);
        let r = self.refs[id];
        let m = self.scene.meshes[r.mesh as usize].material;
        let cutoff = match self.scene.materials[m as usize].alpha_mode {
            AlphaMode::Mask { cutoff } => cutoff,
            _ => 0.0,
        };
        self.scene.base_color(m, uv).w >= cutoff
    }

    /// Closest hit along `origin + t·dir`, t in (0, tmax). With `cull`, back faces of
    /// single-sided materials are skipped (primary rays).
    pub fn closest(&self, origin: Vec3, dir: Vec3, tmax: f32, cull: bool) -> Option<Hit> {
        let ray = Ray::new(
            (origin * self.scale).into(),
            dir.into(),
            0.0,
            tmax * self.scale,
        );
        let mut hit = RayHit::none();
        let found = self.bvh.ray_traverse(ray, &mut hit, |ray, id| {
            let t = self.tris[id].intersect(ray);
            if !t.is_finite() {
                return f32::INFINITY;
            }
            if cull
                && self.single_sided[id]
                && self.tris[id].compute_normal().dot(ray.direction) > 0.0
            {
                return f32::INFINITY;
            }
            if !self.opaque_at(id, ray) {
                return f32::INFINITY;
            }
            t
        });
        if !found {
            return None;
        }
        let id = hit.primitive_id as usize;
        let (u, v) = self.barycentrics(id, ray.origin, ray.direction);
        let r = self.refs[id];
        let mesh = &self.scene.meshes[r.mesh as usize];
        let [a, b, c] = mesh.indices[r.tri as usize].map(|i| mesh.normals[i as usize]);
        let geometric = Vec3::from(self.tris[id].compute_normal());
        let front = geometric.dot(dir) < 0.0;
        let flip = if front { 1.0 } else { -1.0 };
        let ns = (a * (1.0 - u - v) + b * u + c * v).normalize_or(geometric) * flip;
        let t = hit.t / self.scale;
        Some(Hit {
            t,
            p: origin + dir * t,
            ng: geometric * flip,
            ns,
            uv: self.uv_at(id, u, v),
            material: mesh.material,
            front,
        })
    }

    /// True when something blocks `origin + t·dir` for t in (0, tmax).
    pub fn occluded(&self, origin: Vec3, dir: Vec3, tmax: f32) -> bool {
        let ray = Ray::new(
            (origin * self.scale).into(),
            dir.into(),
            0.0,
            tmax * self.scale,
        );
        !self.bvh.ray_traverse_miss(ray, |ray, id| {
            let t = self.tris[id].intersect(ray);
            if t.is_finite() && self.opaque_at(id, ray) {
                t
            } else {
                f32::INFINITY
            }
        })
    }
}

/// Scale-aware offset: large enough to leave the float neighbourhood of `p` and of the ray–
/// triangle tests near it. Those err by about 1e-7 of the coordinates involved, which for large
/// triangles (a 400 m floor) reach the scene's size: hence the floor of 1 % of the scene radius.
pub fn epsilon(p: Vec3, scene_radius: f32) -> f32 {
    2e-4 * p.abs().max_element().max(0.01 * scene_radius).max(1e-4)
}

/// Origin for a secondary ray leaving `hit` in direction `dir`, seen from `eye`: moved along the
/// geometric normal to `dir`'s side and towards the eye by [`epsilon`].
pub fn offset_origin(hit: &Hit, dir: Vec3, eye: Vec3, scene_radius: f32) -> Vec3 {
    let eps = epsilon(hit.p, scene_radius);
    let side = if hit.ng.dot(dir) >= 0.0 {
        hit.ng
    } else {
        -hit.ng
    };
    hit.p + side * eps + (eye - hit.p).normalize_or_zero() * eps
}
