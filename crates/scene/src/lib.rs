//! The CPU scene model of nearfield: everything the renderer and the reference tracer need to know
//! about a scene, with no GPU code.
//!
//! A [`Scene`] is flattened to world space when it is loaded: every mesh carries world-space
//! positions and normals, so consumers never walk a node hierarchy. Materials follow the glTF 2.0
//! metallic-roughness model (colours linear Rec.709), lights follow `KHR_lights_punctual` (point and
//! spot intensities in candela, directional in lux), and the environment is an equirectangular map
//! with the convention documented in [`environment`].
//!
//! Loading: [`load_scene`] reads `.gltf`/`.glb`/`.obj`/`.ply`; [`builtin::scene`] builds the
//! built-in test scenes; [`SceneSource::parse`] understands both spellings used on the command line.

pub mod animation;
pub mod atomic;
pub mod builtin;
pub mod camera;
pub mod dynamic;
pub mod env_source;
pub mod environment;
pub mod error;
pub mod export;
pub mod light;
pub mod limits;
pub mod load;
pub mod material;
pub mod mesh;
pub mod path;
pub mod probes;
pub mod progress;
pub mod sh;
pub mod sky;
pub mod sun;

pub use animation::{Animation, Interpolation, Track};
pub use camera::{Camera, CameraFile};
pub use dynamic::{DynamicError, Placement};
pub use env_source::EnvSource;
pub use environment::Environment;
pub use error::{SceneError, one_line};
pub use light::{Light, LightKind};
pub use material::{AlphaMode, Material, Texture, TextureColorSpace};
pub use mesh::{Aabb, Mesh};
pub use path::{CameraPath, Keyframe};
pub use sun::{Sun, SunMode};

use std::path::{Path, PathBuf};

/// A whole scene in world space.
#[derive(Clone, Debug, Default)]
pub struct Scene {
    /// Human-readable name (file stem or `builtin:NAME`).
    pub name: String,
    /// Triangle meshes in world space, one material each.
    pub meshes: Vec<Mesh>,
    /// Materials referenced by [`Mesh::material`].
    pub materials: Vec<Material>,
    /// Decoded textures referenced by materials.
    pub textures: Vec<Texture>,
    /// Punctual lights in world space.
    pub lights: Vec<Light>,
    /// Cameras defined by the scene (glTF cameras, or a built-in scene's default view). The first
    /// one is the default view.
    pub cameras: Vec<Camera>,
    /// The environment this scene is lit by when the user names none.
    pub default_env: EnvSource,
    /// The animated nodes moving meshes follow (empty: nothing moves).
    pub animation: Animation,
}

impl Scene {
    /// Total number of triangles over all meshes.
    pub fn triangle_count(&self) -> usize {
        self.meshes.iter().map(|m| m.indices.len()).sum()
    }

    /// World-space bounds of all geometry.
    pub fn bounds(&self) -> Aabb {
        let mut b = Aabb::EMPTY;
        for m in &self.meshes {
            for p in &m.positions {
                b.grow(*p);
            }
        }
        b
    }

    /// The camera to use when the user gives none: the scene's own first camera, else a view
    /// framed on the bounding box.
    pub fn default_camera(&self) -> Camera {
        self.cameras
            .first()
            .copied()
            .unwrap_or_else(|| Camera::framing(self.bounds(), 45f32.to_radians()))
    }

    /// Base colour ρ (linear RGBA: factor × bilinear texture) of material `m` at `uv`.
    pub fn base_color(&self, m: u32, uv: glam::Vec2) -> glam::Vec4 {
        let mat = &self.materials[m as usize];
        match mat.base_color_texture {
            Some(t) => mat.base_color * self.textures[t].sample_bilinear(uv.x, uv.y),
            None => mat.base_color,
        }
    }

    /// Emitted radiance of material `m` at `uv` (factor × texture).
    pub fn emission(&self, m: u32, uv: glam::Vec2) -> glam::Vec3 {
        let mat = &self.materials[m as usize];
        match mat.emissive_texture {
            Some(t) => mat.emissive * self.textures[t].sample_bilinear(uv.x, uv.y).truncate(),
            None => mat.emissive,
        }
    }

    /// Checks invariants that every consumer relies on: indices in range, finite positions,
    /// valid material references. Loaders call this before they return.
    pub fn validate(&self, path: &Path) -> Result<(), SceneError> {
        let bad = |what: String| SceneError::Invalid {
            path: path.to_path_buf(),
            what,
        };
        if self.meshes.is_empty() || self.triangle_count() == 0 {
            return Err(bad("no triangles".into()));
        }
        for (i, m) in self.meshes.iter().enumerate() {
            if m.material as usize >= self.materials.len() {
                return Err(bad(format!("mesh {i} references a missing material")));
            }
            if m.normals.len() != m.positions.len() || m.uvs.len() != m.positions.len() {
                return Err(bad(format!("mesh {i} has mismatched attribute counts")));
            }
            let n = m.positions.len() as u32;
            if m.indices.iter().flatten().any(|&v| v >= n) {
                return Err(bad(format!("mesh {i} has a vertex index out of range")));
            }
            if let Some(p) = m
                .positions
                .iter()
                .find(|p| !p.to_array().into_iter().all(limits::sane))
            {
                return Err(bad(format!(
                    "mesh {i} ('{}') has a non-finite or absurd vertex position {p} (beyond ±{:e})",
                    m.name,
                    limits::MAX_COORDINATE
                )));
            }
        }
        let vertices: usize = self.meshes.iter().map(|m| m.positions.len()).sum();
        if self.triangle_count() > limits::MAX_TRIANGLES || vertices > limits::MAX_VERTICES {
            return Err(bad(format!(
                "{} triangles and {vertices} vertices, beyond the limit of {} each",
                self.triangle_count(),
                limits::MAX_TRIANGLES
            )));
        }
        for (i, mat) in self.materials.iter().enumerate() {
            let factors = [mat.metallic, mat.roughness];
            if !(mat.base_color.is_finite()
                && mat.emissive.is_finite()
                && mat.emissive.min_element() >= 0.0
                && factors.iter().all(|f| f.is_finite()))
            {
                return Err(bad(format!(
                    "material {i} ('{}') has a non-finite or negative factor",
                    mat.name
                )));
            }
            for t in [
                mat.base_color_texture,
                mat.metallic_roughness_texture,
                mat.emissive_texture,
            ]
            .into_iter()
            .flatten()
            {
                if t >= self.textures.len() {
                    return Err(bad(format!("material {i} references a missing texture")));
                }
            }
        }
        Ok(())
    }
}

/// Where a scene comes from, as written on the command line: a file path or `builtin:NAME`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum SceneSource {
    File(PathBuf),
    Builtin(String),
}

impl SceneSource {
    /// Parses `builtin:NAME` or a path.
    pub fn parse(s: &str) -> Self {
        match s.strip_prefix("builtin:") {
            Some(name) => SceneSource::Builtin(name.to_string()),
            None => SceneSource::File(PathBuf::from(s)),
        }
    }

    /// Loads the scene.
    pub fn load(&self) -> Result<Scene, SceneError> {
        match self {
            SceneSource::File(p) => load_scene(p),
            SceneSource::Builtin(name) => builtin::scene(name),
        }
    }
}

impl std::fmt::Display for SceneSource {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SceneSource::File(p) => write!(f, "{}", p.display()),
            SceneSource::Builtin(n) => write!(f, "builtin:{n}"),
        }
    }
}

/// Loads a scene file, choosing the format by extension (`.gltf`, `.glb`, `.obj`, `.ply`).
pub fn load_scene(path: &Path) -> Result<Scene, SceneError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase())
        .unwrap_or_default();
    if !matches!(ext.as_str(), "gltf" | "glb" | "obj" | "ply") {
        return Err(SceneError::UnknownFormat {
            path: path.to_path_buf(),
        });
    }
    if !path.is_file() {
        return Err(SceneError::Missing {
            path: path.to_path_buf(),
        });
    }
    let scene = match ext.as_str() {
        "gltf" | "glb" => load::gltf::load(path)?,
        "obj" => load::obj::load(path)?,
        _ => load::ply::load(path)?,
    };
    scene.validate(path)?;
    Ok(scene)
}
