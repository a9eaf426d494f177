//! Display (compute): one image — the `final` frame, an AOV or a technique's own image — or two
//! side by side with a divider (an A/B view), turned into sRGB display bytes: tonemapped colour,
//! normals as colours, scalars in false colour. See display.wgsl. The viewer shows and saves
//! [`DisplayPass::output`]; anyone can use it to look at a float image.

use crate::aov::Aov;
use crate::bindings::{PassLayout, kind};
use crate::frame::Tonemap;
use crate::util;

pub const SHADER: &str = include_str!("display.wgsl");

pub fn source() -> String {
    util::compose(&[util::TONEMAP_OPS_WGSL, SHADER])
}

/// The output's format: sRGB-encoded bytes in a unorm texture (storage textures cannot be sRGB).
/// [`DisplayPass::encoded_view`] samples those bytes as they are (what egui expects of a user
/// texture: gamma-encoded colour).
pub const DISPLAY_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

/// How one side's image becomes display bytes (display.wgsl's modes).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DisplayMode {
    /// Already display bytes (the `final` image).
    Encoded = 0,
    /// Linear radiance or irradiance: exposure, tonemap, sRGB.
    Colour = 1,
    /// Linear values in [0, 1] (albedo): sRGB.
    Linear = 2,
    /// Unit vectors: 0.5 + 0.5 n.
    Normal = 3,
    /// The red channel in false colour over [lo, hi].
    Scalar = 4,
    /// Red and green as signed values in [−hi, hi].
    Vector = 5,
}

impl DisplayMode {
    /// The natural mode of an AOV.
    pub fn for_aov(aov: Aov) -> Self {
        match aov {
            Aov::Final => DisplayMode::Encoded,
            Aov::Albedo => DisplayMode::Linear,
            Aov::Normal => DisplayMode::Normal,
            Aov::Depth | Aov::Ao => DisplayMode::Scalar,
            Aov::Motion => DisplayMode::Vector,
            Aov::Radiance
            | Aov::EnvIrradiance
            | Aov::LightIrradiance
            | Aov::IndirectIrradiance
            | Aov::Diffuse
            | Aov::Specular
            | Aov::DirectRadiance
            | Aov::Lambertian
            | Aov::FarIrradiance => DisplayMode::Colour,
        }
    }
}

/// One side of the display: an image (any float-sampled 2D texture of the display's size or
/// larger), its mode, and whether its alpha is surface coverage.
pub struct DisplaySide<'a> {
    pub view: &'a wgpu::TextureView,
    pub mode: DisplayMode,
    pub coverage: bool,
}

/// Exposure, tonemap and false-colour range shared by both sides.
#[derive(Clone, Copy, Debug)]
pub struct DisplayPost {
    pub exposure: f32,
    pub tonemap: Tonemap,
    /// Range of [`DisplayMode::Scalar`] (lo, hi); `hi` is the scale of [`DisplayMode::Vector`].
    pub range: (f32, f32),
}

crate::gpu_struct! {
    /// `DisplayParams` in display.wgsl.
    pub struct DisplayParams {
        /// Output size (pixels), the split column (≥ width: A only), the divider's half-width.
        pub width: u32,
        pub height: u32,
        pub split: u32,
        pub divider: u32,
        /// [`DisplayMode`] of each side, [`Tonemap::index`], coverage bits (1: A, 2: B).
        pub mode_a: u32,
        pub mode_b: u32,
        pub tonemap: u32,
        pub coverage: u32,
        /// Exposure (EV) and the false-colour range.
        pub exposure: f32,
        pub lo: f32,
        pub hi: f32,
        pub _pad0: f32,
    }
}

crate::bind_group! {
    /// Group 1 of the display pass (group 0 is empty: it runs outside the frame).
    pub struct DisplayBindings: COMPUTE {
        /// `DisplayParams`: size, split column, modes, post settings.
        params: buffer = kind::UNIFORM,
        /// The image left of the split (any float format).
        image_a: view = kind::TEXTURE_UNFILTERABLE,
        /// The image right of the split.
        image_b: view = kind::TEXTURE_UNFILTERABLE,
        /// The presented image (rgba8unorm, sRGB-encoded bytes).
        out_display: view = kind::write(DISPLAY_FORMAT),
    }
}

/// The binding declaration the reflection test checks.
pub fn pass_layout() -> PassLayout {
    PassLayout {
        name: "display",
        source: source(),
        entry_point: "main",
        group1: DisplayBindings::SLOTS,
    }
}

pub struct DisplayPass {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    params: wgpu::Buffer,
    /// Display bytes (rgba8unorm, sRGB-encoded), COPY_SRC for screenshots.
    pub output: wgpu::Texture,
    /// [`Self::output`] for sampling: gives the encoded bytes (no sRGB decode), which a UI that
    /// blends in gamma space (egui) shows unchanged on a non-sRGB surface and decodes itself
    /// for an sRGB one.
    pub encoded_view: wgpu::TextureView,
    storage_view: wgpu::TextureView,
    size: (u32, u32),
}

impl DisplayPass {
    pub fn new(device: &wgpu::Device, size: (u32, u32)) -> Self {
        let layout = DisplayBindings::layout(device);
        let module = crate::pipeline_cache::shader_module(device, "display", &source());
        let pipeline =
            crate::pipeline_cache::standalone_pipeline(device, "display", &module, "main", &layout);
        let params = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("display params"),
            size: std::mem::size_of::<DisplayParams>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let (output, encoded_view, storage_view) = output_texture(device, size);
        DisplayPass {
            pipeline,
            layout,
            params,
            output,
            encoded_view,
            storage_view,
            size,
        }
    }

    pub fn size(&self) -> (u32, u32) {
        self.size
    }

    /// Makes a new output of `size` (the old one is released when no longer referenced).
    pub fn resize(&mut self, device: &wgpu::Device, size: (u32, u32)) {
        if size != self.size {
            (self.output, self.encoded_view, self.storage_view) = output_texture(device, size);
            self.size = size;
        }
    }

    /// Records the display of `a`, or of `a` left of column `split` and `b` right of it.
    pub fn encode(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        a: &DisplaySide,
        b: Option<(&DisplaySide, u32)>,
        post: DisplayPost,
    ) {
        let (w, h) = self.size;
        let (b_side, split) = match b {
            Some((side, split)) => (side, split.min(w)),
            None => (a, w),
        };
        let coverage = a.coverage as u32 | ((b_side.coverage as u32) << 1);
        let p = DisplayParams {
            width: w,
            height: h,
            split,
            divider: 1,
            mode_a: a.mode as u32,
            mode_b: b_side.mode as u32,
            tonemap: post.tonemap.index(),
            coverage,
            exposure: post.exposure,
            lo: post.range.0,
            hi: post.range.1,
            _pad0: 0.0,
        };
        queue.write_buffer(&self.params, 0, bytemuck::bytes_of(&p));
        let bind_group = DisplayBindings {
            params: &self.params,
            image_a: a.view,
            image_b: b_side.view,
            out_display: &self.storage_view,
        }
        .bind_group(device, &self.layout);
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("display"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(1, &bind_group, &[]);
        let (gx, gy) = util::groups_8x8(self.size);
        pass.dispatch_workgroups(gx, gy, 1);
    }
}

fn output_texture(
    device: &wgpu::Device,
    size: (u32, u32),
) -> (wgpu::Texture, wgpu::TextureView, wgpu::TextureView) {
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("display"),
        size: wgpu::Extent3d {
            width: size.0.max(1),
            height: size.1.max(1),
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: DISPLAY_FORMAT,
        usage: wgpu::TextureUsages::STORAGE_BINDING
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    let encoded = texture.create_view(&wgpu::TextureViewDescriptor {
        usage: Some(wgpu::TextureUsages::TEXTURE_BINDING),
        ..Default::default()
    });
    let storage = texture.create_view(&Default::default());
    (texture, encoded, storage)
}
