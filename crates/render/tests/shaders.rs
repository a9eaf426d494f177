//! Every WGSL program parses and validates with naga (no GPU needed), and every struct shared
//! between host and shader has the same size and member offsets on both sides.

use nearfield_render::{
    frame::{FrameUniforms, ViewUniforms},
    gpu_env::PrefilterParams,
    gpu_scene::{GpuLight, GpuMaterial},
};
use std::mem::{offset_of, size_of};

fn module(source: &str) -> naga::Module {
    naga::front::wgsl::parse_str(source).unwrap_or_else(|e| panic!("{}", e.emit_to_string(source)))
}

#[test]
fn every_shader_validates() {
    let sources = nearfield_render::shader_sources();
    assert!(sources.len() >= 8);
    for (name, source) in sources {
        let m = module(&source);
        // pack2x16float (s3ho) needs SHADER_FLOAT16_IN_FLOAT32; the renderer checks the adapter's
        // matching DownlevelFlags::SHADER_F16_IN_F32 before it builds s3ho.
        let caps = naga::valid::Capabilities::default()
            | naga::valid::Capabilities::SHADER_FLOAT16_IN_FLOAT32;
        naga::valid::Validator::new(naga::valid::ValidationFlags::all(), caps)
            .validate(&m)
            .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(&source)));
    }
}

/// (size, [(member name, offset)]) of a struct in a WGSL module.
fn layout(source: &str, name: &str) -> (u32, Vec<(String, u32)>) {
    let m = module(source);
    for (_, ty) in m.types.iter() {
        if ty.name.as_deref() == Some(name)
            && let naga::TypeInner::Struct { members, span } = &ty.inner
        {
            return (
                *span,
                members
                    .iter()
                    .map(|mm| (mm.name.clone().unwrap_or_default(), mm.offset))
                    .collect(),
            );
        }
    }
    panic!("struct {name} not found");
}

fn check(source: &str, name: &str, size: usize, offsets: &[(&str, usize)]) {
    let (span, members) = layout(source, name);
    assert_eq!(span as usize, size, "{name}: size");
    assert_eq!(members.len(), offsets.len(), "{name}: member count");
    for ((wgsl_name, wgsl_off), (rust_name, rust_off)) in members.iter().zip(offsets) {
        assert_eq!(wgsl_name, rust_name, "{name}: member order");
        assert_eq!(*wgsl_off as usize, *rust_off, "{name}.{wgsl_name}: offset");
    }
}

#[test]
fn host_and_shader_structs_agree() {
    let common = nearfield_render::util::COMMON_WGSL;
    macro_rules! offsets {
        ($t:ty: $($f:ident),*) => { [$((stringify!($f), offset_of!($t, $f))),*] };
    }
    check(
        common,
        "View",
        size_of::<ViewUniforms>(),
        ViewUniforms::FIELDS,
    );
    check(
        common,
        "Frame",
        size_of::<FrameUniforms>(),
        FrameUniforms::FIELDS,
    );
    use nearfield_render::gpu_env::EnvUniforms;
    check(
        &nearfield_render::util::compose(&[common, nearfield_render::util::ENV_WGSL]),
        "EnvUniforms",
        size_of::<EnvUniforms>(),
        EnvUniforms::FIELDS,
    );
    use nearfield_render::passes::reproject::ReprojectParams;
    use nearfield_render::technique::horizon::HorizonParams;
    check(
        &nearfield_render::technique::horizon::search::source(),
        "HorizonParams",
        size_of::<HorizonParams>(),
        HorizonParams::FIELDS,
    );
    check(
        &nearfield_render::passes::reproject::source(),
        "ReprojectParams",
        size_of::<ReprojectParams>(),
        &[
            ("reject_depth", offset_of!(ReprojectParams, reject_depth)),
            ("reject_normal", offset_of!(ReprojectParams, reject_normal)),
            ("_pad0", offset_of!(ReprojectParams, _pad0)),
            ("_pad1", offset_of!(ReprojectParams, _pad1)),
        ],
    );
    use nearfield_render::passes::display::DisplayParams;
    check(
        &nearfield_render::passes::display::source(),
        "DisplayParams",
        size_of::<DisplayParams>(),
        &offsets!(DisplayParams: width, height, split, divider, mode_a, mode_b, tonemap,
            coverage, exposure, lo, hi, _pad0),
    );
    let material = offsets!(GpuMaterial: base_color, emissive, alpha_cutoff, metallic, roughness,
        _pad0, _pad1, base_color_texture, metallic_roughness_texture, emissive_texture, _pad2);
    check(
        &nearfield_render::passes::gbuffer::source(),
        "GpuMaterial",
        size_of::<GpuMaterial>(),
        &material,
    );
    check(
        &nearfield_render::passes::shadow::source(),
        "GpuMaterial",
        size_of::<GpuMaterial>(),
        &material,
    );
    check(
        &nearfield_render::passes::direct_lighting::source(),
        "GpuLight",
        size_of::<GpuLight>(),
        &offsets!(GpuLight: position, kind, direction, range, color, tan_radius, cos_inner, cos_outer,
            shadow_layer, shadow_texel),
    );
    check(
        include_str!("../src/passes/env_prefilter.wgsl"),
        "PrefilterParams",
        size_of::<PrefilterParams>(),
        &[
            ("roughness", offset_of!(PrefilterParams, roughness)),
            ("source_width", offset_of!(PrefilterParams, source_width)),
            ("source_height", offset_of!(PrefilterParams, source_height)),
            ("source_mips", offset_of!(PrefilterParams, source_mips)),
        ],
    );
    // The structs of the passes' own parameters.
    use nearfield_render::passes::bilateral_blur::BlurParams;
    use nearfield_render::passes::layers::{LayerView, ShadeParams};
    use nearfield_render::passes::rsm::RsmView;
    use nearfield_render::technique::{s3ho::S3hoParams, ssdo::SsdoParams};
    for source in [
        nearfield_render::technique::ssdo::direct::source(),
        nearfield_render::technique::ssdo::resolve::source(),
        nearfield_render::technique::ssdo::bounce::source(),
    ] {
        check(
            &source,
            "SsdoParams",
            size_of::<SsdoParams>(),
            &offsets!(SsdoParams: radius, sample_light, mode, technique, lod, contrast, scale, fade,
                strength, distance_clamp, pattern, light_samples, layers, cameras, light_segment,
                vpl_mode, vpl_count, vpl_clamp, near, normalise),
        );
    }
    check(
        &nearfield_render::technique::s3ho::sample::source(),
        "S3hoParams",
        size_of::<S3hoParams>(),
        &offsets!(S3hoParams: radius, _pad0, pattern, fade, _pad1, lambda, technique, indirect,
            strength, distance_clamp, layers, cameras),
    );
    check(
        &nearfield_render::passes::bilateral_blur::source(),
        "BlurParams",
        size_of::<BlurParams>(),
        &offsets!(BlurParams: direction, radius, enabled, depth_sigma, normal_power, _pad0, _pad1),
    );
    check(
        common,
        "LayerView",
        size_of::<LayerView>(),
        &offsets!(LayerView: clip_from_world, view_from_world, world_from_view, size, inv_size,
            near, far, aspect, tan_half_fov, peel, exit, _pad0, _pad1, _pad2),
    );
    check(
        &nearfield_render::passes::layers::source(),
        "ShadeParams",
        size_of::<ShadeParams>(),
        &offsets!(ShadeParams: first_view, count, _pad0, _pad1),
    );
    check(
        &nearfield_render::passes::rsm::source(),
        "RsmView",
        size_of::<RsmView>(),
        &offsets!(RsmView: clip_from_world, to_light),
    );
}
