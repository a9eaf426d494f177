//! Moving objects on the GPU: the vertices of every mesh that follows an animated node, posed at
//! the scene's time before each frame, and the previous frame's positions the G-buffer makes its
//! motion vectors of (the book, "In motion").

use crate::vertex::Vertex;
use nearfield_scene::Scene;
use nearfield_scene::animation::{Animation, MeshMotion};

/// A moving mesh: where its vertices start in the scene's vertex buffer, how it moves, and the
/// vertices the buffer holds now.
struct MovingMesh {
    first: u64,
    motion: MeshMotion,
    posed: Vec<Vertex>,
}

/// The scene's moving meshes and its clock.
pub struct MovingObjects {
    animation: Animation,
    meshes: Vec<MovingMesh>,
    /// The time the next frame shows (s), and the time the vertex buffer holds.
    time: f32,
    shown: f32,
    /// Whether the previous positions still differ from the vertices.
    previous_stale: bool,
}

impl MovingObjects {
    /// The moving meshes of `scene` (`vertices`: the vertex buffer's contents, each mesh's
    /// first vertex in `first`), posed as `scene` is; `None` when nothing moves.
    pub fn new(scene: &Scene, vertices: &[Vertex], first: &[u32]) -> Option<Self> {
        if !scene.moves() {
            return None;
        }
        let meshes = scene
            .meshes
            .iter()
            .zip(first)
            .filter_map(|(m, &f)| {
                let motion = m.motion.clone()?;
                let posed = vertices[f as usize..f as usize + m.positions.len()].to_vec();
                Some(MovingMesh {
                    first: f as u64,
                    motion,
                    posed,
                })
            })
            .collect();
        Some(MovingObjects {
            animation: scene.animation.clone(),
            meshes,
            time: f32::NAN,
            shown: f32::NAN,
            previous_stale: false,
        })
    }

    /// Sets the time (s) the next frame shows.
    pub fn set_time(&mut self, t: f32) {
        self.time = t;
    }

    /// Before a frame: poses the meshes at the time set (writing the vertices they held as the
    /// previous positions), or, when they did not move, makes the previous positions the
    /// current ones again. Whether they moved.
    pub fn advance(
        &mut self,
        queue: &wgpu::Queue,
        vertices: &wgpu::Buffer,
        previous: &wgpu::Buffer,
    ) -> bool {
        let stride = std::mem::size_of::<Vertex>() as u64;
        let moved = self.time.is_finite() && self.time.to_bits() != self.shown.to_bits();
        if !(moved || self.previous_stale) {
            return false;
        }
        for m in &mut self.meshes {
            queue.write_buffer(previous, m.first * stride, bytemuck::cast_slice(&m.posed));
            if moved {
                let world = self.animation.motion_at(m.motion.node, self.time);
                let (positions, normals) = m.motion.posed(world);
                for ((v, p), n) in m.posed.iter_mut().zip(positions).zip(normals) {
                    v.position = p.into();
                    v.normal = n.into();
                }
                queue.write_buffer(vertices, m.first * stride, bytemuck::cast_slice(&m.posed));
            }
        }
        self.previous_stale = moved;
        self.shown = self.time;
        moved
    }
}
