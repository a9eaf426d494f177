//! The far field on the GPU (the book, "The far field"): the open sky beyond R, or a probe
//! volume baked by `nearfield bake` (`nearfield_scene::probes::ProbeVolume`). Three bindings
//! of group 0 that `shaders/far.wgsl` reads: the probe texture (its row 0 the grid, `FarGrid`),
//! the visibility atlas and the irradiance atlas (`ProbeVolume::irradiance_tile`, for passes
//! that need only E(n)); with the sky they hold one dummy probe and `far_volume()` is false, so
//! every pass computes what it computed before the volume existed.

use bytemuck::{Pod, Zeroable};
use nearfield_scene::probes::{IRR_TILE, ProbeVolume, SH_COEFFS, VIS_TILE};
use wgpu::util::DeviceExt;

/// Texels per probe in the probe texture: (offset xyz, active) and the 9 SH coefficients.
pub const PROBE_TEXELS: u32 = 1 + SH_COEFFS as u32;
/// Widest texture the far field makes (texels).
const MAX_WIDTH: u32 = 8190;

/// `FarGrid` in far.wgsl and the irradiance atlas's texel size: texels 0..4 of the probe
/// texture's row 0 (counts as floats).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct FarGridUniforms {
    /// xyz: position of probe (0, 0, 0); w: 1 with a volume, 0 for the sky.
    pub origin: [f32; 4],
    /// xyz: spacing (m); w: the lookup's bias (m).
    pub spacing: [f32; 4],
    /// Probes per axis; w: probes per row of both textures (exact as f32 up to 2²⁴).
    pub counts: [f32; 4],
    /// Largest recorded distance (m), 1/atlas width, 1/atlas height, unused.
    pub vis: [f32; 4],
    /// 1 / the irradiance atlas's width and height, unused, unused (texel 4).
    pub irr: [f32; 4],
}

/// Which far field a frame uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum FarMode {
    /// The environment beyond R, unoccluded (each technique's own environment term).
    #[default]
    Sky,
    /// A baked probe volume.
    Volume,
}

/// The far field's GPU resources.
pub struct GpuFarField {
    pub mode: FarMode,
    pub probes_view: wgpu::TextureView,
    pub visibility_view: wgpu::TextureView,
    pub irradiance_view: wgpu::TextureView,
    /// Probes in the volume (0 for the sky).
    pub probes: usize,
}

impl GpuFarField {
    /// The open sky: one dummy probe, `far_volume()` false.
    pub fn sky(device: &wgpu::Device, queue: &wgpu::Queue) -> Self {
        let uniforms = FarGridUniforms {
            origin: [0.0; 4],
            spacing: [1.0, 1.0, 1.0, 0.0],
            counts: [1.0; 4],
            vis: [1.0, 1.0, 1.0, 0.0],
            irr: [1.0, 1.0, 0.0, 0.0],
        };
        let probes = vec![[0f32; 4]; PROBE_TEXELS as usize];
        let vis = vec![half::f16::ZERO; 2];
        let irr = vec![half::f16::ZERO; 4];
        Self::upload(
            device,
            queue,
            FarMode::Sky,
            uniforms,
            &probes,
            PROBE_TEXELS,
            (&vis, (1, 1)),
            (&irr, (1, 1)),
            0,
        )
    }

    /// Uploads a baked volume.
    pub fn volume(device: &wgpu::Device, queue: &wgpu::Queue, v: &ProbeVolume) -> Self {
        let n = v.probes.len() as u32;
        let row = n.clamp(1, MAX_WIDTH / VIS_TILE);
        let rows = n.div_ceil(row);
        let mut probes = vec![[0f32; 4]; (row * PROBE_TEXELS * rows) as usize];
        for (i, p) in v.probes.iter().enumerate() {
            let i = i as u32;
            let start = ((i / row) * row * PROBE_TEXELS + (i % row) * PROBE_TEXELS) as usize;
            probes[start] = [
                p.offset.x,
                p.offset.y,
                p.offset.z,
                if p.active { 1.0 } else { 0.0 },
            ];
            for (k, c) in p.sh.iter().enumerate() {
                probes[start + 1 + k] = [c.x, c.y, c.z, 0.0];
            }
        }
        let (aw, ah) = (row * VIS_TILE, rows * VIS_TILE);
        let mut vis = vec![half::f16::ZERO; (aw * ah * 2) as usize];
        let tile = (VIS_TILE * VIS_TILE) as usize;
        for i in 0..v.probes.len() {
            let (tx, ty) = ((i as u32 % row) * VIS_TILE, (i as u32 / row) * VIS_TILE);
            for y in 0..VIS_TILE {
                for x in 0..VIS_TILE {
                    let m = v.visibility[i * tile + (y * VIS_TILE + x) as usize];
                    let at = (((ty + y) * aw + tx + x) * 2) as usize;
                    vis[at] = half::f16::from_f32(m[0]);
                    vis[at + 1] = half::f16::from_f32(m[1]);
                }
            }
        }
        let (iw, ih) = (row * IRR_TILE, rows * IRR_TILE);
        let mut irr = vec![half::f16::ZERO; (iw * ih * 4) as usize];
        for i in 0..v.probes.len() {
            let (tx, ty) = ((i as u32 % row) * IRR_TILE, (i as u32 / row) * IRR_TILE);
            for (k, e) in v.irradiance_tile(i).into_iter().enumerate() {
                let (x, y) = (k as u32 % IRR_TILE, k as u32 / IRR_TILE);
                let at = (((ty + y) * iw + tx + x) * 4) as usize;
                for c in 0..3 {
                    irr[at + c] = half::f16::from_f32(e[c]);
                }
            }
        }
        let g = &v.grid;
        let uniforms = FarGridUniforms {
            origin: [g.origin.x, g.origin.y, g.origin.z, 1.0],
            spacing: [g.spacing.x, g.spacing.y, g.spacing.z, v.bias()],
            counts: [
                g.counts[0] as f32,
                g.counts[1] as f32,
                g.counts[2] as f32,
                row as f32,
            ],
            vis: [v.max_distance, 1.0 / aw as f32, 1.0 / ah as f32, 0.0],
            irr: [1.0 / iw as f32, 1.0 / ih as f32, 0.0, 0.0],
        };
        Self::upload(
            device,
            queue,
            FarMode::Volume,
            uniforms,
            &probes,
            row * PROBE_TEXELS,
            (&vis, (aw, ah)),
            (&irr, (iw, ih)),
            v.probes.len(),
        )
    }

    #[allow(clippy::too_many_arguments)]
    fn upload(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        mode: FarMode,
        uniforms: FarGridUniforms,
        probes: &[[f32; 4]],
        probes_width: u32,
        (vis, vis_size): (&[half::f16], (u32, u32)),
        (irr, irr_size): (&[half::f16], (u32, u32)),
        count: usize,
    ) -> Self {
        // Row 0: the grid; then the probes.
        let mut texels = vec![[0f32; 4]; probes_width as usize];
        texels[..5].copy_from_slice(&[
            uniforms.origin,
            uniforms.spacing,
            uniforms.counts,
            uniforms.vis,
            uniforms.irr,
        ]);
        texels.extend_from_slice(probes);
        let probes_size = (probes_width, texels.len() as u32 / probes_width);
        let texture = |label, size: (u32, u32), format, data: &[u8]| {
            device
                .create_texture_with_data(
                    queue,
                    &wgpu::TextureDescriptor {
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
                        usage: wgpu::TextureUsages::TEXTURE_BINDING,
                        view_formats: &[],
                    },
                    wgpu::util::TextureDataOrder::LayerMajor,
                    data,
                )
                .create_view(&Default::default())
        };
        let bits = |h: &[half::f16]| -> Vec<u16> { h.iter().map(|h| h.to_bits()).collect() };
        GpuFarField {
            mode,
            probes_view: texture(
                "far probes",
                probes_size,
                wgpu::TextureFormat::Rgba32Float,
                bytemuck::cast_slice(&texels),
            ),
            visibility_view: texture(
                "far visibility",
                vis_size,
                wgpu::TextureFormat::Rg16Float,
                bytemuck::cast_slice(&bits(vis)),
            ),
            irradiance_view: texture(
                "far irradiance",
                irr_size,
                wgpu::TextureFormat::Rgba16Float,
                bytemuck::cast_slice(&bits(irr)),
            ),
            probes: count,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nearfield_scene::probes::{IRR_RES, VIS_RES};

    /// far.wgsl's layout constants are the Rust ones (and env.wgsl's irradiance map rows).
    #[test]
    fn far_wgsl_constants_match_the_volume_layout() {
        let value = |name: &str| -> f32 {
            let line = crate::util::FAR_WGSL
                .lines()
                .find(|l| l.starts_with(&format!("const {name}:")))
                .unwrap_or_else(|| panic!("far.wgsl declares {name}"));
            let v = line.split('=').nth(1).unwrap().trim().trim_end_matches(';');
            v.trim_end_matches('u').parse().unwrap()
        };
        assert_eq!(value("FAR_TEXELS"), PROBE_TEXELS as f32);
        assert_eq!(value("FAR_VIS_RES"), VIS_RES as f32);
        assert_eq!(value("FAR_TILE"), VIS_TILE as f32);
        assert_eq!(value("FAR_IRR_RES"), IRR_RES as f32);
        assert_eq!(value("FAR_IRR_TILE"), IRR_TILE as f32);
        let rows = crate::util::ENV_WGSL
            .lines()
            .find(|l| l.starts_with("const ENV_IRRADIANCE_ROWS:"))
            .and_then(|l| l.split('=').nth(1))
            .map(|v| v.trim().trim_end_matches(';').parse::<f32>().unwrap());
        assert_eq!(rows, Some(crate::gpu_env::IRRADIANCE_SIZE.1 as f32));
    }
}
