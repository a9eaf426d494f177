//! The far field on the GPU (the book, "The far field"): the open sky beyond R, or a probe
//! volume baked by `nearfield bake` (`nearfield_scene::probes::ProbeVolume`). Three bindings
//! of group 0 that `shaders/far.wgsl` reads: the probe texture (its row 0 the grid, `FarGrid`),
//! the visibility atlas and the irradiance atlas (`ProbeVolume::irradiance_tile`, for passes
//! that need only E(n)); with the sky they hold one dummy probe and `far_volume()` is false, so
//! every pass computes what it computed before the volume existed.

use bytemuck::{Pod, Zeroable};
use nearfield_scene::probes::{IRR_TILE, ProbeVolume, SH_COEFFS, VIS_TILE};
use wgpu::util::DeviceExt;

/// Texels per probe in the probe texture: (offset xyz, active), the 9 SH coefficients of the
/// radiance, and its visibility within R as 9 scalar SH coefficients in 3 texels.
pub const PROBE_TEXELS: u32 = 1 + SH_COEFFS as u32 + 3;
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

/// What a volume's probe texture is made from, kept to recompute its visibility for another R.
struct VolumeSource {
    volume: std::sync::Arc<ProbeVolume>,
    /// Probes per row of the probe texture.
    row: u32,
    /// The radius of the uploaded visibility (m).
    radius: f32,
}

/// The far field's GPU resources.
pub struct GpuFarField {
    pub mode: FarMode,
    probes_texture: wgpu::Texture,
    volume: Option<VolumeSource>,
    pub probes_view: wgpu::TextureView,
    pub visibility_view: wgpu::TextureView,
    pub irradiance_view: wgpu::TextureView,
    /// Probes in the volume (0 for the sky).
    pub probes: usize,
}

impl GpuFarField {
    /// A probe volume's far field (its visibility within `radius`), or the sky's for `None`.
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        volume: Option<&ProbeVolume>,
        radius: f32,
    ) -> Self {
        match volume {
            Some(v) => Self::volume(device, queue, v, radius),
            None => Self::sky(device, queue),
        }
    }

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

    /// Uploads a baked volume, with its probes' visibility within `radius` (m; the technique's
    /// R, [`Self::set_radius`]).
    pub fn volume(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        v: &ProbeVolume,
        radius: f32,
    ) -> Self {
        let n = v.probes.len() as u32;
        let row = n.clamp(1, MAX_WIDTH / VIS_TILE);
        let probes = probe_texels(v, row, radius);
        let vis_tile = (VIS_TILE * VIS_TILE) as usize;
        let (vis, (aw, ah)) = atlas::<2>(v.probes.len(), row, VIS_TILE, |i, tiles| {
            for (k, texel) in tiles.iter_mut().enumerate() {
                *texel = v.visibility[i * vis_tile + k];
            }
        });
        let (irr, (iw, ih)) = atlas::<4>(v.probes.len(), row, IRR_TILE, |i, tiles| {
            for (texel, e) in tiles.iter_mut().zip(v.irradiance_tile(i)) {
                *texel = [e.x, e.y, e.z, 0.0];
            }
        });
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
        let mut far = Self::upload(
            device,
            queue,
            FarMode::Volume,
            uniforms,
            &probes,
            row * PROBE_TEXELS,
            (&vis, (aw, ah)),
            (&irr, (iw, ih)),
            v.probes.len(),
        );
        far.volume = Some(VolumeSource {
            volume: std::sync::Arc::new(v.clone()),
            row,
            radius,
        });
        far
    }

    /// Recomputes the probes' visibility within `radius` (m) when it changed: what AO-only
    /// techniques divide by (far.wgsl's far_ao_at). Nothing for the sky.
    pub fn set_radius(&mut self, queue: &wgpu::Queue, radius: f32) {
        let Some(src) = &mut self.volume else {
            return;
        };
        if src.radius == radius || !radius.is_finite() {
            return;
        }
        src.radius = radius;
        let texels = probe_texels(&src.volume, src.row, radius);
        let width = src.row * PROBE_TEXELS;
        queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &self.probes_texture,
                mip_level: 0,
                // Row 0 holds the grid; the probes start at row 1.
                origin: wgpu::Origin3d { x: 0, y: 1, z: 0 },
                aspect: wgpu::TextureAspect::All,
            },
            bytemuck::cast_slice(&texels),
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(width * 16),
                rows_per_image: None,
            },
            wgpu::Extent3d {
                width,
                height: texels.len() as u32 / width,
                depth_or_array_layers: 1,
            },
        );
    }

    /// The radius the probes' visibility was computed for (None for the sky).
    pub fn radius(&self) -> Option<f32> {
        self.volume.as_ref().map(|s| s.radius)
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
            device.create_texture_with_data(
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
                    usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
                    view_formats: &[],
                },
                wgpu::util::TextureDataOrder::LayerMajor,
                data,
            )
        };
        let bits = |h: &[half::f16]| -> Vec<u16> { h.iter().map(|h| h.to_bits()).collect() };
        let probes_texture = texture(
            "far probes",
            probes_size,
            wgpu::TextureFormat::Rgba32Float,
            bytemuck::cast_slice(&texels),
        );
        let view = |t: wgpu::Texture| t.create_view(&Default::default());
        GpuFarField {
            mode,
            probes_view: probes_texture.create_view(&Default::default()),
            probes_texture,
            volume: None,
            visibility_view: view(texture(
                "far visibility",
                vis_size,
                wgpu::TextureFormat::Rg16Float,
                bytemuck::cast_slice(&bits(vis)),
            )),
            irradiance_view: view(texture(
                "far irradiance",
                irr_size,
                wgpu::TextureFormat::Rgba16Float,
                bytemuck::cast_slice(&bits(irr)),
            )),
            probes: count,
        }
    }
}

/// The probe texture's rows after row 0: per probe (offset, active), its 9 SH coefficients and
/// its visibility within `radius` as 9 scalar SH coefficients in 3 texels, `row` probes a row.
fn probe_texels(v: &ProbeVolume, row: u32, radius: f32) -> Vec<[f32; 4]> {
    let n = v.probes.len() as u32;
    let rows = n.div_ceil(row);
    let mut probes = vec![[0f32; 4]; (row * PROBE_TEXELS * rows) as usize];
    let vis_sh = v.visibility_sh(radius);
    for (i, (p, a)) in v.probes.iter().zip(&vis_sh).enumerate() {
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
        for k in 0..3 {
            probes[start + 1 + SH_COEFFS + k] = [a[3 * k], a[3 * k + 1], a[3 * k + 2], 0.0];
        }
    }
    probes
}

/// An f16 atlas of `count` square tiles of `tile` texels a side, `row` tiles per row (texel
/// rows top to bottom); `fill(i, texels)` writes probe i's tile, row-major. Returns the texels
/// (C channels each) and the atlas size.
fn atlas<const C: usize>(
    count: usize,
    row: u32,
    tile: u32,
    fill: impl Fn(usize, &mut [[f32; C]]),
) -> (Vec<half::f16>, (u32, u32)) {
    let (w, h) = (row * tile, (count as u32).div_ceil(row).max(1) * tile);
    let mut out = vec![half::f16::ZERO; (w * h) as usize * C];
    let mut texels = vec![[0f32; C]; (tile * tile) as usize];
    for i in 0..count {
        fill(i, &mut texels);
        let (tx, ty) = ((i as u32 % row) * tile, (i as u32 / row) * tile);
        for (k, texel) in texels.iter().enumerate() {
            let (x, y) = (k as u32 % tile, k as u32 / tile);
            let at = (((ty + y) * w + tx + x) as usize) * C;
            for (o, &c) in out[at..at + C].iter_mut().zip(texel) {
                *o = half::f16::from_f32(c);
            }
        }
    }
    (out, (w, h))
}

#[cfg(test)]
mod tests {
    use super::*;
    use nearfield_scene::probes::{IRR_RES, VIS_RES};

    /// far.wgsl's layout constants are the Rust ones (and env.wgsl's irradiance map rows).
    #[test]
    fn far_wgsl_constants_match_the_volume_layout() {
        let constant = |source: &str, name: &str| -> f32 {
            let line = source
                .lines()
                .find(|l| l.starts_with(&format!("const {name}:")))
                .unwrap_or_else(|| panic!("the WGSL declares {name}"));
            let v = line.split('=').nth(1).unwrap().trim().trim_end_matches(';');
            v.trim_end_matches('u').parse().unwrap()
        };
        let value = |name: &str| constant(crate::util::FAR_WGSL, name);
        assert_eq!(value("FAR_TEXELS"), PROBE_TEXELS as f32);
        assert_eq!(value("FAR_VIS_RES"), VIS_RES as f32);
        assert_eq!(value("FAR_TILE"), VIS_TILE as f32);
        assert_eq!(value("FAR_IRR_RES"), IRR_RES as f32);
        assert_eq!(value("FAR_IRR_TILE"), IRR_TILE as f32);
        assert_eq!(
            constant(crate::util::ENV_WGSL, "ENV_IRRADIANCE_ROWS"),
            crate::gpu_env::IRRADIANCE_SIZE.1 as f32
        );
    }
}
