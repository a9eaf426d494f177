//! The glue's pipelines, made once on Bevy's device, and the declarations of its uniform and
//! bind groups (checked against glue.wgsl by naga: the test below).

use bevy::prelude::*;
use bevy::render::renderer::{RenderAdapter, RenderDevice};
use nearfield_render::bindings::kind;
use nearfield_render::wgpu;

pub(super) const GLUE: &str = include_str!("../glue.wgsl");

nearfield_render::gpu_struct! {
    /// The glue's uniform (`Glue` in glue.wgsl).
    pub struct Glue {
        pub view_from_clip: [[f32; 4]; 4],
        pub previous_clip_from_view: [[f32; 4]; 4],
        pub size: [f32; 2],
        pub has_motion: u32,
        pub indirect_intensity: f32,
        pub ambient_occlusion: u32,
        pub far_rule: u32,
        pub has_gbuffer: u32,
        pub _pad: u32,
    }
}

nearfield_render::bind_group! {
    /// Group 0 of every glue pass.
    pub struct GlueBindings: FRAGMENT | COMPUTE {
        /// [`Glue`].
        glue: buffer = kind::UNIFORM,
    }
}

nearfield_render::bind_group! {
    /// Group 1 of `fs_inputs`: Bevy's prepass images.
    pub struct InputsBindings: FRAGMENT {
        /// Bevy's depth prepass (reverse-z).
        bevy_depth: view = kind::TEXTURE_UNFILTERABLE,
        /// Bevy's normal prepass (rgb10a2unorm).
        bevy_normal: view = kind::TEXTURE_UNFILTERABLE,
        /// Bevy's motion vectors (rg16float), or any image where there are none.
        bevy_motion: view = kind::TEXTURE_UNFILTERABLE,
        /// Bevy's lit colour of the frame before, a = its view depth (`fs_capture`'s).
        captured: view = kind::TEXTURE_UNFILTERABLE,
    }
}

nearfield_render::bind_group! {
    /// Group 1 of `fs_capture`: Bevy's lit colour and nearfield's view depth of the frame.
    pub struct CaptureBindings: FRAGMENT {
        bevy_colour: view = kind::TEXTURE_UNFILTERABLE,
        view_depth: view = kind::TEXTURE_UNFILTERABLE,
    }
}

nearfield_render::bind_group! {
    /// Group 1 of `fs_add_indirect`: Bevy's deferred G-buffer and nearfield's indirect light.
    pub struct AddBindings: FRAGMENT {
        /// Bevy's deferred G-buffer (rgba32uint).
        bevy_gbuffer: view = kind::TEXTURE_UINT,
        /// nearfield's indirect-irradiance (rgba16float).
        indirect_irradiance: view = kind::TEXTURE_UNFILTERABLE,
    }
}

nearfield_render::bind_group! {
    /// Group 1 of `cs_ao`: nearfield's ao into Bevy's ao image (whose format the adapter
    /// decides: [`ao_layout`]), with what the far rule reads of the pixel.
    pub struct AoBindings: COMPUTE {
        near_field_ao: view = kind::TEXTURE_UNFILTERABLE,
        bevy_ao: view = kind::write(wgpu::TextureFormat::R16Float),
        /// nearfield's view depth and world normal (the inputs pass's).
        ao_view_depth: view = kind::TEXTURE_UNFILTERABLE,
        ao_normal: view = kind::TEXTURE_UNFILTERABLE,
        /// The technique's env-irradiance, or any image where it writes none.
        ao_env_irradiance: view = kind::TEXTURE_UNFILTERABLE,
        /// Bevy's deferred G-buffer, or [`GluePipelines::no_gbuffer`].
        ao_gbuffer: view = kind::TEXTURE_UINT,
    }
}

nearfield_render::bind_group! {
    /// Group 2 of `cs_ao`: nearfield's view of the frame and the far field the technique read
    /// (the sky's or a baked volume's, `GpuFarField`), with the environment's sampler.
    pub struct FarBindings: COMPUTE {
        ao_cam: buffer = kind::UNIFORM,
        ao_far_probes: view = kind::TEXTURE_UNFILTERABLE,
        ao_far_visibility: view = kind::TEXTURE,
        ao_far_atlas: view = kind::TEXTURE,
        ao_far_sampler: sampler = kind::SAMPLER,
        /// The technique's `EnvUniforms` (its SH: the environment's unoccluded E/π).
        ao_env: buffer = kind::UNIFORM,
    }
}

nearfield_render::gpu_struct! {
    /// `EnvRead` in glue.wgsl: how `cs_env` reads a view's environment map.
    pub struct EnvRead {
        /// Direction in the cube of a world direction (Bevy's lookup).
        pub cube_from_world: [[f32; 4]; 4],
        /// The lat-long map's size.
        pub size: [f32; 2],
        pub _pad: [f32; 2],
    }
}

nearfield_render::bind_group! {
    /// Group 1 of `cs_env` (group 0 is not used): a view's environment map into a lat-long map.
    pub struct EnvReadBindings: COMPUTE {
        /// [`EnvRead`].
        env_read: buffer = kind::UNIFORM,
        /// The environment map's radiance cube.
        env_cube: view = kind::TEXTURE_CUBE,
        env_cube_sampler: sampler = kind::SAMPLER,
        /// The lat-long map (rgba32float).
        env_latlong: view = kind::write(wgpu::TextureFormat::Rgba32Float),
    }
}

/// [`AoBindings`]' layout with Bevy's ao image in `format`.
fn ao_layout(device: &wgpu::Device, format: wgpu::TextureFormat) -> wgpu::BindGroupLayout {
    let mut slots = AoBindings::SLOTS.to_vec();
    slots[1].1 = kind::write(format);
    nearfield_render::bindings::layout(device, "AoBindings", &slots, AoBindings::STAGES)
}

/// The section of the glue that reads nearfield's far field ([`glue_section`]).
pub(super) const AO_SECTION: usize = 4;
/// The section that reads a view's environment map.
const ENV_SECTION: usize = 5;

/// The glue shader's header (the `Glue` uniform, the full-screen triangle) with one of its
/// sections (split at the lines that start with `// --- `); the ao section after nearfield's
/// libraries common.wgsl, env.wgsl and far.wgsl, whose far-field lookups it makes.
pub(super) fn glue_section(index: usize, ao_format: &str) -> String {
    use nearfield_render::util::{COMMON_WGSL, ENV_WGSL, FAR_WGSL};
    let sections: Vec<&str> = GLUE.split("\n// --- ").collect();
    let libraries = if index == AO_SECTION {
        format!("{COMMON_WGSL}\n{ENV_WGSL}\n{FAR_WGSL}\n")
    } else {
        String::new()
    };
    format!("{libraries}{}\n// --- {}", sections[0], sections[index])
        .replace("AO_FORMAT", ao_format)
}

/// The glue's pipelines, made once on Bevy's device.
#[derive(Resource)]
pub(crate) struct GluePipelines {
    pub glue_layout: wgpu::BindGroupLayout,
    pub inputs_layout: wgpu::BindGroupLayout,
    pub inputs: wgpu::RenderPipeline,
    pub capture_layout: wgpu::BindGroupLayout,
    /// Into the captured colour (rgba16float).
    pub capture: wgpu::RenderPipeline,
    pub add_layout: wgpu::BindGroupLayout,
    /// The additive pass, by Bevy's main-texture format (hdr and not).
    pub add: Vec<(wgpu::TextureFormat, wgpu::RenderPipeline)>,
    pub ao_layout: wgpu::BindGroupLayout,
    pub far_layout: wgpu::BindGroupLayout,
    pub ao: wgpu::ComputePipeline,
    /// A 1×1 rgba32uint image bound where Bevy's G-buffer is not (`has_gbuffer` = 0).
    pub no_gbuffer: nearfield_render::targets::Target,
    pub env_layout: wgpu::BindGroupLayout,
    /// A view's environment map into a lat-long map (render/environment.rs).
    pub env: wgpu::ComputePipeline,
    /// Bilinear, clamped: how `cs_env` samples the cube.
    pub env_sampler: wgpu::Sampler,
}

/// A full-screen triangle's pipeline over the glue's group and `groups[1]`, with fragment
/// `entry` of `module` into `targets`.
fn fullscreen_pipeline(
    device: &wgpu::Device,
    label: &str,
    module: &wgpu::ShaderModule,
    entry: &str,
    groups: [&wgpu::BindGroupLayout; 2],
    targets: &[Option<wgpu::ColorTargetState>],
) -> wgpu::RenderPipeline {
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(label),
        bind_group_layouts: &[Some(groups[0]), Some(groups[1])],
        immediate_size: 0,
    });
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(label),
        layout: Some(&pipeline_layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some("vs_fullscreen"),
            compilation_options: Default::default(),
            buffers: &[],
        },
        primitive: Default::default(),
        depth_stencil: None,
        multisample: Default::default(),
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            targets,
        }),
        multiview_mask: None,
        cache: None,
    })
}

impl FromWorld for GluePipelines {
    fn from_world(world: &mut World) -> Self {
        let device = world.resource::<RenderDevice>().wgpu_device().clone();
        let adapter = world.resource::<RenderAdapter>();
        // The format Bevy's SSAO gives its ao image (bevy_pbr's ssao: r16float where the adapter
        // can store to it, else r32float).
        let ao_format = if adapter
            .get_texture_format_features(wgpu::TextureFormat::R16Float)
            .allowed_usages
            .contains(wgpu::TextureUsages::STORAGE_BINDING)
        {
            wgpu::TextureFormat::R16Float
        } else {
            wgpu::TextureFormat::R32Float
        };
        let glue_layout = GlueBindings::layout(&device);
        let inputs_layout = InputsBindings::layout(&device);
        let capture_layout = CaptureBindings::layout(&device);
        let add_layout = AddBindings::layout(&device);
        let ao_layout = ao_layout(&device, ao_format);
        let far_layout = FarBindings::layout(&device);
        let module = |label, index| {
            let format = match ao_format {
                wgpu::TextureFormat::R16Float => "r16float",
                _ => "r32float",
            };
            device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(label),
                source: wgpu::ShaderSource::Wgsl(glue_section(index, format).into()),
            })
        };
        let raster = |label, index, entry, group: &wgpu::BindGroupLayout, targets: &[_]| {
            let m = module(label, index);
            fullscreen_pipeline(&device, label, &m, entry, [&glue_layout, group], targets)
        };
        use wgpu::TextureFormat as F;
        let inputs = raster(
            "nearfield glue inputs",
            1,
            "fs_inputs",
            &inputs_layout,
            &[
                Some(F::R32Float.into()),
                Some(F::Rgba16Float.into()),
                Some(F::Rg16Float.into()),
                Some(F::Rgba16Float.into()),
            ],
        );
        let capture = raster(
            "nearfield glue capture",
            2,
            "fs_capture",
            &capture_layout,
            &[Some(F::Rgba16Float.into())],
        );
        let additive = wgpu::BlendState {
            color: wgpu::BlendComponent {
                src_factor: wgpu::BlendFactor::One,
                dst_factor: wgpu::BlendFactor::One,
                operation: wgpu::BlendOperation::Add,
            },
            alpha: wgpu::BlendComponent {
                src_factor: wgpu::BlendFactor::Zero,
                dst_factor: wgpu::BlendFactor::One,
                operation: wgpu::BlendOperation::Add,
            },
        };
        let add = [F::Rgba16Float, F::Rgba8UnormSrgb]
            .into_iter()
            .map(|format| {
                let p = raster(
                    "nearfield glue add indirect",
                    3,
                    "fs_add_indirect",
                    &add_layout,
                    &[Some(wgpu::ColorTargetState {
                        format,
                        blend: Some(additive),
                        write_mask: wgpu::ColorWrites::ALL,
                    })],
                );
                (format, p)
            })
            .collect();
        let ao_module = module("nearfield glue ao", AO_SECTION);
        let ao_pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("nearfield glue ao"),
            bind_group_layouts: &[Some(&glue_layout), Some(&ao_layout), Some(&far_layout)],
            immediate_size: 0,
        });
        let no_gbuffer = nearfield_render::targets::Target::new(
            &device,
            "nearfield no G-buffer",
            (1, 1),
            F::Rgba32Uint,
            wgpu::TextureUsages::TEXTURE_BINDING,
        );
        let ao = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("nearfield glue ao"),
            layout: Some(&ao_pipeline_layout),
            module: &ao_module,
            entry_point: Some("cs_ao"),
            compilation_options: Default::default(),
            cache: None,
        });
        let env_layout = EnvReadBindings::layout(&device);
        let env_module = module("nearfield glue environment", ENV_SECTION);
        let env_pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("nearfield glue environment"),
            bind_group_layouts: &[None, Some(&env_layout)],
            immediate_size: 0,
        });
        let env = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("nearfield glue environment"),
            layout: Some(&env_pipeline_layout),
            module: &env_module,
            entry_point: Some("cs_env"),
            compilation_options: Default::default(),
            cache: None,
        });
        let env_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("nearfield glue environment"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        GluePipelines {
            env_layout,
            env,
            env_sampler,
            glue_layout,
            inputs_layout,
            inputs,
            capture_layout,
            capture,
            add_layout,
            add,
            ao_layout,
            far_layout,
            ao,
            no_gbuffer,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The glue's sections: (entry point, section index) of each program.
    const SECTIONS: [(&str, usize); 5] = [
        ("fs_inputs", 1),
        ("fs_capture", 2),
        ("fs_add_indirect", 3),
        ("cs_ao", AO_SECTION),
        ("cs_env", ENV_SECTION),
    ];

    /// Each section's bindings and the `Glue` uniform agree with their declarations here.
    #[test]
    fn the_glue_declarations_agree_with_glue_wgsl() {
        let own: [&[(&str, nearfield_render::bindings::Slot)]; 5] = [
            InputsBindings::SLOTS,
            CaptureBindings::SLOTS,
            AddBindings::SLOTS,
            AoBindings::SLOTS,
            EnvReadBindings::SLOTS,
        ];
        let mut errors = Vec::new();
        for ((entry, index), group1) in SECTIONS.into_iter().zip(own) {
            let source = glue_section(index, "r16float");
            let far: &[_] = if index == AO_SECTION {
                FarBindings::SLOTS
            } else {
                &[]
            };
            let groups: Vec<_> = [GlueBindings::SLOTS, group1, far]
                .into_iter()
                .filter(|g| !g.is_empty())
                .collect();
            errors.extend(nearfield_render::reflect::group_mismatches(
                entry, &source, entry, &groups,
            ));
            errors.extend(nearfield_render::reflect::struct_mismatches(
                &source,
                "Glue",
                std::mem::size_of::<Glue>(),
                Glue::FIELDS,
            ));
        }
        errors.extend(nearfield_render::reflect::struct_mismatches(
            &glue_section(ENV_SECTION, "r16float"),
            "EnvRead",
            std::mem::size_of::<EnvRead>(),
            EnvRead::FIELDS,
        ));
        assert!(errors.is_empty(), "{}", errors.join("\n"));
        // The check fails where the WGSL and the declaration part.
        let renamed = glue_section(1, "r16float").replace("bevy_normal", "bevy_normals");
        let errors = nearfield_render::reflect::group_mismatches(
            "fs_inputs",
            &renamed,
            "fs_inputs",
            &[GlueBindings::SLOTS, InputsBindings::SLOTS],
        );
        assert!(!errors.is_empty());
    }
}
