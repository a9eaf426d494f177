//! The quads, boxes and floors the built-in scenes are made of.

use crate::{Camera, EnvSource, Material, Mesh, Scene};
use glam::{Quat, Vec2, Vec3};

/// Accumulates quads into one mesh per material.
pub(super) struct Builder {
    pub(super) scene: Scene,
}

impl Builder {
    pub(super) fn new(name: &str) -> Self {
        Builder {
            scene: Scene {
                name: format!("builtin:{name}"),
                ..Default::default()
            },
        }
    }

    pub(super) fn material(&mut self, m: Material) -> u32 {
        let name = m.name.clone();
        self.scene.materials.push(m);
        self.scene.meshes.push(Mesh {
            name: name.clone(),
            material: (self.scene.materials.len() - 1) as u32,
            nodes: vec![name],
            ..Default::default()
        });
        (self.scene.materials.len() - 1) as u32
    }

    /// A material whose mesh is dynamic: an object the far field's bake leaves out.
    pub(super) fn dynamic_material(&mut self, m: Material) -> u32 {
        let i = self.material(m);
        self.scene.meshes[i as usize].dynamic = true;
        i
    }

    /// A planar quad with corners in counter-clockwise order seen from the front.
    pub(super) fn quad(&mut self, material: u32, corners: [Vec3; 4]) {
        let m = &mut self.scene.meshes[material as usize];
        let n = (corners[1] - corners[0])
            .cross(corners[2] - corners[0])
            .normalize();
        let base = m.positions.len() as u32;
        let uv = [
            Vec2::new(0.0, 1.0),
            Vec2::new(1.0, 1.0),
            Vec2::new(1.0, 0.0),
            Vec2::ZERO,
        ];
        for (c, t) in corners.iter().zip(uv) {
            m.positions.push(*c);
            m.normals.push(n);
            m.uvs.push(t);
        }
        m.indices.push([base, base + 1, base + 2]);
        m.indices.push([base, base + 2, base + 3]);
    }

    /// A horizontal rectangle at height y facing +Y (or −Y when `down`).
    pub(super) fn floor(&mut self, material: u32, min: Vec2, max: Vec2, y: f32, down: bool) {
        let mut c = [
            Vec3::new(min.x, y, max.y),
            Vec3::new(max.x, y, max.y),
            Vec3::new(max.x, y, min.y),
            Vec3::new(min.x, y, min.y),
        ];
        if down {
            c.reverse();
        }
        self.quad(material, c);
    }

    /// A closed box standing on y = base, rotated by `yaw` degrees about +Y, faces outward. The
    /// bottom face is omitted (it rests on a floor).
    pub(super) fn block(
        &mut self,
        material: u32,
        center_xz: Vec2,
        size: Vec3,
        base: f32,
        yaw_deg: f32,
    ) {
        let rot = Quat::from_rotation_y(yaw_deg.to_radians());
        let c = Vec3::new(center_xz.x, base, center_xz.y);
        let h = size * 0.5;
        let p = |x: f32, y: f32, z: f32| c + rot * Vec3::new(x * h.x, y * size.y, z * h.z);
        // Top
        self.quad(
            material,
            [
                p(-1., 1., 1.),
                p(1., 1., 1.),
                p(1., 1., -1.),
                p(-1., 1., -1.),
            ],
        );
        // +Z, −Z, +X, −X
        self.quad(
            material,
            [p(-1., 0., 1.), p(1., 0., 1.), p(1., 1., 1.), p(-1., 1., 1.)],
        );
        self.quad(
            material,
            [
                p(1., 0., -1.),
                p(-1., 0., -1.),
                p(-1., 1., -1.),
                p(1., 1., -1.),
            ],
        );
        self.quad(
            material,
            [p(1., 0., 1.), p(1., 0., -1.), p(1., 1., -1.), p(1., 1., 1.)],
        );
        self.quad(
            material,
            [
                p(-1., 0., -1.),
                p(-1., 0., 1.),
                p(-1., 1., 1.),
                p(-1., 1., -1.),
            ],
        );
    }

    /// A sphere of `radius` around `center`, `rings` latitude bands of `2 · rings` quads each,
    /// faces outward with smooth normals.
    pub(super) fn sphere(&mut self, material: u32, center: Vec3, radius: f32, rings: u32) {
        let m = &mut self.scene.meshes[material as usize];
        let base = m.positions.len() as u32;
        let around = 2 * rings;
        for i in 0..=rings {
            let theta = std::f32::consts::PI * i as f32 / rings as f32;
            for j in 0..=around {
                let phi = std::f32::consts::TAU * j as f32 / around as f32;
                let n = Vec3::new(
                    theta.sin() * phi.cos(),
                    theta.cos(),
                    -theta.sin() * phi.sin(),
                );
                m.positions.push(center + radius * n);
                m.normals.push(n);
                m.uvs
                    .push(Vec2::new(j as f32 / around as f32, i as f32 / rings as f32));
            }
        }
        let at = |i: u32, j: u32| base + i * (around + 1) + j;
        for i in 0..rings {
            for j in 0..around {
                let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                if i > 0 {
                    m.indices.push([a, b, d]);
                }
                if i + 1 < rings {
                    m.indices.push([d, b, c]);
                }
            }
        }
    }

    pub(super) fn finish(mut self, camera: Camera, env: EnvSource) -> Scene {
        self.scene.meshes.retain(|m| !m.indices.is_empty());
        self.scene.cameras = vec![camera];
        self.scene.default_env = env;
        self.scene
    }
}
