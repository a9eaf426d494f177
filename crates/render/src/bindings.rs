//! Bindings by name: every pass declares its resources as a struct whose field order is its
//! binding order ([`bind_group!`]), and its WGSL declares the same names at the same numbers.
//!
//! - Group 0 is the frame and the environment ([`FrameBindings`]), the same for every screen
//!   pass and raster pass of a frame; one bind group, built by the renderer.
//! - Group 1 is the pass's own resources, numbered from 0 in declaration order.
//!
//! A CPU test (`tests/bindings.rs`) reflects every pass's WGSL with naga and compares name,
//! group, number, type, format and access of each binding its entry point uses with the
//! struct's [`Slot`]s.

use wgpu::{
    BindGroupLayoutEntry, BindingType, SamplerBindingType, ShaderStages, StorageTextureAccess,
    TextureFormat, TextureSampleType, TextureViewDimension,
};

/// The type of one binding, as its WGSL declares it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Slot {
    /// `var<uniform>`.
    Uniform,
    /// `var<uniform>` bound at a dynamic offset, `size` bytes from it.
    DynamicUniform { size: u64 },
    /// `var<storage, read>` (`read_only`) or `var<storage, read_write>`.
    Storage { read_only: bool },
    /// A sampled texture: `texture_2d<f32>` (float, filterable or not), `texture_2d<u32>`,
    /// `texture_depth_2d`, and their `_array` forms.
    Texture {
        sample: TextureSampleType,
        dimension: TextureViewDimension,
    },
    /// `texture_storage_2d<format, access>` and `texture_storage_2d_array<…>`.
    StorageTexture {
        format: TextureFormat,
        access: StorageTextureAccess,
        dimension: TextureViewDimension,
    },
    /// `sampler` or `sampler_comparison`.
    Sampler(SamplerBindingType),
}

impl Slot {
    /// The layout entry of this slot at `binding`.
    pub fn entry(self, binding: u32, visibility: ShaderStages) -> BindGroupLayoutEntry {
        let ty = match self {
            Slot::Uniform => BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            Slot::DynamicUniform { size } => BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: true,
                min_binding_size: wgpu::BufferSize::new(size),
            },
            Slot::Storage { read_only } => BindingType::Buffer {
                ty: wgpu::BufferBindingType::Storage { read_only },
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            Slot::Texture { sample, dimension } => BindingType::Texture {
                sample_type: sample,
                view_dimension: dimension,
                multisampled: false,
            },
            Slot::StorageTexture {
                format,
                access,
                dimension,
            } => BindingType::StorageTexture {
                access,
                format,
                view_dimension: dimension,
            },
            Slot::Sampler(kind) => BindingType::Sampler(kind),
        };
        BindGroupLayoutEntry {
            binding,
            visibility,
            ty,
            count: None,
        }
    }
}

/// The slots of a binding struct's kinds (used by [`bind_group!`]).
pub mod kind {
    use super::Slot;
    use wgpu::{
        SamplerBindingType as S, StorageTextureAccess as A, TextureFormat, TextureSampleType as T,
        TextureViewDimension as D,
    };

    pub const UNIFORM: Slot = Slot::Uniform;
    /// `var<uniform>` at a dynamic offset (one of several views in one buffer).
    pub const fn uniform_dynamic(size: u64) -> Slot {
        Slot::DynamicUniform { size }
    }
    pub const STORAGE_READ: Slot = Slot::Storage { read_only: true };
    pub const STORAGE_READ_WRITE: Slot = Slot::Storage { read_only: false };
    /// `texture_2d<f32>`, filterable (rgba16float, rgba8unorm).
    pub const TEXTURE: Slot = Slot::Texture {
        sample: T::Float { filterable: true },
        dimension: D::D2,
    };
    /// `texture_2d<f32>` of an unfilterable format (r32float, rgba32float).
    pub const TEXTURE_UNFILTERABLE: Slot = Slot::Texture {
        sample: T::Float { filterable: false },
        dimension: D::D2,
    };
    /// `texture_2d<u32>`.
    pub const TEXTURE_UINT: Slot = Slot::Texture {
        sample: T::Uint,
        dimension: D::D2,
    };
    /// `texture_depth_2d`.
    pub const TEXTURE_DEPTH: Slot = Slot::Texture {
        sample: T::Depth,
        dimension: D::D2,
    };
    /// `texture_2d_array<f32>`, filterable.
    pub const TEXTURE_ARRAY: Slot = Slot::Texture {
        sample: T::Float { filterable: true },
        dimension: D::D2Array,
    };
    /// `texture_2d_array<f32>` of an unfilterable format.
    pub const TEXTURE_ARRAY_UNFILTERABLE: Slot = Slot::Texture {
        sample: T::Float { filterable: false },
        dimension: D::D2Array,
    };
    /// `texture_cube<f32>`, filterable.
    pub const TEXTURE_CUBE: Slot = Slot::Texture {
        sample: T::Float { filterable: true },
        dimension: D::Cube,
    };
    /// `texture_depth_2d_array`.
    pub const TEXTURE_DEPTH_ARRAY: Slot = Slot::Texture {
        sample: T::Depth,
        dimension: D::D2Array,
    };
    pub const SAMPLER: Slot = Slot::Sampler(S::Filtering);
    pub const SAMPLER_COMPARISON: Slot = Slot::Sampler(S::Comparison);

    /// `texture_storage_2d<format, write>`.
    pub const fn write(format: TextureFormat) -> Slot {
        Slot::StorageTexture {
            format,
            access: A::WriteOnly,
            dimension: D::D2,
        }
    }
    /// `texture_storage_2d_array<format, write>`.
    pub const fn write_array(format: TextureFormat) -> Slot {
        Slot::StorageTexture {
            format,
            access: A::WriteOnly,
            dimension: D::D2Array,
        }
    }
}

/// The Rust type a binding field holds, by the resource its slot takes.
#[macro_export]
macro_rules! binding_field_type {
    (buffer, $l:lifetime) => { &$l wgpu::Buffer };
    (buffer_range, $l:lifetime) => { wgpu::BufferBinding<$l> };
    (view, $l:lifetime) => { &$l wgpu::TextureView };
    (sampler, $l:lifetime) => { &$l wgpu::Sampler };
}

/// The [`wgpu::BindingResource`] of a binding field.
#[macro_export]
macro_rules! binding_resource {
    (buffer, $e:expr) => {
        $e.as_entire_binding()
    };
    (buffer_range, $e:expr) => {
        wgpu::BindingResource::Buffer($e.clone())
    };
    (view, $e:expr) => {
        wgpu::BindingResource::TextureView($e)
    };
    (sampler, $e:expr) => {
        wgpu::BindingResource::Sampler($e)
    };
}

/// Declares a bind group: a struct of named resources whose field order is the binding order,
/// each with its [`kind`] slot and the resource it takes (`buffer`, `buffer_range`, `view`,
/// `sampler`):
///
/// ```ignore
/// bind_group! {
///     /// Group 1 of the tonemap pass.
///     pub struct TonemapBindings: COMPUTE {
///         /// The linear HDR frame (rgba16float).
///         radiance: view = kind::TEXTURE,
///         /// The tonemapped sRGB image.
///         out_final: view = kind::write(TextureFormat::Rgba8Unorm),
///     }
/// }
/// ```
/// It gets `SLOTS` (names and slots, for the reflection test), `layout` and `bind_group`.
#[macro_export]
macro_rules! bind_group {
    (
        $(#[$meta:meta])*
        pub struct $name:ident : $($stage:ident)|+ {
            $($(#[$fmeta:meta])* $field:ident : $res:ident = $slot:expr),* $(,)?
        }
    ) => {
        $(#[$meta])*
        pub struct $name<'a> {
            $($(#[$fmeta])* pub $field: $crate::binding_field_type!($res, 'a),)*
        }

        impl<'a> $name<'a> {
            /// Every binding's WGSL name and slot, in binding order.
            pub const SLOTS: &'static [(&'static str, $crate::bindings::Slot)] = &[
                $((stringify!($field), $slot),)*
            ];
            /// The shader stages that see the group.
            pub const STAGES: wgpu::ShaderStages = wgpu::ShaderStages::from_bits_truncate(
                0 $(| wgpu::ShaderStages::$stage.bits())+
            );

            /// The group's layout.
            pub fn layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
                $crate::bindings::layout(device, stringify!($name), Self::SLOTS, Self::STAGES)
            }

            /// The bind group of these resources under `layout` (made by [`Self::layout`]).
            pub fn bind_group(&self, device: &wgpu::Device, layout: &wgpu::BindGroupLayout) -> wgpu::BindGroup {
                let resources = [$($crate::binding_resource!($res, self.$field),)*];
                $crate::bindings::bind_group(device, stringify!($name), layout, &resources)
            }
        }
    };
}

crate::bind_group! {
    /// Group 0 of every pass of the frame: the view, the environment, the far field and the
    /// rest of the frame, as shaders/frame_bindings.wgsl declares them (the libraries
    /// common.wgsl, env.wgsl and far.wgsl take them as parameters).
    pub struct FrameBindings: VERTEX | FRAGMENT | COMPUTE {
        /// `View` (common.wgsl, [`crate::frame::ViewUniforms`]): camera matrices of this and
        /// last frame, image size, projection, frame index, seed, history: all a near-field
        /// kernel reads of the frame.
        view: buffer = kind::UNIFORM,
        /// The environment's radiance, lat-long rgba16float with box-filtered mips.
        env_radiance: view = kind::TEXTURE,
        /// GGX-prefiltered radiance, one roughness per mip (rgba16float).
        env_specular: view = kind::TEXTURE,
        /// Repeats in u, clamps in v, linear.
        env_sampler: sampler = kind::SAMPLER,
        /// `EnvUniforms` (env.wgsl, [`crate::gpu_env::EnvUniforms`]): rotation, intensity, mip
        /// counts, the order-3 SH projection of the radiance.
        env: buffer = kind::UNIFORM,
        /// The pre-convolved diffuse map E(n)/π, lat-long rgba16float.
        env_irradiance_map: view = kind::TEXTURE,
        /// The far field ([`crate::far`], far.wgsl): row 0 the grid (`FarGrid`: sky or probe
        /// volume), then per probe its offset and state and order-2 SH radiance (rgba32float).
        far_probes: view = kind::TEXTURE_UNFILTERABLE,
        /// The probes' octahedral distance moments (rg16float atlas).
        far_visibility: view = kind::TEXTURE,
        /// The probes' octahedral E(n)/π (rgba16float atlas).
        far_irradiance_atlas: view = kind::TEXTURE,
        /// `Frame` (common.wgsl, [`crate::frame::FrameUniforms`]): exposure, tone mapping,
        /// light count. A read-only storage buffer: a third uniform buffer in
        /// group 0 crashes lavapipe (Mesa 22.3) in every technique.
        frame: buffer = kind::STORAGE_READ,
    }
}

/// A layout from slots numbered in order.
pub fn layout(
    device: &wgpu::Device,
    label: &str,
    slots: &[(&str, Slot)],
    stages: ShaderStages,
) -> wgpu::BindGroupLayout {
    let entries: Vec<BindGroupLayoutEntry> = slots
        .iter()
        .enumerate()
        .map(|(i, (_, slot))| slot.entry(i as u32, stages))
        .collect();
    crate::pipeline_cache::bind_group_layout(device, label, &entries)
}

/// A bind group of resources numbered in order.
pub fn bind_group(
    device: &wgpu::Device,
    label: &str,
    layout: &wgpu::BindGroupLayout,
    resources: &[wgpu::BindingResource],
) -> wgpu::BindGroup {
    let entries: Vec<wgpu::BindGroupEntry> = resources
        .iter()
        .enumerate()
        .map(|(i, resource)| wgpu::BindGroupEntry {
            binding: i as u32,
            resource: resource.clone(),
        })
        .collect();
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout,
        entries: &entries,
    })
}

/// One pass's binding declaration, for the reflection test: its name, its WGSL as compiled,
/// the entry point, and the group-1 slots.
pub struct PassLayout {
    pub name: &'static str,
    pub source: String,
    pub entry_point: &'static str,
    pub group1: &'static [(&'static str, Slot)],
}

impl PassLayout {
    /// The declarations of a pass whose entry points (a raster pass's vertex and fragment
    /// stage, or kernels that share one group) all bind `group1`.
    pub fn entries(
        name: &'static str,
        source: String,
        entry_points: &[&'static str],
        group1: &'static [(&'static str, Slot)],
    ) -> Vec<PassLayout> {
        entry_points
            .iter()
            .map(|&entry_point| PassLayout {
                name,
                source: source.clone(),
                entry_point,
                group1,
            })
            .collect()
    }
}

/// Declares a uniform struct shared with WGSL (`#[repr(C)]`, `Pod`) together with its field
/// table `FIELDS` (name, byte offset, in order), which `tests/shaders.rs` compares with naga's
/// layout of the WGSL struct of the same name: a new field is its line here and in the WGSL.
#[macro_export]
macro_rules! gpu_struct {
    ($(#[$meta:meta])* pub struct $name:ident { $($(#[$fmeta:meta])* pub $field:ident : $ty:ty),* $(,)? }) => {
        $(#[$meta])*
        #[repr(C)]
        #[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
        pub struct $name { $($(#[$fmeta])* pub $field: $ty),* }

        impl $name {
            /// Every field with its byte offset, in declaration order.
            pub const FIELDS: &'static [(&'static str, usize)] =
                &[$((stringify!($field), std::mem::offset_of!($name, $field))),*];
        }
    };
}
