//! The environment on the GPU: the lat-long radiance map with box-filtered mips, the
//! GGX-prefiltered specular chain (passes/env_prefilter.wgsl) and the order-3 SH projection.

use crate::bindings::{PassLayout, kind};
use crate::util;
use glam::Vec3;
use nearfield_scene::{Environment, sh};
use wgpu::util::DeviceExt;

/// Number of roughness levels in the specular chain (roughness 0, 0.2, …, 1).
pub const SPECULAR_LEVELS: u32 = 6;
/// Width of the specular chain's level 0 (at most; never wider than the map).
pub const SPECULAR_WIDTH: u32 = 512;
/// Radiance maps wider than this are box-downsampled on upload.
pub const MAX_RADIANCE_WIDTH: u32 = 2048;
/// Largest value an rgba16float texel can hold; brighter texels (a sun's core) are clamped on
/// upload. The SH projection is computed in f32 from the unclamped map.
pub const F16_MAX: f32 = 65000.0;
/// Size of the pre-convolved diffuse map (lat-long; irradiance varies slowly).
pub const IRRADIANCE_SIZE: (u32, u32) = (64, 32);

/// The environment's mip chains: env_prefilter.wgsl.
pub const PREFILTER_WGSL: &str = include_str!("passes/env_prefilter.wgsl");

crate::bind_group! {
    /// Group 1 of the environment's `downsample` and `prefilter` kernels (group 0 is empty).
    pub struct PrefilterBindings: COMPUTE {
        /// `PrefilterParams`.
        params: buffer = kind::UNIFORM,
        /// The finer mip (downsample) or the whole radiance chain (prefilter) (rgba16float).
        source: view = kind::TEXTURE,
        /// Repeats in u, clamps in v, trilinear.
        source_sampler: sampler = kind::SAMPLER,
        /// The level written (rgba16float).
        destination: view = kind::write(wgpu::TextureFormat::Rgba16Float),
    }
}

/// The binding declarations the reflection test checks.
pub fn pass_layouts() -> Vec<PassLayout> {
    PassLayout::entries(
        "env_prefilter",
        PREFILTER_WGSL.to_string(),
        &["downsample", "prefilter"],
        PrefilterBindings::SLOTS,
    )
}

crate::gpu_struct! {
    /// `PrefilterParams` in env_prefilter.wgsl.
    pub struct PrefilterParams {
        pub roughness: f32,
        pub source_width: f32,
        pub source_height: f32,
        pub source_mips: f32,
    }
}

crate::gpu_struct! {
    /// `EnvUniforms` in shaders/env.wgsl, field for field: the environment's own uniform (group 0,
    /// binding 4), all that env.wgsl's lookups read besides the maps.
    pub struct EnvUniforms {
        /// Rotation about +Y (rad).
        pub rotation: f32,
        /// Multiplies the (raw) maps; already applied to `sh`.
        pub intensity: f32,
        /// Mip counts of the GGX-prefiltered map and of the radiance chain.
        pub specular_mips: f32,
        pub radiance_mips: f32,
        /// Order-3 SH projection of the radiance: 16 rgb coefficients (w unused), rotation and
        /// intensity applied.
        pub sh: [[f32; 4]; 16],
    }
}

impl EnvUniforms {
    fn new(
        rotation: f32,
        intensity: f32,
        specular_mips: u32,
        radiance_mips: u32,
        sh: &[Vec3],
    ) -> Self {
        let mut padded = [[0f32; 4]; 16];
        for (p, c) in padded.iter_mut().zip(sh) {
            *p = [c.x, c.y, c.z, 0.0];
        }
        EnvUniforms {
            rotation,
            intensity,
            specular_mips: specular_mips as f32,
            radiance_mips: radiance_mips as f32,
            sh: padded,
        }
    }
}

/// GPU resources of one environment.
pub struct GpuEnvironment {
    pub radiance: wgpu::Texture,
    pub radiance_view: wgpu::TextureView,
    pub specular_view: wgpu::TextureView,
    /// The pre-convolved diffuse map, E(n)/π (`Environment::irradiance_map`), lat-long
    /// `IRRADIANCE_SIZE`, unrotated and without intensity like the other textures.
    pub irradiance_view: wgpu::TextureView,
    pub sampler: wgpu::Sampler,
    /// [`EnvUniforms`]: rotation, intensity, mip counts and the SH (env.wgsl's `EnvUniforms`).
    pub uniform_buffer: wgpu::Buffer,
    /// The coefficients in `uniform_buffer`.
    pub sh: Vec<Vec3>,
    pub radiance_mips: u32,
    pub rotation: f32,
    pub intensity: f32,
    /// The CPU map, kept to re-project the SH when the rotation changes.
    source: Environment,
}

impl GpuEnvironment {
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, env: &Environment) -> Self {
        let sh_coeffs = sh::project_environment(env, 16);
        let radiance = radiance_texture(device, queue, env);
        let w = radiance.width();
        let radiance_mips = radiance.mip_level_count();
        let sw = SPECULAR_WIDTH.min(w);
        let sh_ = (sw / 2).max(1);
        let specular = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("env specular"),
            size: wgpu::Extent3d {
                width: sw,
                height: sh_,
                depth_or_array_layers: 1,
            },
            mip_level_count: SPECULAR_LEVELS.min(32 - sh_.leading_zeros()),
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba16Float,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::STORAGE_BINDING,
            view_formats: &[],
        });
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("env sampler"),
            address_mode_u: wgpu::AddressMode::Repeat,
            address_mode_v: wgpu::AddressMode::ClampToEdge,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            mipmap_filter: wgpu::MipmapFilterMode::Linear,
            ..Default::default()
        });
        let radiance_view = radiance.create_view(&Default::default());
        prefilter_chains(
            device,
            queue,
            &radiance,
            &radiance_view,
            &specular,
            &sampler,
        );
        let irradiance = irradiance_texture(device, queue, env);
        let uniforms = EnvUniforms::new(
            env.rotation,
            env.intensity,
            specular.mip_level_count(),
            radiance_mips,
            &sh_coeffs,
        );
        let uniform_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("env uniforms"),
            contents: bytemuck::bytes_of(&uniforms),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        GpuEnvironment {
            irradiance_view: irradiance.create_view(&Default::default()),
            radiance,
            radiance_view,
            specular_view: specular.create_view(&Default::default()),
            sampler,
            uniform_buffer,
            sh: sh_coeffs,
            radiance_mips,
            rotation: env.rotation,
            intensity: env.intensity,
            source: env.clone(),
        }
    }

    /// Turns the environment about +Y: lookups take the new angle from [`EnvUniforms`], the SH
    /// coefficients are re-projected here. Nothing else needs rebuilding.
    pub fn set_rotation(&mut self, queue: &wgpu::Queue, rotation: f32) {
        self.rotation = rotation;
        self.source.rotation = rotation;
        self.write_sh(queue);
    }

    /// Multiplies the radiance by `intensity` (≥ 0): lookups take it from [`EnvUniforms`], the
    /// SH coefficients are re-projected here.
    pub fn set_intensity(&mut self, queue: &wgpu::Queue, intensity: f32) {
        self.intensity = intensity;
        self.source.intensity = intensity;
        self.write_sh(queue);
    }

    fn write_sh(&mut self, queue: &wgpu::Queue) {
        self.sh = sh::project_environment(&self.source, 16);
        queue.write_buffer(
            &self.uniform_buffer,
            0,
            bytemuck::bytes_of(&self.uniforms()),
        );
    }

    /// What `uniform_buffer` holds.
    pub fn uniforms(&self) -> EnvUniforms {
        EnvUniforms::new(
            self.rotation,
            self.intensity,
            self.specular_view.texture().mip_level_count(),
            self.radiance_mips,
            &self.sh,
        )
    }

    /// The CPU map (rotation applied in its `rotation`; raw texels without `intensity`).
    pub fn source(&self) -> &Environment {
        &self.source
    }
}

/// Colours as rgba16float texels (clamped to f16's range, alpha 1).
fn f16_texels(colours: &[Vec3]) -> Vec<u16> {
    colours
        .iter()
        .flat_map(|c| {
            let c = c.min(Vec3::splat(F16_MAX));
            [c.x, c.y, c.z, 1.0].map(|v| half::f16::from_f32(v).to_bits())
        })
        .collect()
}

/// The radiance map with its level 0 uploaded (box-downsampled on the CPU if the map is very
/// wide) and room for a full mip chain.
fn radiance_texture(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    env: &Environment,
) -> wgpu::Texture {
    let (w, h, texels) = env.box_downsampled(MAX_RADIANCE_WIDTH);
    let size = wgpu::Extent3d {
        width: w,
        height: h,
        depth_or_array_layers: 1,
    };
    let radiance = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("env radiance"),
        size,
        mip_level_count: 32 - w.min(h).leading_zeros(),
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba16Float,
        usage: wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::STORAGE_BINDING
            | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    queue.write_texture(
        radiance.as_image_copy(),
        bytemuck::cast_slice(&f16_texels(&texels)),
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(8 * w),
            rows_per_image: Some(h),
        },
        size,
    );
    radiance
}

/// The irradiance map (E(n)/π per direction, equirectangular).
fn irradiance_texture(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    env: &Environment,
) -> wgpu::Texture {
    let (iw, ih) = IRRADIANCE_SIZE;
    device.create_texture_with_data(
        queue,
        &wgpu::TextureDescriptor {
            label: Some("env irradiance map"),
            size: wgpu::Extent3d {
                width: iw,
                height: ih,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba16Float,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        bytemuck::cast_slice(&f16_texels(&env.irradiance_map(iw, ih))),
    )
}

/// Encodes and submits both chains: the radiance map's mips, each downsampled from the one
/// above, and the specular levels, each prefiltered from the radiance map at its roughness.
fn prefilter_chains(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    radiance: &wgpu::Texture,
    radiance_view: &wgpu::TextureView,
    specular: &wgpu::Texture,
    sampler: &wgpu::Sampler,
) {
    let (w, h, radiance_mips) = (
        radiance.width(),
        radiance.height(),
        radiance.mip_level_count(),
    );
    let (sw, sh_, specular_levels) = (
        specular.width(),
        specular.height(),
        specular.mip_level_count(),
    );
    let layout = PrefilterBindings::layout(device);
    let module = crate::pipeline_cache::shader_module(device, "env prefilter", PREFILTER_WGSL);
    let pipeline = |label, entry| {
        crate::pipeline_cache::standalone_pipeline(device, label, &module, entry, &layout)
    };
    let downsample = pipeline("env downsample", "downsample");
    let prefilter = pipeline("env prefilter", "prefilter");
    let mip_view = |t: &wgpu::Texture, level: u32| {
        t.create_view(&wgpu::TextureViewDescriptor {
            base_mip_level: level,
            mip_level_count: Some(1),
            ..Default::default()
        })
    };
    let mut encoder = device.create_command_encoder(&Default::default());
    let mut pass = |pipeline: &wgpu::ComputePipeline,
                    roughness: f32,
                    source: &wgpu::TextureView,
                    destination: &wgpu::TextureView,
                    size: (u32, u32)| {
        let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: None,
            contents: bytemuck::bytes_of(&PrefilterParams {
                roughness,
                source_width: w as f32,
                source_height: h as f32,
                source_mips: radiance_mips as f32,
            }),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let bg = PrefilterBindings {
            params: &params,
            source,
            source_sampler: sampler,
            destination,
        }
        .bind_group(device, &layout);
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(pipeline);
        pass.set_bind_group(1, &bg, &[]);
        let (gx, gy) = util::groups_8x8(size);
        pass.dispatch_workgroups(gx, gy, 1);
    };
    for level in 0..radiance_mips - 1 {
        let (src, dst) = (mip_view(radiance, level), mip_view(radiance, level + 1));
        let size = ((w >> (level + 1)).max(1), (h >> (level + 1)).max(1));
        pass(&downsample, 0.0, &src, &dst, size);
    }
    for level in 0..specular_levels {
        let roughness = level as f32 / (specular_levels - 1).max(1) as f32;
        let size = ((sw >> level).max(1), (sh_ >> level).max(1));
        pass(
            &prefilter,
            roughness,
            radiance_view,
            &mip_view(specular, level),
            size,
        );
    }
    queue.submit([encoder.finish()]);
}
