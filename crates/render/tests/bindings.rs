//! Every pass's bindings in Rust agree with its WGSL, by naga's reflection (no GPU needed): each
//! binding the entry point uses is declared by the pass's binding struct under the same name,
//! group and number with the same type, format and access; and each binding the struct declares
//! is declared so in the WGSL.

use naga::{AddressSpace, ImageClass, ImageDimension, ScalarKind, StorageAccess, TypeInner};
use nearfield_render::bindings::{FrameBindings, Slot};
use wgpu::TextureViewDimension as D;
use wgpu::{SamplerBindingType, StorageTextureAccess, TextureFormat, TextureSampleType as T};

fn storage_format(f: naga::StorageFormat) -> Option<TextureFormat> {
    use naga::StorageFormat as S;
    Some(match f {
        S::Rgba16Float => TextureFormat::Rgba16Float,
        S::Rgba32Float => TextureFormat::Rgba32Float,
        S::R32Float => TextureFormat::R32Float,
        S::Rgba8Unorm => TextureFormat::Rgba8Unorm,
        S::Rgba32Uint => TextureFormat::Rgba32Uint,
        S::R32Uint => TextureFormat::R32Uint,
        _ => return None,
    })
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
                dim: ImageDimension::D2,
                arrayed,
                class,
            },
        ) => {
            *arrayed == (dimension == D::D2Array)
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
                dim: ImageDimension::D2,
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
            *arrayed == (dimension == D::D2Array)
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

/// Every mismatch between a pass's WGSL and its declared groups.
fn check(name: &str, source: &str, entry_point: &str, group1: &[(&str, Slot)]) -> Vec<String> {
    let module = naga::front::wgsl::parse_str(source)
        .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(source)));
    let caps =
        naga::valid::Capabilities::default() | naga::valid::Capabilities::SHADER_FLOAT16_IN_FLOAT32;
    let info = naga::valid::Validator::new(naga::valid::ValidationFlags::all(), caps)
        .validate(&module)
        .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(source)));
    let Some(ep) = module
        .entry_points
        .iter()
        .position(|e| e.name == entry_point)
    else {
        return vec![format!("{name}: no entry point {entry_point}")];
    };
    let uses = info.get_entry_point(ep);
    let groups: [&[(&str, Slot)]; 2] = [FrameBindings::SLOTS, group1];
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
    // What Rust declares in group 1 is declared so in the WGSL.
    for (i, (rust_name, slot)) in group1.iter().enumerate() {
        let found = module.global_variables.iter().find(|(_, v)| {
            v.binding
                .as_ref()
                .is_some_and(|b| b.group == 1 && b.binding == i as u32)
                && v.name.as_deref() == Some(*rust_name)
        });
        match found {
            None => errors.push(format!(
                "{name}: Rust declares {rust_name} at @group(1) @binding({i}); the WGSL does not"
            )),
            Some((_, var)) => {
                if let Some(m) = mismatch(&module, var, *slot) {
                    errors.push(format!("{name}: {rust_name}: {m}"));
                }
            }
        }
    }
    errors
}

#[test]
fn every_pass_binds_what_its_wgsl_declares() {
    let passes = nearfield_render::pass_layouts();
    assert!(passes.len() >= 10, "only {} passes declared", passes.len());
    let errors: Vec<String> = passes
        .iter()
        .flat_map(|p| check(p.name, &p.source, p.entry_point, p.group1))
        .collect();
    assert!(errors.is_empty(), "{}", errors.join("\n"));
}

#[test]
fn the_check_catches_a_renamed_or_renumbered_binding() {
    // The tonemap pass, then the same WGSL with its two bindings swapped and one renamed.
    let pass = nearfield_render::pass_layouts()
        .into_iter()
        .find(|p| p.name == "tonemap")
        .expect("tonemap pass");
    assert!(check(pass.name, &pass.source, pass.entry_point, pass.group1).is_empty());
    let swapped = pass
        .source
        .replace("@group(1) @binding(0)", "@group(1) @binding(9)")
        .replace("@group(1) @binding(1)", "@group(1) @binding(0)")
        .replace("@group(1) @binding(9)", "@group(1) @binding(1)");
    assert!(!check(pass.name, &swapped, pass.entry_point, pass.group1).is_empty());
    let format = pass.source.replace("rgba8unorm", "rgba16float");
    assert!(!check(pass.name, &format, pass.entry_point, pass.group1).is_empty());
}
