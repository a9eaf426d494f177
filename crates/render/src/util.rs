//! Small helpers: shader composition, the raster pipeline of every mesh pass, readback.

/// WGSL library: the `View` and `Frame` structs and view-space helpers (no bindings).
pub const COMMON_WGSL: &str = include_str!("shaders/common.wgsl");
/// WGSL library: the environment's uniform, lat-long lookups and SH irradiance (no bindings).
pub const ENV_WGSL: &str = include_str!("shaders/env.wgsl");
/// WGSL library (with [`ENV_WGSL`]): the far field, sky or probe volume (no bindings).
pub const FAR_WGSL: &str = include_str!("shaders/far.wgsl");
/// nearfield's glue for group 0 ([`crate::bindings::FrameBindings`]): the view, environment,
/// far-field and frame bindings that its entry files pass to the libraries. The one shared WGSL
/// file that declares bindings.
pub const FRAME_BINDINGS_WGSL: &str = include_str!("shaders/frame_bindings.wgsl");
/// WGSL library: one light's incident light and shadow-map visibility (the maps as parameters).
pub const LIGHTS_WGSL: &str = include_str!("shaders/lights.wgsl");

/// WGSL library: `GpuMaterial` and `NO_TEXTURE`.
pub const GPU_MATERIAL_WGSL: &str = include_str!("shaders/gpu_material.wgsl");
/// WGSL library (after [`GPU_MATERIAL_WGSL`]): a material's surface at a fragment (its maps as
/// parameters).
pub const MATERIALS_WGSL: &str = include_str!("shaders/materials.wgsl");
/// WGSL library: the G-buffer surface at a pixel (the images as parameters).
pub const SURFACE_WGSL: &str = include_str!("shaders/surface.wgsl");
/// WGSL library: the technique's env- and indirect-irradiance as the composite and AOV passes
/// read them (formed from ao after an ao-only technique).
pub const IRRADIANCE_TERMS_WGSL: &str = include_str!("passes/irradiance_terms.wgsl");
/// WGSL library: tonemap operators and the sRGB transfer function.
pub const TONEMAP_OPS_WGSL: &str = include_str!("shaders/tonemap_ops.wgsl");

/// Concatenates WGSL sources (shared preludes first).
pub fn compose(parts: &[&str]) -> String {
    parts.join("\n")
}

/// A mesh raster pipeline as every nearfield raster pass draws one: `Vertex` triangle lists,
/// group 0 (the frame, where the pass reads it) and group 1 (its own), `targets::DEPTH_FORMAT` depth tested `Less` and written, colour targets
/// written without blending. What differs between the passes is in here.
pub struct RasterPipeline<'a> {
    pub label: &'a str,
    /// Group 0: the frame's layout, or `None` for a pass that does not read the frame.
    pub frame: Option<&'a wgpu::BindGroupLayout>,
    /// Group 1: the pass's own resources.
    pub layout: &'a wgpu::BindGroupLayout,
    pub module: &'a wgpu::ShaderModule,
    pub vertex: &'a str,
    pub fragment: &'a str,
    pub color_formats: &'a [wgpu::TextureFormat],
    /// `None` draws both faces (double-sided materials, peeling, shadow and light views).
    pub cull: Option<wgpu::Face>,
    pub depth_bias: wgpu::DepthBiasState,
    /// The vertex buffers: the scene's ([`crate::gpu_scene::Vertex::LAYOUT`]), and for the
    /// G-buffer the previous frame's positions too.
    pub vertex_buffers: &'a [Option<wgpu::VertexBufferLayout<'static>>],
}

/// The pipeline `p` describes (made once per device: [`crate::pipeline_cache`]).
pub fn raster_pipeline(device: &wgpu::Device, p: &RasterPipeline) -> wgpu::RenderPipeline {
    let key = crate::pipeline_cache::RasterKey {
        module: p.module.clone(),
        vertex: p.vertex.to_string(),
        fragment: p.fragment.to_string(),
        groups: [p.frame.cloned(), Some(p.layout.clone())],
        color_formats: p.color_formats.to_vec(),
        cull: p.cull,
        depth_bias: (
            p.depth_bias.constant,
            p.depth_bias.slope_scale.to_bits(),
            p.depth_bias.clamp.to_bits(),
        ),
    };
    crate::pipeline_cache::raster_pipeline(device, key, || make_raster_pipeline(device, p))
}

fn make_raster_pipeline(device: &wgpu::Device, p: &RasterPipeline) -> wgpu::RenderPipeline {
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(p.label),
        bind_group_layouts: &[p.frame, Some(p.layout)],
        immediate_size: 0,
    });
    let targets: Vec<Option<wgpu::ColorTargetState>> = p
        .color_formats
        .iter()
        .map(|&format| {
            Some(wgpu::ColorTargetState {
                format,
                blend: None,
                write_mask: wgpu::ColorWrites::ALL,
            })
        })
        .collect();
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(p.label),
        layout: Some(&pipeline_layout),
        vertex: wgpu::VertexState {
            module: p.module,
            entry_point: Some(p.vertex),
            compilation_options: Default::default(),
            buffers: p.vertex_buffers,
        },
        primitive: wgpu::PrimitiveState {
            topology: wgpu::PrimitiveTopology::TriangleList,
            front_face: wgpu::FrontFace::Ccw,
            cull_mode: p.cull,
            ..Default::default()
        },
        depth_stencil: Some(wgpu::DepthStencilState {
            format: crate::targets::DEPTH_FORMAT,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::Less),
            stencil: Default::default(),
            bias: p.depth_bias,
        }),
        multisample: Default::default(),
        fragment: Some(wgpu::FragmentState {
            module: p.module,
            entry_point: Some(p.fragment),
            compilation_options: Default::default(),
            targets: &targets,
        }),
        multiview_mask: None,
        cache: None,
    })
}

/// The default view of `t` (all of it, its own format and dimension).
pub fn view(t: &wgpu::Texture) -> wgpu::TextureView {
    t.create_view(&Default::default())
}

/// Workgroup counts for an 8×8 compute kernel over `size` pixels.
pub fn groups_8x8(size: (u32, u32)) -> (u32, u32) {
    (size.0.div_ceil(8), size.1.div_ceil(8))
}

/// Records a copy of mip 0 of `texture` after the work in `encoder`, submits it and waits:
/// the texels in host memory, rows tightly packed (`texel_bytes` per texel).
pub fn read_texture(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    mut encoder: wgpu::CommandEncoder,
    texture: &wgpu::Texture,
    texel_bytes: u32,
) -> Vec<u8> {
    let (w, h) = (texture.width(), texture.height());
    let row = w * texel_bytes;
    let padded =
        row.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size: (padded * h) as u64,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    encoder.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded),
                rows_per_image: Some(h),
            },
        },
        wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
    );
    queue.submit([encoder.finish()]);
    let slice = buffer.slice(..);
    let mapped = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    let flag = mapped.clone();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        flag.store(r.is_ok(), std::sync::atomic::Ordering::SeqCst)
    });
    let _ = device.poll(wgpu::PollType::wait_indefinitely());
    // A lost device maps nothing: the texels read as zeros, and the context says it was lost
    // (`GpuContext::lost`), which every command checks before it writes an output.
    if !mapped.load(std::sync::atomic::Ordering::SeqCst) {
        return vec![0; (row * h) as usize];
    }
    let Ok(data) = slice.get_mapped_range() else {
        return vec![0; (row * h) as usize];
    };
    let mut out = Vec::with_capacity((row * h) as usize);
    for y in 0..h as usize {
        let start = y * padded as usize;
        out.extend_from_slice(&data[start..start + row as usize]);
    }
    out
}
