//! Screen-sized render targets of one frame. Every screen-space pass reads and writes these; the
//! formats here are the contract with the shaders.

use crate::RenderError;
use crate::contract::io::{NearFieldInputs, NearFieldOutputs};

pub use crate::contract::formats::*;

/// A texture and its full view.
pub struct Target {
    pub texture: wgpu::Texture,
    pub view: wgpu::TextureView,
}

impl Target {
    pub fn new(
        device: &wgpu::Device,
        label: &str,
        size: (u32, u32),
        format: wgpu::TextureFormat,
        usage: wgpu::TextureUsages,
    ) -> Self {
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width: size.0,
                height: size.1,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage,
            view_formats: &[],
        });
        let view = texture.create_view(&Default::default());
        Target { texture, view }
    }
}

/// All screen-sized targets.
pub struct FrameTargets {
    pub size: (u32, u32),
    // G-buffer (raster).
    pub normal: Target,
    pub albedo: Target,
    pub material: Target,
    pub emissive: Target,
    pub motion: Target,
    pub view_depth: Target,
    pub depth: Target,
    // Direct lighting.
    pub light_irradiance: Target,
    pub specular: Target,
    /// Ping-pong pair: frame i writes `direct_radiance[i % 2]` and can read last frame's from
    /// the other one.
    pub direct_radiance: [Target; 2],
    /// The far field at each surface point (rgba16float): rgb its unoccluded E(n)/π, a its own
    /// visibility within R (1 for the sky), what composite and aov count the techniques' near
    /// field against (passes/irradiance_terms.wgsl).
    pub far_field: Target,
    // Near-field technique outputs.
    pub ao: Target,
    pub env_irradiance: Target,
    pub indirect_irradiance: Target,
    // Composite, tonemap, readback.
    pub radiance: Target,
    pub final_ldr: Target,
    pub aov: Target,
}

/// GPU memory per pixel a frame may take: the frame targets (≈ 116 bytes) and the most a
/// technique adds (history, layers, denoiser: up to ≈ 400 bytes), rounded up.
pub const BYTES_PER_PIXEL: u64 = 512;

/// Memory the system offers a CPU adapter (lavapipe allocates from it): `MemAvailable` of
/// /proc/meminfo, where there is one.
fn available_system_memory() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

/// Checks that an image of `size` fits the memory of a CPU adapter (whose textures live in
/// system memory, where running out ends the process rather than failing an allocation).
/// Other adapters report running out as an error when the targets are made.
pub fn check_memory(size: (u32, u32), device_type: wgpu::DeviceType) -> Result<(), RenderError> {
    if device_type != wgpu::DeviceType::Cpu {
        return Ok(());
    }
    let need = size.0 as u64 * size.1 as u64 * BYTES_PER_PIXEL;
    if let Some(available) = available_system_memory()
        && need > available / 10 * 8
    {
        return Err(RenderError::Memory(format!(
            "image size {}×{}: needs about {} MiB of GPU memory, more than the {} MiB this CPU \
             adapter can take (80 % of the available system memory)",
            size.0,
            size.1,
            need >> 20,
            (available / 10 * 8) >> 20
        )));
    }
    Ok(())
}

/// Checks an image size before anything is allocated.
pub fn check_size(size: (u32, u32), device_max: u32) -> Result<(), RenderError> {
    let (width, height) = size;
    let limit = MAX_SIZE.min(device_max);
    if width == 0 || height == 0 {
        return Err(RenderError::Size {
            width,
            height,
            why: "both sides must be at least 1".into(),
        });
    }
    if width > limit || height > limit {
        return Err(RenderError::Size {
            width,
            height,
            why: format!("the largest side supported is {limit}"),
        });
    }
    Ok(())
}

impl FrameTargets {
    /// The near-field techniques' inputs, from these targets.
    pub fn near_field_inputs(&self) -> NearFieldInputs<'_> {
        NearFieldInputs {
            size: self.size,
            view_depth: &self.view_depth.view,
            normal: &self.normal.view,
            albedo: &self.albedo.view,
            material: &self.material.view,
            emission: &self.emissive.view,
            direct_radiance: [&self.direct_radiance[0].view, &self.direct_radiance[1].view],
            motion: &self.motion.view,
            depth: Some(&self.depth.view),
        }
    }

    /// The near-field techniques' outputs, into these targets.
    pub fn near_field_outputs(&self) -> NearFieldOutputs<'_> {
        NearFieldOutputs {
            ao: &self.ao.view,
            // Nothing of nearfield's frame reads a bent normal (gtao's, hbil's and vbgi's
            // `bent-cone` history is their debug image of it).
            bent_normal: None,
            env_irradiance: Some(&self.env_irradiance.view),
            indirect_irradiance: Some(&self.indirect_irradiance.view),
            light_irradiance: Some(&self.light_irradiance.view),
        }
    }

    pub fn new(device: &wgpu::Device, size: (u32, u32)) -> Self {
        use wgpu::TextureUsages as U;
        let raster = U::RENDER_ATTACHMENT | U::TEXTURE_BINDING;
        let storage = U::STORAGE_BINDING | U::TEXTURE_BINDING;
        let t = |label: &str, format, usage| Target::new(device, label, size, format, usage);
        FrameTargets {
            size,
            normal: t("gbuffer normal", NORMAL_FORMAT, raster),
            albedo: t("gbuffer albedo", ALBEDO_FORMAT, raster),
            material: t("gbuffer material", MATERIAL_FORMAT, raster),
            emissive: t("gbuffer emissive", EMISSIVE_FORMAT, raster),
            motion: t("gbuffer motion", MOTION_FORMAT, raster),
            view_depth: t("gbuffer view depth", VIEW_DEPTH_FORMAT, raster),
            depth: t(
                "gbuffer depth",
                DEPTH_FORMAT,
                U::RENDER_ATTACHMENT | U::TEXTURE_BINDING,
            ),
            light_irradiance: t("light irradiance", HDR_FORMAT, storage),
            specular: t("specular", HDR_FORMAT, storage),
            direct_radiance: [
                t("direct radiance 0", HDR_FORMAT, storage),
                t("direct radiance 1", HDR_FORMAT, storage),
            ],
            far_field: t("far field", HDR_FORMAT, storage),
            ao: t("ao", AO_FORMAT, storage),
            env_irradiance: t("env irradiance", HDR_FORMAT, storage),
            indirect_irradiance: t("indirect irradiance", HDR_FORMAT, storage),
            radiance: t("radiance", HDR_FORMAT, storage),
            final_ldr: t("final", FINAL_FORMAT, storage | U::COPY_SRC),
            aov: t("aov", AOV_FORMAT, storage | U::COPY_SRC),
        }
    }
}
