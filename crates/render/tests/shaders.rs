//! Every WGSL program parses and validates with naga (no GPU needed), and every struct shared
//! between host and shader has the same size and member offsets on both sides.

use nearfield_render::{
    frame::FrameUniforms,
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
    check(
        common,
        "Frame",
        size_of::<FrameUniforms>(),
        &[
            (
                "clip_from_world",
                offset_of!(FrameUniforms, clip_from_world),
            ),
            (
                "world_from_clip",
                offset_of!(FrameUniforms, world_from_clip),
            ),
            (
                "view_from_world",
                offset_of!(FrameUniforms, view_from_world),
            ),
            (
                "world_from_view",
                offset_of!(FrameUniforms, world_from_view),
            ),
            (
                "prev_clip_from_world",
                offset_of!(FrameUniforms, prev_clip_from_world),
            ),
            (
                "prev_view_from_world",
                offset_of!(FrameUniforms, prev_view_from_world),
            ),
            (
                "prev_world_from_view",
                offset_of!(FrameUniforms, prev_world_from_view),
            ),
            (
                "camera_position",
                offset_of!(FrameUniforms, camera_position),
            ),
            ("size", offset_of!(FrameUniforms, size)),
            ("projection", offset_of!(FrameUniforms, projection)),
            ("env_params", offset_of!(FrameUniforms, env_params)),
            ("post", offset_of!(FrameUniforms, post)),
            (
                "prev_projection",
                offset_of!(FrameUniforms, prev_projection),
            ),
            ("counts", offset_of!(FrameUniforms, counts)),
            ("history", offset_of!(FrameUniforms, history)),
        ],
    );
    use nearfield_render::passes::reproject::ReprojectParams;
    use nearfield_render::technique::horizon::HorizonParams;
    macro_rules! offsets {
        ($t:ty: $($f:ident),*) => { vec![$((stringify!($f), offset_of!($t, $f))),*] };
    }
    check(
        &nearfield_render::technique::horizon::source(),
        "HorizonParams",
        size_of::<HorizonParams>(),
        &offsets!(HorizonParams: radius, slices, steps, falloff, max_pixels, scale, indirect,
            step_power, reject_a, reject_b, layer_width, layer_height, temporal, max_history, far,
            fresnel, reject_depth, reject_normal, aperture, far_steps),
    );
    check(
        &nearfield_render::passes::reproject::source(),
        "ReprojectParams",
        size_of::<ReprojectParams>(),
        &[
            ("reject_depth", offset_of!(ReprojectParams, reject_depth)),
            ("reject_normal", offset_of!(ReprojectParams, reject_normal)),
            ("_pad0", offset_of!(ReprojectParams, _pad)),
            ("_pad1", offset_of!(ReprojectParams, _pad) + 4),
        ],
    );
    use nearfield_render::passes::display::DisplayParams;
    check(
        &nearfield_render::passes::display::source(),
        "DisplayParams",
        size_of::<DisplayParams>(),
        &[
            ("size", offset_of!(DisplayParams, size)),
            ("mode", offset_of!(DisplayParams, mode)),
            ("range", offset_of!(DisplayParams, range)),
        ],
    );
    let material = [
        ("base_color", offset_of!(GpuMaterial, base_color)),
        ("emissive", offset_of!(GpuMaterial, emissive)),
        ("params", offset_of!(GpuMaterial, params)),
        ("textures", offset_of!(GpuMaterial, textures)),
    ];
    check(
        &nearfield_render::passes::gbuffer::source(),
        "GpuMaterial",
        size_of::<GpuMaterial>(),
        &material,
    );
    check(
        nearfield_render::passes::shadow::SHADER,
        "GpuMaterial",
        size_of::<GpuMaterial>(),
        &material,
    );
    check(
        &nearfield_render::passes::direct_lighting::source(),
        "GpuLight",
        size_of::<GpuLight>(),
        &[
            ("position", offset_of!(GpuLight, position)),
            ("direction", offset_of!(GpuLight, direction)),
            ("color", offset_of!(GpuLight, color)),
            ("cone", offset_of!(GpuLight, cone)),
        ],
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
}
