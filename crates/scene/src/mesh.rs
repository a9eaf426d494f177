//! Triangle meshes in world space.

use glam::{Mat4, Vec2, Vec3};

/// A triangle mesh in world space with one material.
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    /// Name from the source file, if any.
    pub name: String,
    /// World-space positions (metres).
    pub positions: Vec<Vec3>,
    /// World-space unit shading normals, one per position.
    pub normals: Vec<Vec3>,
    /// Texture coordinates (glTF convention: v down), one per position.
    pub uvs: Vec<Vec2>,
    /// Triangles, counter-clockwise when seen from the front.
    pub indices: Vec<[u32; 3]>,
    /// Index into [`crate::Scene::materials`].
    pub material: u32,
    /// Names of the scene nodes it hangs from, root first (glTF node names; a built-in scene's
    /// object; empty where the format names none): what `--dynamic NAME` matches.
    pub nodes: Vec<String>,
    /// Not in the far field's bake: an object added or moved after it (glTF extras
    /// `"nearfield": {"dynamic": true}`, `--dynamic NAME`, `--add FILE`). The frame and the
    /// reference draw it; `nearfield bake` leaves it out (the book, "Near and far").
    pub dynamic: bool,
    /// The animated node it follows and its rest pose, when it moves ([`crate::Scene::pose`]).
    pub motion: Option<crate::animation::MeshMotion>,
}

impl Mesh {
    /// Replaces the normals with smooth, area-weighted vertex normals: each vertex gets the sum of
    /// its triangles' unnormalised cross products (whose length is twice the area), normalised.
    /// Vertices that belong to no non-degenerate triangle get +Y.
    pub fn generate_smooth_normals(&mut self) {
        let mut acc = vec![Vec3::ZERO; self.positions.len()];
        for t in &self.indices {
            let [a, b, c] = t.map(|i| self.positions[i as usize]);
            let n = (b - a).cross(c - a);
            for &i in t {
                acc[i as usize] += n;
            }
        }
        self.normals = acc
            .into_iter()
            .map(|n| n.try_normalize().unwrap_or(Vec3::Y))
            .collect();
    }

    /// True when normals are missing or some are not unit-length-ish (zero or NaN), in which case
    /// loaders regenerate them.
    pub fn normals_need_generating(&self) -> bool {
        self.normals.len() != self.positions.len()
            || self
                .normals
                .iter()
                .any(|n| !n.is_finite() || n.length_squared() < 1e-8)
    }

    /// Applies a world-from-local transform to positions and normals; flips the winding when the
    /// transform mirrors (negative determinant) so that front faces stay counter-clockwise.
    pub fn transform(&mut self, world_from_local: Mat4) {
        let normal_matrix = world_from_local.inverse().transpose();
        for p in &mut self.positions {
            *p = world_from_local.transform_point3(*p);
        }
        for n in &mut self.normals {
            *n = normal_matrix
                .transform_vector3(*n)
                .try_normalize()
                .unwrap_or(*n);
        }
        if world_from_local.determinant() < 0.0 {
            for t in &mut self.indices {
                t.swap(1, 2);
            }
        }
    }

    /// Sum of triangle areas (m²).
    pub fn area(&self) -> f32 {
        self.indices
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| self.positions[i as usize]);
                0.5 * (b - a).cross(c - a).length()
            })
            .sum()
    }
}

/// Axis-aligned bounding box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    pub min: Vec3,
    pub max: Vec3,
}

impl Aabb {
    pub const EMPTY: Aabb = Aabb {
        min: Vec3::splat(f32::INFINITY),
        max: Vec3::splat(f32::NEG_INFINITY),
    };

    pub fn grow(&mut self, p: Vec3) {
        self.min = self.min.min(p);
        self.max = self.max.max(p);
    }

    pub fn is_empty(&self) -> bool {
        self.min.cmpgt(self.max).any()
    }

    pub fn center(&self) -> Vec3 {
        0.5 * (self.min + self.max)
    }

    pub fn extent(&self) -> Vec3 {
        self.max - self.min
    }

    /// Radius of the bounding sphere around the centre.
    pub fn radius(&self) -> f32 {
        0.5 * self.extent().length()
    }

    /// The eight corners.
    pub fn corners(&self) -> [Vec3; 8] {
        std::array::from_fn(|i| {
            Vec3::new(
                if i & 1 == 0 { self.min.x } else { self.max.x },
                if i & 2 == 0 { self.min.y } else { self.max.y },
                if i & 4 == 0 { self.min.z } else { self.max.z },
            )
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn smooth_normals_are_area_weighted() {
        // Two triangles sharing vertex 0: a large one in the XZ plane (normal +Y) and a small one
        // in the XY plane (normal +Z). The shared normal leans to +Y in proportion to area.
        let mut m = Mesh {
            positions: vec![
                Vec3::ZERO,
                Vec3::new(0.0, 0.0, 2.0),
                Vec3::new(2.0, 0.0, 0.0),
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
            ],
            indices: vec![[0, 1, 2], [0, 3, 4]],
            ..Default::default()
        };
        m.uvs = vec![Vec2::ZERO; 5];
        m.generate_smooth_normals();
        let n = m.normals[0];
        // Areas 2 and 0.5: direction (0, 4, 1) / |.|
        let expect = Vec3::new(0.0, 4.0, 1.0).normalize();
        assert!((n - expect).length() < 1e-6, "{n}");
    }

    #[test]
    fn mirroring_transform_keeps_front_faces() {
        let mut m = Mesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            normals: vec![Vec3::Z; 3],
            uvs: vec![Vec2::ZERO; 3],
            indices: vec![[0, 1, 2]],
            ..Default::default()
        };
        m.transform(Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0)));
        let [a, b, c] = m.indices[0].map(|i| m.positions[i as usize]);
        let geometric = (b - a).cross(c - a).normalize();
        assert!(geometric.dot(m.normals[0]) > 0.99);
    }
}
