//! Every WGSL program parses and validates with naga (no GPU needed), and every struct shared
//! between host and shader has the same size and member offsets on both sides.

use nearfield_render::{
    frame::{FrameUniforms, ViewUniforms},
    gpu_env::PrefilterParams,
    gpu_scene::{GpuLight, GpuMaterial},
};
use std::mem::size_of;

#[test]
fn every_shader_validates() {
    let sources = nearfield_render::shader_sources();
    assert!(sources.len() >= 8);
    for (name, source) in sources {
        if let Err(e) = nearfield_render::reflect::validate(&source) {
            panic!("{name}: {e}");
        }
    }
}

fn check(source: &str, name: &str, size: usize, fields: &[(&str, usize)]) {
    let errors = nearfield_render::reflect::struct_mismatches(source, name, size, fields);
    assert!(errors.is_empty(), "{}", errors.join("\n"));
}

#[test]
fn host_and_shader_structs_agree() {
    let common = nearfield_render::util::COMMON_WGSL;
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
        ReprojectParams::FIELDS,
    );
    use nearfield_render::passes::denoise::SvgfParams;
    check(
        &nearfield_render::passes::denoise::atrous::source(),
        "SvgfParams",
        size_of::<SvgfParams>(),
        SvgfParams::FIELDS,
    );
    use nearfield_render::technique::vbgi::VbgiParams;
    check(
        &nearfield_render::technique::vbgi::bitmask::source(),
        "VbgiParams",
        size_of::<VbgiParams>(),
        VbgiParams::FIELDS,
    );
    use nearfield_render::passes::aov::AovSelection;
    check(
        &nearfield_render::passes::aov::source(),
        "AovSelection",
        size_of::<AovSelection>(),
        AovSelection::FIELDS,
    );
    use nearfield_render::passes::display::DisplayParams;
    check(
        &nearfield_render::passes::display::source(),
        "DisplayParams",
        size_of::<DisplayParams>(),
        DisplayParams::FIELDS,
    );
    let material = GpuMaterial::FIELDS;
    check(
        &nearfield_render::passes::gbuffer::source(),
        "GpuMaterial",
        size_of::<GpuMaterial>(),
        material,
    );
    check(
        &nearfield_render::passes::shadow::source(),
        "GpuMaterial",
        size_of::<GpuMaterial>(),
        material,
    );
    check(
        &nearfield_render::passes::direct_lighting::source(),
        "GpuLight",
        size_of::<GpuLight>(),
        GpuLight::FIELDS,
    );
    check(
        include_str!("../src/passes/env_prefilter.wgsl"),
        "PrefilterParams",
        size_of::<PrefilterParams>(),
        PrefilterParams::FIELDS,
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
            SsdoParams::FIELDS,
        );
    }
    check(
        &nearfield_render::technique::s3ho::sample::source(),
        "S3hoParams",
        size_of::<S3hoParams>(),
        S3hoParams::FIELDS,
    );
    check(
        &nearfield_render::passes::bilateral_blur::source(),
        "BlurParams",
        size_of::<BlurParams>(),
        BlurParams::FIELDS,
    );
    check(
        common,
        "LayerView",
        size_of::<LayerView>(),
        LayerView::FIELDS,
    );
    check(
        &nearfield_render::passes::layers::source(),
        "ShadeParams",
        size_of::<ShadeParams>(),
        ShadeParams::FIELDS,
    );
    check(
        &nearfield_render::passes::rsm::source(),
        "RsmView",
        size_of::<RsmView>(),
        RsmView::FIELDS,
    );
}

#[test]
fn the_struct_check_catches_a_moved_or_missing_member() {
    use nearfield_render::passes::aov::AovSelection;
    let source = nearfield_render::passes::aov::source();
    let check = |wgsl: &str| {
        nearfield_render::reflect::struct_mismatches(
            wgsl,
            "AovSelection",
            size_of::<AovSelection>(),
            AovSelection::FIELDS,
        )
    };
    assert!(check(&source).is_empty());
    let moved = source.replace(
        "    aov: u32,\n    _pad0: u32,",
        "    _pad0: u32,\n    aov: u32,",
    );
    assert_ne!(moved, source);
    assert!(!check(&moved).is_empty());
    let missing = source.replace("    _pad2: u32,\n}", "}");
    assert_ne!(missing, source);
    assert!(!check(&missing).is_empty());
}
