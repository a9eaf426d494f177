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

/// The WGSL libraries (docs/src/architecture.md, "Lifting a pass into another engine"), each with
/// the libraries it is composed after. A library declares no binding and reads no name it does
/// not declare or take as a parameter: it validates on its own with only its prelude, no entry
/// file and no bindings glue.
const LIBRARIES: &[(&str, &[&str])] = &[
    ("shaders/common.wgsl", &[]),
    ("shaders/env.wgsl", &["shaders/common.wgsl"]),
    (
        "shaders/far.wgsl",
        &["shaders/common.wgsl", "shaders/env.wgsl"],
    ),
    ("shaders/lights.wgsl", &[]),
    ("shaders/surface.wgsl", &["shaders/common.wgsl"]),
    ("shaders/gpu_material.wgsl", &[]),
    ("shaders/materials.wgsl", &["shaders/gpu_material.wgsl"]),
    ("shaders/tonemap_ops.wgsl", &[]),
    ("technique/horizon/params.wgsl", &["shaders/common.wgsl"]),
    (
        "technique/horizon/slice.wgsl",
        &[
            "shaders/common.wgsl",
            "shaders/env.wgsl",
            "shaders/far.wgsl",
            "technique/horizon/params.wgsl",
            "technique/horizon/half.wgsl",
        ],
    ),
    (
        "technique/horizon/half.wgsl",
        &[
            "shaders/common.wgsl",
            "shaders/env.wgsl",
            "shaders/far.wgsl",
            "technique/horizon/params.wgsl",
        ],
    ),
    (
        "technique/horizon/march.wgsl",
        &[
            "shaders/common.wgsl",
            "shaders/env.wgsl",
            "shaders/far.wgsl",
            "technique/horizon/params.wgsl",
            "technique/horizon/half.wgsl",
            "technique/horizon/slice.wgsl",
        ],
    ),
    (
        "technique/horizon/resolve.wgsl",
        &[
            "shaders/common.wgsl",
            "shaders/env.wgsl",
            "shaders/far.wgsl",
            "technique/horizon/params.wgsl",
        ],
    ),
    (
        "technique/samples.wgsl",
        &["shaders/common.wgsl", "shaders/surface.wgsl"],
    ),
    (
        "technique/senders.wgsl",
        &[
            "shaders/common.wgsl",
            "shaders/surface.wgsl",
            "technique/samples.wgsl",
        ],
    ),
    ("technique/ssdo/params.wgsl", &["shaders/common.wgsl"]),
    (
        "technique/ssdo/segment.wgsl",
        &[
            "shaders/common.wgsl",
            "shaders/lights.wgsl",
            "shaders/surface.wgsl",
            "technique/samples.wgsl",
            "technique/ssdo/params.wgsl",
        ],
    ),
    (
        "technique/s3ho/sh.wgsl",
        &["shaders/common.wgsl", "shaders/env.wgsl"],
    ),
    ("passes/denoise/params.wgsl", &["shaders/common.wgsl"]),
    ("passes/irradiance_terms.wgsl", &["shaders/common.wgsl"]),
];

/// nearfield's own glue for group 0: the one shared file that declares bindings.
const GLUE: &str = "shaders/frame_bindings.wgsl";
/// Glue shared by a few entry files: it declares nothing and reads the bindings they all declare
/// under the same names (what a storage array, which WGSL cannot pass, needs).
const PASS_GLUE: &[&str] = &[
    "technique/layers_glue.wgsl",
    "technique/ssdo/segment_glue.wgsl",
];

fn wgsl_files(dir: &std::path::Path, out: &mut Vec<std::path::PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            wgsl_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "wgsl") {
            out.push(p);
        }
    }
}

#[test]
fn shared_wgsl_declares_no_globals() {
    let src = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let read = |rel: &str| std::fs::read_to_string(src.join(rel)).unwrap();
    // Every WGSL file is an entry file (it has an entry point and declares its own bindings),
    // the glue, or a library listed above.
    let mut files = Vec::new();
    wgsl_files(&src, &mut files);
    let mut unlisted = Vec::new();
    for f in &files {
        let rel = f
            .strip_prefix(&src)
            .unwrap()
            .to_string_lossy()
            .replace('\\', "/");
        let text = std::fs::read_to_string(f).unwrap();
        let entry = ["@compute", "@vertex", "@fragment"]
            .iter()
            .any(|s| text.contains(s));
        if PASS_GLUE.contains(&rel.as_str()) {
            let declares = text
                .lines()
                .any(|l| l.starts_with("var") || l.starts_with("@group"));
            assert!(
                !declares && !entry,
                "{rel}: pass glue declares a binding or an entry point"
            );
            continue;
        }
        if !entry && rel != GLUE && !LIBRARIES.iter().any(|(l, _)| *l == rel) {
            unlisted.push(rel);
        }
    }
    assert!(
        unlisted.is_empty(),
        "WGSL files with no entry point that are not listed as libraries: {unlisted:?}"
    );
    for (lib, prelude) in LIBRARIES {
        let mut parts: Vec<String> = prelude.iter().map(|p| read(p)).collect();
        parts.push(read(lib));
        let source = parts.join("\n");
        let module = naga::front::wgsl::parse_str(&source)
            .unwrap_or_else(|e| panic!("{lib} alone: {}", e.emit_to_string(&source)));
        let globals: Vec<_> = module
            .global_variables
            .iter()
            .map(|(_, g)| g.name.clone().unwrap_or_default())
            .collect();
        assert!(globals.is_empty(), "{lib} declares {globals:?}");
        validate(lib, &source, &module);
    }
    // The glue declares group 0 in FrameBindings' order, and nothing else.
    let glue = read(GLUE);
    let source = [
        read("shaders/common.wgsl"),
        read("shaders/env.wgsl"),
        glue.clone(),
    ]
    .join("\n");
    let module = naga::front::wgsl::parse_str(&source).unwrap();
    let names: Vec<(u32, String)> = module
        .global_variables
        .iter()
        .map(|(_, g)| {
            let b = g.binding.as_ref().expect("a binding");
            assert_eq!(b.group, 0, "{GLUE}: group");
            (b.binding, g.name.clone().unwrap())
        })
        .collect();
    let expected: Vec<(u32, String)> = nearfield_render::bindings::FrameBindings::SLOTS
        .iter()
        .enumerate()
        .map(|(i, (name, _))| (i as u32, name.to_string()))
        .collect();
    assert_eq!(names, expected, "{GLUE} against FrameBindings");
}

/// The kernels are compiled without wgpu's loop bounding (`pipeline_cache::kernel_runtime_checks`),
/// whose safety condition is that no loop runs forever. Every loop must therefore be a `for`
/// that counts an integer variable up by one against a bound and that no statement of its body
/// writes: no `loop` and no `while`. (The bounds themselves are constants or validated settings.)
#[test]
fn every_loop_counts_an_integer_to_a_bound() {
    let header = regex::Regex::new(r"^var (\w+) = ([^;]+); (.+); (\w+)\+\+$").unwrap();
    let words = regex::Regex::new(r"\b(loop|while)\b").unwrap();
    let float = regex::Regex::new(r"\d\.|\d+(\.\d*)?f\b|f32|f16").unwrap();
    let mut loops = 0;
    // Every WGSL file of the crate: the entry files and the libraries they include.
    let mut files = Vec::new();
    wgsl_files(
        &std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src"),
        &mut files,
    );
    assert!(files.len() > 40, "{} WGSL files", files.len());
    for file in files {
        let name = file.display();
        let source = std::fs::read_to_string(&file).unwrap();
        let code: String = source
            .lines()
            .map(|l| l.split("//").next().unwrap_or(""))
            .collect::<Vec<_>>()
            .join("\n");
        assert!(
            !words.is_match(&code),
            "{name}: a `loop` or `while` (only counted `for` loops)"
        );
        for (at, _) in code.match_indices("for (") {
            loops += 1;
            let open = at + "for ".len();
            let close = matching(&code, open, b'(', b')');
            let head = &code[open + 1..close];
            let caps = header
                .captures(head)
                .unwrap_or_else(|| panic!("{name}: `for ({head})` does not count an integer up"));
            let var = &caps[1];
            assert!(
                !float.is_match(&caps[2]),
                "{name}: `for ({head})` counts a float"
            );
            assert_eq!(
                &caps[4], var,
                "{name}: `for ({head})` steps another variable"
            );
            let bound = regex::Regex::new(&format!(r"\b{var}\b( \+ 1u)? <=? ")).unwrap();
            assert!(
                bound.is_match(&caps[3]),
                "{name}: `for ({head})` has no upper bound on {var}"
            );
            let body_open = close + code[close..].find('{').unwrap();
            let body = &code[body_open..=matching(&code, body_open, b'{', b'}')];
            let write =
                regex::Regex::new(&format!(r"\b{var}\s*(\+\+|--|[-+*/%&|^]?=[^=])")).unwrap();
            assert!(
                !write.is_match(body),
                "{name}: the body of `for ({head})` writes {var}"
            );
        }
    }
    assert!(loops > 50, "only {loops} loops found");
}

/// The index of the bracket that closes the one at `open`.
fn matching(code: &str, open: usize, left: u8, right: u8) -> usize {
    let mut depth = 0;
    for (i, b) in code.bytes().enumerate().skip(open) {
        if b == left {
            depth += 1;
        } else if b == right {
            depth -= 1;
            if depth == 0 {
                return i;
            }
        }
    }
    panic!("unbalanced brackets")
}
