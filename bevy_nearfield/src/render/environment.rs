//! The view's own environment map as the technique's sky, where there is no baked volume
//! (docs/src/bevy.md, "The far field"): the radiance of the camera's `EnvironmentMapLight` (its
//! specular map's sharpest level) or the source cube of its `GeneratedEnvironmentMapLight`, read
//! once from Bevy's GPU image into a lat-long map in nearfield's convention, at the light's
//! intensity and rotation. The technique then finds that light in the directions it finds free,
//! and the ao pass keeps of Bevy's environment light the share that reaches the point through
//! them (glue.wgsl, `FAR_REPLACE_SKY`). An atmosphere's map, drawn anew by Bevy as the sun
//! moves, is not read (the technique sees a white sky).

use super::pipelines::{EnvRead, EnvReadBindings, GluePipelines};
use bevy::light::{
    AtmosphereEnvironmentMapLight, EnvironmentMapLight, GeneratedEnvironmentMapLight,
};
use bevy::prelude::*;
use bevy::render::texture::GpuImage;
use nearfield_render::wgpu;
use nearfield_scene::Environment;

/// The lat-long map's size: 0.7° texels, each the mean of 4 × 4 taps of the cube (glue.wgsl's
/// `cs_env`), as fine as nearfield's own maps are read for diffuse light.
pub(crate) const LATLONG: (u32, u32) = (512, 256);

/// What the render world knows of a camera's environment map: the radiance cube, its
/// intensity (cd/m² per unit of the map) and its rotation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewEnvironment {
    pub image: AssetId<Image>,
    pub intensity: f32,
    pub rotation: Quat,
}

impl ViewEnvironment {
    /// The camera's environment map, if it has one that gives light and is not an
    /// atmosphere's: a generated one's source cube (its filtered maps are written on the GPU
    /// later), else the specular map of an `EnvironmentMapLight` (level 0: the radiance itself).
    pub(crate) fn of_camera(
        light: Option<&EnvironmentMapLight>,
        generated: Option<&GeneratedEnvironmentMapLight>,
        atmosphere: Option<&AtmosphereEnvironmentMapLight>,
    ) -> Option<Self> {
        if atmosphere.is_some() {
            return None;
        }
        let (image, intensity, rotation) = match (generated, light) {
            (Some(g), _) => (g.environment_map.id(), g.intensity, g.rotation),
            (None, Some(l)) => (l.specular_map.id(), l.intensity, l.rotation),
            (None, None) => return None,
        };
        (intensity.is_finite() && intensity > 0.0).then_some(ViewEnvironment {
            image,
            intensity,
            rotation,
        })
    }

    /// Bevy's lookup of world direction d: the map's rotation undone, z negated (cube maps are
    /// left-handed; bevy_pbr's environment_map.wesl).
    fn cube_from_world(&self) -> Mat4 {
        Mat4::from_scale(Vec3::new(1.0, 1.0, -1.0)) * Mat4::from_quat(self.rotation.inverse())
    }

    /// Reads the cube in `image` into nearfield's environment (raw texels, `intensity` beside
    /// them). Refused: an image that is not a cube of six faces, or whose format cannot be
    /// filtered, or that reads black (a map not drawn yet).
    pub(super) fn read(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        pipelines: &GluePipelines,
        image: &GpuImage,
    ) -> Result<Environment, String> {
        let texture: &wgpu::Texture = &image.texture;
        if texture.dimension() != wgpu::TextureDimension::D2 || texture.depth_or_array_layers() != 6
        {
            return Err(format!(
                "its environment map is not a cube ({}×{}×{})",
                texture.width(),
                texture.height(),
                texture.depth_or_array_layers()
            ));
        }
        let format = texture.format();
        if format.sample_type(None, Some(device.features()))
            != Some(wgpu::TextureSampleType::Float { filterable: true })
        {
            return Err(format!(
                "its environment map's format {format:?} cannot be filtered"
            ));
        }
        let cube = texture.create_view(&wgpu::TextureViewDescriptor {
            label: Some("nearfield environment cube"),
            dimension: Some(wgpu::TextureViewDimension::Cube),
            base_mip_level: 0,
            mip_level_count: Some(1),
            base_array_layer: 0,
            array_layer_count: Some(6),
            ..Default::default()
        });
        let (w, h) = LATLONG;
        let latlong = nearfield_render::targets::Target::new(
            device,
            "nearfield environment lat-long",
            (w, h),
            wgpu::TextureFormat::Rgba32Float,
            wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::COPY_SRC,
        );
        let uniforms = EnvRead {
            cube_from_world: self.cube_from_world().to_cols_array_2d(),
            size: [w as f32, h as f32],
            _pad: [0.0; 2],
        };
        let buffer = wgpu::util::DeviceExt::create_buffer_init(
            device,
            &wgpu::util::BufferInitDescriptor {
                label: Some("nearfield environment read"),
                contents: bytemuck::bytes_of(&uniforms),
                usage: wgpu::BufferUsages::UNIFORM,
            },
        );
        let group = EnvReadBindings {
            env_read: &buffer,
            env_cube: &cube,
            env_cube_sampler: &pipelines.env_sampler,
            env_latlong: &latlong.view,
        }
        .bind_group(device, &pipelines.env_layout);
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(&pipelines.env);
            pass.set_bind_group(1, &group, &[]);
            let (gx, gy) = nearfield_render::util::groups_8x8((w, h));
            pass.dispatch_workgroups(gx, gy, 1);
        }
        let bytes =
            nearfield_render::util::read_texture(device, queue, encoder, &latlong.texture, 16);
        let texels: Vec<glam::Vec3> = bytes
            .chunks_exact(16)
            .map(|t| {
                let c = |k: usize| f32::from_le_bytes(t[4 * k..4 * k + 4].try_into().unwrap());
                glam::Vec3::new(c(0), c(1), c(2))
            })
            .collect();
        if let Some(bad) = texels
            .iter()
            .find(|t| !t.is_finite() || t.min_element() < 0.0)
        {
            return Err(format!(
                "its environment map holds a texel of {bad} (not a finite radiance ≥ 0)"
            ));
        }
        if texels.iter().all(|t| *t == glam::Vec3::ZERO) {
            return Err("its environment map reads black".into());
        }
        Ok(Environment {
            name: "Bevy's environment map".into(),
            width: w,
            height: h,
            texels,
            rotation: 0.0,
            intensity: self.intensity,
            sun: None,
        })
    }
}
