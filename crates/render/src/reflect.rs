//! The checks that tie host declarations to WGSL, by naga's reflection (no GPU needed): a
//! program validates, its bindings are the ones its [`crate::bind_group!`] structs declare, and a
//! [`crate::gpu_struct!`] has its WGSL struct's size and member offsets. The crate's own tests run
//! them over every pass; an engine that declares its glue with the same macros runs them over its
//! own WGSL.

use crate::bindings::Slot;
use naga::{AddressSpace, ImageClass, ImageDimension, ScalarKind, StorageAccess, TypeInner};
use wgpu::TextureViewDimension as D;
use wgpu::{SamplerBindingType, StorageTextureAccess, TextureFormat, TextureSampleType as T};

/// Parses and validates a WGSL program (with `SHADER_FLOAT16_IN_FLOAT32`, which s3ho's
/// pack2x16float needs; the renderer checks the adapter's matching flag before it builds s3ho).
pub fn validate(source: &str) -> Result<(naga::Module, naga::valid::ModuleInfo), String> {
    let module = naga::front::wgsl::parse_str(source).map_err(|e| e.emit_to_string(source))?;
    let caps =
        naga::valid::Capabilities::default() | naga::valid::Capabilities::SHADER_FLOAT16_IN_FLOAT32;
    let info = naga::valid::Validator::new(naga::valid::ValidationFlags::all(), caps)
        .validate(&module)
        .map_err(|e| e.emit_to_string(source))?;
    Ok((module, info))
}

fn storage_format(f: naga::StorageFormat) -> Option<TextureFormat> {
    use naga::StorageFormat as S;
    Some(match f {
        S::Rgba16Float => TextureFormat::Rgba16Float,
        S::Rgba32Float => TextureFormat::Rgba32Float,
        S::R16Float => TextureFormat::R16Float,
        S::Rg16Float => TextureFormat::Rg16Float,
        S::R32Float => TextureFormat::R32Float,
        S::Rg32Float => TextureFormat::Rg32Float,
        S::Rgba8Unorm => TextureFormat::Rgba8Unorm,
        S::Rgba32Uint => TextureFormat::Rgba32Uint,
        S::R32Uint => TextureFormat::R32Uint,
        _ => return None,
    })
}

/// naga's dimension and arrayness of a view dimension.
fn image_dimension(dimension: D) -> (ImageDimension, bool) {
    match dimension {
        D::D2Array => (ImageDimension::D2, true),
        D::Cube => (ImageDimension::Cube, false),
        D::CubeArray => (ImageDimension::Cube, true),
        D::D3 => (ImageDimension::D3, false),
        D::D1 => (ImageDimension::D1, false),
        D::D2 => (ImageDimension::D2, false),
    }
}

/// Why the WGSL declaration of a global disagrees with `slot`, if it does.
fn mismatch(module: &naga::Module, var: &naga::GlobalVariable, slot: Slot) -> Option<String> {
    let inner = &module.types[var.ty].inner;
    let ok = match (slot, var.space, inner) {
        (Slot::Uniform | Slot::DynamicUniform { .. }, AddressSpace::Uniform, _) => true,
        (Slot::Storage { read_only }, AddressSpace::Storage { access }, _) => {
            read_only != access.contains(StorageAccess::STORE)
        }
        (
            Slot::Texture { sample, dimension },
            AddressSpace::Handle,
            TypeInner::Image {
                dim,
                arrayed,
                class,
            },
        ) => {
            (*dim, *arrayed) == image_dimension(dimension)
                && match (sample, class) {
                    (T::Float { .. }, ImageClass::Sampled { kind, multi }) => {
                        *kind == ScalarKind::Float && !multi
                    }
                    (T::Uint, ImageClass::Sampled { kind, multi }) => {
                        *kind == ScalarKind::Uint && !multi
                    }
                    (T::Depth, ImageClass::Depth { multi }) => !multi,
                    _ => false,
                }
        }
        (
            Slot::StorageTexture {
                format,
                access,
                dimension,
            },
            AddressSpace::Handle,
            TypeInner::Image {
                dim,
                arrayed,
                class:
                    ImageClass::Storage {
                        format: f,
                        access: a,
                    },
            },
        ) => {
            let wgsl_access = match (
                a.contains(StorageAccess::LOAD),
                a.contains(StorageAccess::STORE),
            ) {
                (true, true) => StorageTextureAccess::ReadWrite,
                (true, false) => StorageTextureAccess::ReadOnly,
                _ => StorageTextureAccess::WriteOnly,
            };
            (*dim, *arrayed) == image_dimension(dimension)
                && storage_format(*f) == Some(format)
                && wgsl_access == access
        }
        (Slot::Sampler(kind), AddressSpace::Handle, TypeInner::Sampler { comparison }) => {
            *comparison == (kind == SamplerBindingType::Comparison)
        }
        _ => false,
    };
    (!ok).then(|| format!("Rust declares {slot:?}, WGSL {:?} {inner:?}", var.space))
}

/// Every mismatch between a program's WGSL and its declared groups (`groups[g]` for
/// `@group(g)`): each binding `entry_point` uses is declared under the same name, group and
/// number with the same type, format and access; each binding of the groups after the first
/// (a pass's own) is declared so in the WGSL.
pub fn group_mismatches(
    name: &str,
    source: &str,
    entry_point: &str,
    groups: &[&[(&str, Slot)]],
) -> Vec<String> {
    let (module, info) = match validate(source) {
        Ok(m) => m,
        Err(e) => return vec![format!("{name}: {e}")],
    };
    let Some(ep) = module
        .entry_points
        .iter()
        .position(|e| e.name == entry_point)
    else {
        return vec![format!("{name}: no entry point {entry_point}")];
    };
    let uses = info.get_entry_point(ep);
    let mut errors = Vec::new();
    // What the entry point uses is declared in Rust.
    for (handle, var) in module.global_variables.iter() {
        let Some(b) = &var.binding else { continue };
        if uses[handle].is_empty() {
            continue;
        }
        let wgsl_name = var.name.clone().unwrap_or_default();
        let declared = groups
            .get(b.group as usize)
            .and_then(|g| g.get(b.binding as usize));
        match declared {
            None => errors.push(format!(
                "{name}: {wgsl_name} at @group({}) @binding({}) has no Rust declaration",
                b.group, b.binding
            )),
            Some((rust_name, slot)) => {
                if *rust_name != wgsl_name {
                    errors.push(format!(
                        "{name}: @group({}) @binding({}) is {wgsl_name} in WGSL, {rust_name} in Rust",
                        b.group, b.binding
                    ));
                }
                if let Some(m) = mismatch(&module, var, *slot) {
                    errors.push(format!("{name}: {wgsl_name}: {m}"));
                }
            }
        }
    }
    // What Rust declares in a pass's own groups is declared so in the WGSL.
    for (g, group) in groups.iter().enumerate().skip(1) {
        for (i, (rust_name, slot)) in group.iter().enumerate() {
            let found = module.global_variables.iter().find(|(_, v)| {
                v.binding
                    .as_ref()
                    .is_some_and(|b| b.group == g as u32 && b.binding == i as u32)
                    && v.name.as_deref() == Some(*rust_name)
            });
            match found {
                None => errors.push(format!(
                    "{name}: Rust declares {rust_name} at @group({g}) @binding({i}); the WGSL does not"
                )),
                Some((_, var)) => {
                    if let Some(m) = mismatch(&module, var, *slot) {
                        errors.push(format!("{name}: {rust_name}: {m}"));
                    }
                }
            }
        }
    }
    errors
}

/// Every difference between a host struct (its size and `(name, offset)` fields, as
/// [`crate::gpu_struct!`] gives them) and the WGSL struct `name` in `source`.
pub fn struct_mismatches(
    source: &str,
    name: &str,
    size: usize,
    fields: &[(&str, usize)],
) -> Vec<String> {
    let module = match naga::front::wgsl::parse_str(source) {
        Ok(m) => m,
        Err(e) => return vec![format!("{name}: {}", e.emit_to_string(source))],
    };
    let Some((span, members)) = module.types.iter().find_map(|(_, ty)| match &ty.inner {
        TypeInner::Struct { members, span } if ty.name.as_deref() == Some(name) => {
            Some((*span, members))
        }
        _ => None,
    }) else {
        return vec![format!("struct {name} not found")];
    };
    let mut errors = Vec::new();
    if span as usize != size {
        errors.push(format!("{name}: size {span} in WGSL, {size} in Rust"));
    }
    if members.len() != fields.len() {
        errors.push(format!(
            "{name}: {} members in WGSL, {} in Rust",
            members.len(),
            fields.len()
        ));
    }
    for (m, (rust_name, rust_offset)) in members.iter().zip(fields) {
        let wgsl_name = m.name.clone().unwrap_or_default();
        if wgsl_name != *rust_name {
            errors.push(format!(
                "{name}: member {wgsl_name} in WGSL where Rust has {rust_name}"
            ));
        } else if m.offset as usize != *rust_offset {
            errors.push(format!(
                "{name}.{wgsl_name}: offset {} in WGSL, {rust_offset} in Rust",
                m.offset
            ));
        }
    }
    errors
}
