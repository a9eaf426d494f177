//! Reading nearfield's images of a view back to the CPU: a camera with [`NearFieldReadback`]
//! gets its ao, indirect irradiance and the radiance it gathered copied inside the frame's own
//! command buffer (a render-graph copy, not a screenshot), then mapped after the frame is
//! submitted. The latest images of each camera are in [`NearFieldImages`]. For tests and tools:
//! it waits for the GPU every frame.

use bevy::ecs::query::QueryItem;
use bevy::prelude::*;
use bevy::render::RenderApp;
use bevy::render::extract_component::{ExtractComponent, ExtractComponentPlugin};
use bevy::render::sync_component::SyncComponent;
use nearfield_render::wgpu;
use std::collections::HashMap;
use std::sync::{Arc, Mutex};

/// Put on a camera with [`crate::NearField`] to have its images read back every frame.
#[derive(Component, Clone, Copy, Debug, Default)]
pub struct NearFieldReadback;

/// One frame's images of a camera (row 0 at the top, `size.0 × size.1` pixels).
#[derive(Clone, Debug, Default)]
pub struct ReadbackImages {
    pub size: (u32, u32),
    /// The frames the view had rendered when these were read (1 = its first).
    pub frames: u32,
    /// `ao`: (1/π) ∫ V_R cos θ dω.
    pub ao: Vec<f32>,
    /// `indirect-irradiance`: (1/π) ∫ (1 − V_R) L_o cos θ dω (rgb; zero where the technique
    /// writes none).
    pub indirect_irradiance: Vec<[f32; 3]>,
    /// `env-irradiance`: (1/π) ∫ V_R L_far cos θ dω, the far field the technique read in the
    /// directions it found free (rgb; zero where it writes none).
    pub env_irradiance: Vec<[f32; 3]>,
    /// Bevy's lit colour of the frame, as kept for the next frame's gathering (rgb).
    pub radiance: Vec<[f32; 3]>,
}

/// The latest images of every camera with [`NearFieldReadback`], by camera entity.
#[derive(Resource, Clone, Default)]
pub struct NearFieldImages(Arc<Mutex<HashMap<Entity, ReadbackImages>>>);

impl NearFieldImages {
    /// Stores the latest images of `camera`.
    pub(crate) fn insert(&self, camera: Entity, images: ReadbackImages) {
        self.0.lock().unwrap().insert(camera, images);
    }

    /// The latest images of `camera`, if any were read.
    pub fn get(&self, camera: Entity) -> Option<ReadbackImages> {
        self.0.lock().unwrap().get(&camera).cloned()
    }
}

#[derive(Component, Clone, Copy)]
pub struct ExtractedReadback;

impl SyncComponent<RenderApp> for NearFieldReadback {
    type Target = ExtractedReadback;
}

impl ExtractComponent<RenderApp> for NearFieldReadback {
    type QueryData = ();
    type QueryFilter = With<NearFieldReadback>;
    type Out = ExtractedReadback;

    fn extract_component(_: QueryItem<'_, '_, Self::QueryData>) -> Option<Self::Out> {
        Some(ExtractedReadback)
    }
}

pub(crate) fn build(app: &mut App) {
    let images = NearFieldImages::default();
    app.insert_resource(images.clone())
        .add_plugins(ExtractComponentPlugin::<NearFieldReadback>::default());
    if let Some(render_app) = app.get_sub_app_mut(RenderApp) {
        render_app.insert_resource(images);
    }
}

/// Four mappable buffers of a view's size.
pub struct ReadbackBuffers {
    size: (u32, u32),
    ao: wgpu::Buffer,
    indirect: wgpu::Buffer,
    env: wgpu::Buffer,
    radiance: wgpu::Buffer,
}

/// Bytes per row of a copy of `width` texels of `bytes` each.
fn padded_row(width: u32, bytes: u32) -> u32 {
    (width * bytes).div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT)
        * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT
}

fn copy_to(
    encoder: &mut wgpu::CommandEncoder,
    texture: &wgpu::Texture,
    buffer: &wgpu::Buffer,
    bytes: u32,
) {
    let (w, h) = (texture.width(), texture.height());
    encoder.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo {
            texture,
            mip_level: 0,
            origin: wgpu::Origin3d::ZERO,
            aspect: wgpu::TextureAspect::All,
        },
        wgpu::TexelCopyBufferInfo {
            buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded_row(w, bytes)),
                rows_per_image: Some(h),
            },
        },
        wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
    );
}

impl ReadbackBuffers {
    /// Records the copies of the ao and the indirect and env irradiance (after the technique)
    /// into the view's buffers, made (again) at the images' size.
    pub(crate) fn copy(
        slot: &Mutex<Option<ReadbackBuffers>>,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        ao: &wgpu::Texture,
        [indirect, env]: [Option<&wgpu::Texture>; 2],
    ) {
        let mut slot = slot.lock().unwrap();
        let size = (ao.width(), ao.height());
        if slot.as_ref().is_none_or(|b| b.size != size) {
            let buffer = |label, bytes| {
                device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(label),
                    size: (padded_row(size.0, bytes) * size.1) as u64,
                    usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
                    mapped_at_creation: false,
                })
            };
            *slot = Some(ReadbackBuffers {
                size,
                ao: buffer("nearfield readback ao", 4),
                indirect: buffer("nearfield readback indirect", 8),
                env: buffer("nearfield readback env", 8),
                radiance: buffer("nearfield readback radiance", 8),
            });
        }
        let b = slot.as_ref().unwrap();
        copy_to(encoder, ao, &b.ao, 4);
        // gtao writes no indirect or env light: those buffers stay zero.
        if let Some(indirect) = indirect {
            copy_to(encoder, indirect, &b.indirect, 8);
        }
        if let Some(env) = env {
            copy_to(encoder, env, &b.env, 8);
        }
    }

    /// Records the copy of the radiance kept for the next frame (after the capture).
    pub(crate) fn copy_radiance(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        texture: &wgpu::Texture,
    ) {
        copy_to(encoder, texture, &self.radiance, 8);
    }

    /// Maps the copies (after the frame is submitted): the images of the view's frame
    /// `frames`.
    pub(crate) fn read(&self, device: &wgpu::Device, frames: u32) -> ReadbackImages {
        let rgb = |buffer| rgb_of_half(&read(device, buffer, self.size, 8));
        ReadbackImages {
            size: self.size,
            frames,
            ao: bytemuck::pod_collect_to_vec(&read(device, &self.ao, self.size, 4)),
            indirect_irradiance: rgb(&self.indirect),
            env_irradiance: rgb(&self.env),
            radiance: rgb(&self.radiance),
        }
    }
}

fn read(device: &wgpu::Device, buffer: &wgpu::Buffer, size: (u32, u32), bytes: u32) -> Vec<u8> {
    let slice = buffer.slice(..);
    let (tx, rx) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    let _ = device.poll(wgpu::PollType::wait_indefinitely());
    if !matches!(rx.recv(), Ok(Ok(()))) {
        return Vec::new();
    }
    let Ok(data) = slice.get_mapped_range() else {
        return Vec::new();
    };
    let row = padded_row(size.0, bytes) as usize;
    let mut out = Vec::with_capacity((size.0 * size.1 * bytes) as usize);
    for y in 0..size.1 as usize {
        out.extend_from_slice(&data[y * row..y * row + (size.0 * bytes) as usize]);
    }
    drop(data);
    buffer.unmap();
    out
}

fn rgb_of_half(bytes: &[u8]) -> Vec<[f32; 3]> {
    bytes
        .chunks_exact(8)
        .map(|p| {
            let c = |i: usize| half::f16::from_le_bytes([p[2 * i], p[2 * i + 1]]).to_f32();
            [c(0), c(1), c(2)]
        })
        .collect()
}
