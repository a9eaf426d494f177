//! Every kernel translates, with naga, into each backend's language — SPIR-V (Vulkan), MSL
//! (Metal), HLSL (DX12) and GLSL ES 3.1 (GL, what wgpu's GL backend writes for compute) — with
//! its `override` constants at their defaults, every entry point on its own. The portability
//! check that needs none of those GPUs (the book, "Lifting a pass into another engine").

use naga::back;
use naga::valid::{Capabilities, ModuleInfo, ValidationFlags, Validator};

fn validate(name: &str, source: &str, module: &naga::Module) -> ModuleInfo {
    // pack2x16float (s3ho) needs SHADER_FLOAT16_IN_FLOAT32 (tests/shaders.rs says why).
    Validator::new(
        ValidationFlags::all(),
        Capabilities::default() | Capabilities::SHADER_FLOAT16_IN_FLOAT32,
    )
    .validate(module)
    .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(source)))
}

/// Translates one entry point to the four targets; the errors, one line each.
fn translate(
    module: &naga::Module,
    info: &ModuleInfo,
    stage: naga::ShaderStage,
    entry: &str,
) -> Vec<String> {
    let mut errors = Vec::new();
    let constants = back::PipelineConstants::default();
    let (module, info) = match back::pipeline_constants::process_overrides(
        module,
        info,
        Some((stage, entry)),
        &constants,
    ) {
        Ok(x) => x,
        Err(e) => return vec![format!("overrides: {e}")],
    };

    let spv = back::spv::Options {
        lang_version: (1, 3),
        ..Default::default()
    };
    let spv_pipeline = back::spv::PipelineOptions {
        shader_stage: stage,
        entry_point: entry.into(),
    };
    if let Err(e) = back::spv::write_vec(&module, &info, &spv, Some(&spv_pipeline)) {
        errors.push(format!("SPIR-V: {e}"));
    }

    let msl = back::msl::Options {
        lang_version: (2, 4),
        fake_missing_bindings: true,
        ..Default::default()
    };
    let msl_pipeline = back::msl::PipelineOptions {
        entry_point: Some((stage, entry.into())),
        ..Default::default()
    };
    if let Err(e) = back::msl::write_string(&module, &info, &msl, &msl_pipeline) {
        errors.push(format!("MSL: {e}"));
    }

    let hlsl = back::hlsl::Options {
        shader_model: back::hlsl::ShaderModel::V6_0,
        fake_missing_bindings: true,
        ..Default::default()
    };
    let hlsl_pipeline = back::hlsl::PipelineOptions {
        entry_point: Some((stage, entry.into())),
    };
    let mut out = String::new();
    if let Err(e) =
        back::hlsl::Writer::new(&mut out, &hlsl, &hlsl_pipeline).write(&module, &info, None)
    {
        errors.push(format!("HLSL: {e}"));
    }

    let glsl = back::glsl::Options {
        version: back::glsl::Version::new_gles(310),
        ..Default::default()
    };
    let glsl_pipeline = back::glsl::PipelineOptions {
        shader_stage: stage,
        entry_point: entry.into(),
        multiview: None,
    };
    let mut out = String::new();
    match back::glsl::Writer::new(
        &mut out,
        &module,
        &info,
        &glsl,
        &glsl_pipeline,
        naga::proc::BoundsCheckPolicies::default(),
    ) {
        Ok(mut w) => {
            if let Err(e) = w.write() {
                errors.push(format!("GLSL ES 3.1: {e}"));
            }
        }
        Err(e) => errors.push(format!("GLSL ES 3.1: {e}")),
    }
    errors
}

#[test]
fn every_kernel_translates_to_spirv_msl_hlsl_and_glsl() {
    let sources = nearfield_render::shader_sources();
    assert!(sources.len() >= 20, "{} programs", sources.len());
    let mut failures = Vec::new();
    let mut entries = 0;
    for (name, source) in &sources {
        let module = naga::front::wgsl::parse_str(source)
            .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(source)));
        let info = validate(name, source, &module);
        for ep in &module.entry_points {
            entries += 1;
            for e in translate(&module, &info, ep.stage, &ep.name) {
                failures.push(format!("{name}::{}: {e}", ep.name));
            }
        }
    }
    assert!(entries >= sources.len());
    assert!(
        failures.is_empty(),
        "{} of {entries} entry points do not translate:\n{}",
        failures.len(),
        failures.join("\n")
    );
}
