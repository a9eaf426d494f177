//! Per-frame uniforms shared by every pass: `View` (shaders/common.wgsl), what the near-field
//! kernels read, and `Frame` (shaders/common.wgsl), the rest of nearfield's own frame. The
//! environment's parameters are the environment's own uniform ([`crate::gpu_env::EnvUniforms`]).

use glam::{Mat4, Vec3};
use nearfield_scene::{Aabb, Camera};

/// Tone-mapping operators (tonemap.wgsl).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Tonemap {
    /// Narkowicz' ACES filmic fit.
    #[default]
    Aces,
    /// Khronos PBR Neutral.
    Neutral,
    /// Clamp to [0, 1].
    Linear,
}

impl Tonemap {
    pub const NAMES: &'static [&'static str] = &["aces", "neutral", "linear"];

    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "aces" => Some(Tonemap::Aces),
            "neutral" => Some(Tonemap::Neutral),
            "linear" => Some(Tonemap::Linear),
            _ => None,
        }
    }

    pub fn index(self) -> u32 {
        self as u32
    }
}

crate::gpu_struct! {
    /// `View` in shaders/common.wgsl, field for field: what the near-field kernels read of the
    /// frame — the camera of this and last frame, the image size, the frame's index and noise
    /// seed, whether history may be reused. Nothing of exposure, tone mapping, AOVs or lights.
    pub struct ViewUniforms {
        pub clip_from_world: [[f32; 4]; 4],
        pub world_from_clip: [[f32; 4]; 4],
        pub view_from_world: [[f32; 4]; 4],
        pub world_from_view: [[f32; 4]; 4],
        pub prev_clip_from_world: [[f32; 4]; 4],
        pub prev_view_from_world: [[f32; 4]; 4],
        pub prev_world_from_view: [[f32; 4]; 4],
        /// xyz camera position; w unused.
        pub camera_position: [f32; 4],
        /// Width, height (pixels).
        pub size: [f32; 2],
        /// 1/width, 1/height.
        pub inv_size: [f32; 2],
        /// Near and far plane (m), aspect (w/h), tan(yfov/2).
        pub near: f32,
        pub far: f32,
        pub aspect: f32,
        pub tan_half_fov: f32,
        /// Last frame's near, far, aspect, tan(yfov/2).
        pub prev_near: f32,
        pub prev_far: f32,
        pub prev_aspect: f32,
        pub prev_tan_half_fov: f32,
        /// Frame index and the noise seed.
        pub frame_index: u32,
        pub seed: u32,
        /// 1 when last frame's buffers may be reused (0 on the first frame and after a camera
        /// cut); frames since the last cut.
        pub history_valid: u32,
        pub frames_since_cut: u32,
    }
}

crate::gpu_struct! {
    /// `Frame` in shaders/common.wgsl, field for field: the rest of nearfield's own frame — post
    /// settings and the light count. Read by nearfield's own passes and by the
    /// techniques that shade with the light table (ssdo, s3ho); a host that runs gtao, hbil or
    /// vbgi never writes it ([`crate::passes::FrameGroup::new`] with `None`).
    pub struct FrameUniforms {
        /// Exposure (EV), tonemap operator ([`Tonemap::index`]), shadow normal offset (texels).
        pub exposure: f32,
        pub tonemap: u32,
        pub shadow_normal_offset: f32,
        /// Lights in the light table.
        pub light_count: u32,
    }
}

/// The camera matrices of one frame.
#[derive(Clone, Copy, Debug)]
pub struct CameraMatrices {
    pub view_from_world: Mat4,
    pub clip_from_view: Mat4,
    pub near: f32,
    pub far: f32,
}

impl CameraMatrices {
    pub fn new(camera: &Camera, size: (u32, u32), bounds: Aabb) -> Self {
        let (near, far) = camera.depth_range(bounds);
        let aspect = size.0 as f32 / size.1 as f32;
        CameraMatrices {
            view_from_world: camera.view_from_world(),
            clip_from_view: camera.clip_from_view(aspect, near, far),
            near,
            far,
        }
    }

    pub fn clip_from_world(&self) -> Mat4 {
        self.clip_from_view * self.view_from_world
    }
}

/// The post settings of a frame.
#[derive(Clone, Copy, Debug)]
pub struct PostUniforms {
    /// EV stops.
    pub exposure: f32,
    pub tonemap: Tonemap,
    /// Shadow receivers' offset along the normal, in shadow-map texels.
    pub shadow_normal_offset: f32,
}

/// Everything that goes into [`ViewUniforms`].
pub struct FrameInputs<'a> {
    pub camera: &'a Camera,
    pub current: CameraMatrices,
    pub previous: CameraMatrices,
    pub size: (u32, u32),
    pub frame_index: u32,
    pub seed: u32,
    /// Last frame's camera (tan(yfov/2) for its projection row).
    pub previous_tan_half_fov: f32,
    /// Whether last frame's buffers may be reused, and frames since the last cut.
    pub history: (bool, u32),
}

impl ViewUniforms {
    pub fn new(f: &FrameInputs) -> Self {
        let clip_from_world = f.current.clip_from_world();
        let world_from_view = f.current.view_from_world.inverse();
        let eye: Vec3 = f.camera.eye;
        ViewUniforms {
            clip_from_world: clip_from_world.to_cols_array_2d(),
            world_from_clip: clip_from_world.inverse().to_cols_array_2d(),
            view_from_world: f.current.view_from_world.to_cols_array_2d(),
            world_from_view: world_from_view.to_cols_array_2d(),
            prev_clip_from_world: f.previous.clip_from_world().to_cols_array_2d(),
            prev_view_from_world: f.previous.view_from_world.to_cols_array_2d(),
            prev_world_from_view: f.previous.view_from_world.inverse().to_cols_array_2d(),
            camera_position: [eye.x, eye.y, eye.z, 0.0],
            size: [f.size.0 as f32, f.size.1 as f32],
            inv_size: [1.0 / f.size.0 as f32, 1.0 / f.size.1 as f32],
            near: f.current.near,
            far: f.current.far,
            aspect: f.size.0 as f32 / f.size.1 as f32,
            tan_half_fov: (0.5 * f.camera.yfov).tan(),
            prev_near: f.previous.near,
            prev_far: f.previous.far,
            prev_aspect: f.size.0 as f32 / f.size.1 as f32,
            prev_tan_half_fov: f.previous_tan_half_fov,
            frame_index: f.frame_index,
            seed: f.seed,
            history_valid: f.history.0 as u32,
            frames_since_cut: f.history.1,
        }
    }
}

impl FrameUniforms {
    pub fn new(post: PostUniforms, light_count: u32) -> Self {
        FrameUniforms {
            exposure: post.exposure,
            tonemap: post.tonemap.index(),
            shadow_normal_offset: post.shadow_normal_offset,
            light_count,
        }
    }
}
