//! Bad input never panics: each case below exits with status 2 and prints exactly one line that
//! names the problem. Cases that reach the GPU (sizes, methods) fail before an adapter is needed.

use std::path::{Path, PathBuf};
use std::process::Command;

fn nearfield(args: &[&str]) -> (i32, String) {
    nearfield_with(args, &[])
}

/// `nearfield ARGS` with environment variables `envs`: (exit status, stderr).
fn nearfield_with(args: &[&str], envs: &[(&str, &Path)]) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_nearfield"))
        .args(args)
        .envs(envs.iter().copied())
        .output()
        .expect("run nearfield");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn scratch() -> PathBuf {
    let dir = std::env::temp_dir().join(format!("nearfield-bad-input-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn write(dir: &Path, name: &str, bytes: &[u8]) -> String {
    let p = dir.join(name);
    std::fs::write(&p, bytes).unwrap();
    p.to_str().unwrap().to_string()
}

/// A one-triangle glTF whose buffer is a data URI; `extra` is spliced into the root object.
fn gltf(buffer_uri: &str, extra: &str) -> String {
    format!(
        r#"{{"asset":{{"version":"2.0"}},"buffers":[{{"byteLength":36,"uri":"{buffer_uri}"}}],
        "bufferViews":[{{"buffer":0,"byteLength":36}}],
        "accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}},"material":0}}]}}],
        "materials":[{{}}],
        "nodes":[{{"mesh":0}}],"scenes":[{{"nodes":[0]}}],"scene":0{extra}}}"#
    )
}

fn triangle_data_uri() -> String {
    let floats: [f32; 9] = [0., 0., 0., 1., 0., 0., 0., 1., 0.];
    let bytes: Vec<u8> = floats.iter().flat_map(|f| f.to_le_bytes()).collect();
    // Minimal base64 (standard alphabet, padded).
    const A: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::new();
    for c in bytes.chunks(3) {
        let n = (c[0] as u32) << 16
            | (*c.get(1).unwrap_or(&0) as u32) << 8
            | *c.get(2).unwrap_or(&0) as u32;
        for i in 0..4 {
            if i <= c.len() {
                s.push(A[(n >> (18 - 6 * i) & 63) as usize] as char);
            } else {
                s.push('=');
            }
        }
    }
    format!("data:application/octet-stream;base64,{s}")
}

fn exr_with(dir: &Path, name: &str, value: f32) -> String {
    let mut img = image::Rgb32FImage::from_pixel(8, 4, image::Rgb([0.5, 0.5, 0.5]));
    img.put_pixel(3, 2, image::Rgb([value, 0.0, 0.0]));
    let p = dir.join(name);
    img.save_with_format(&p, image::ImageFormat::OpenExr)
        .unwrap();
    p.to_str().unwrap().to_string()
}

#[test]
fn every_bad_input_exits_2_with_one_line() {
    let view_script = write(&scratch(), "view.txt", b"aov ao\nteleport home\n");
    let d = scratch();
    let uri = triangle_data_uri();
    let good_gltf = write(&d, "good.gltf", gltf(&uri, "").as_bytes());
    let cases: Vec<(Vec<String>, &str)> = vec![
        (vec!["render".into(), d.join("nope.gltf").to_str().unwrap().into()], "no such file"),
        (vec!["render".into(), write(&d, "scene.xyz", b"hello")], "unknown scene format"),
        (vec!["render".into(), write(&d, "corrupt.gltf", b"{ not json")], "invalid glTF"),
        (vec!["render".into(), write(&d, "corrupt.glb", b"glTF\x02\x00\x00\x00garbage")], "invalid glTF"),
        (vec!["render".into(), write(&d, "nobuffer.gltf", gltf("missing.bin", "").as_bytes())], "buffer"),
        (
            vec![
                "render".into(),
                write(
                    &d,
                    "notexture.gltf",
                    gltf(&uri, r#","images":[{"uri":"missing.png"}],"textures":[{"source":0}]"#)
                        .replace(r#""materials":[{}]"#, r#""materials":[{"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}}]"#)
                        .as_bytes(),
                ),
            ],
            "image",
        ),
        (
            vec![
                "render".into(),
                write(&d, "required.gltf", gltf(&uri, r#","extensionsUsed":["KHR_draco_mesh_compression"],"extensionsRequired":["KHR_draco_mesh_compression"]"#).as_bytes()),
            ],
            "KHR_draco_mesh_compression",
        ),
        (vec!["render".into(), write(&d, "corrupt.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n")], "OBJ"),
        (vec!["render".into(), write(&d, "empty.obj", b"# nothing\n")], "empty.obj"),
        (vec!["render".into(), write(&d, "corrupt.ply", b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_header\n0\n1\n")], "PLY"),
        (vec!["render".into(), write(&d, "badindex.ply", b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n")], "vertex 7"),
        (vec!["render".into(), good_gltf.clone(), "--env".into(), write(&d, "corrupt.hdr", b"#?RADIANCE\ngarbage")], "environment"),
        (vec!["render".into(), good_gltf.clone(), "--env".into(), write(&d, "corrupt.exr", b"not an exr")], "environment"),
        (vec!["render".into(), good_gltf.clone(), "--env".into(), exr_with(&d, "nan.exr", f32::NAN)], "not finite"),
        (vec!["render".into(), good_gltf.clone(), "--env".into(), exr_with(&d, "inf.exr", f32::INFINITY)], "not finite"),
        (vec!["render".into(), good_gltf.clone(), "--env".into(), d.join("missing.hdr").to_str().unwrap().into()], "no such file"),
        (vec!["render".into(), "--env".into(), "constant:1,x,2".into()], "constant:R,G,B"),
        (vec!["render".into(), "--size".into(), "0x0".into()], "at least 1"),
        (vec!["render".into(), "--size".into(), "100000x100000".into()], "largest side"),
        (vec!["render".into(), "--size".into(), "big".into()], "WIDTHxHEIGHT"),
        (vec!["render".into(), "--method".into(), "magic".into()], "unknown technique"),
        (vec!["render".into(), "--dynamic".into(), "chair".into()], "no node of builtin:cornell"),
        (vec!["render".into(), write(&d, "plain.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"), "--dynamic".into(), "box".into()], "names no nodes"),
        (
            vec![
                "render".into(),
                write(&d, "extras.gltf", gltf(&uri, "").replace(r#""nodes":[{"mesh":0}]"#, r#""nodes":[{"mesh":0,"extras":{"nearfield":3}}]"#).as_bytes()),
            ],
            "must be an object",
        ),
        (
            vec![
                "render".into(),
                write(&d, "extras2.gltf", gltf(&uri, "").replace(r#""nodes":[{"mesh":0}]"#, r#""nodes":[{"mesh":0,"extras":{"nearfield":{"dynamic":"yes"}}}]"#).as_bytes()),
            ],
            "must be true or false",
        ),
        (vec!["render".into(), "--add".into(), format!("{good_gltf}@1,2")], "--add"),
        (vec!["render".into(), "--add".into(), format!("{good_gltf}@1,2,3,-1")], "scale"),
        (vec!["compare".into(), "--methods".into(), "hbil".into(), "--footprint".into()], "no dynamic node"),
        (vec!["render".into(), "--far".into(), "sky".into(), "--spacing".into(), "2".into()], "no volume to bake"),
        (vec!["render".into(), "--radius".into(), "sometimes".into()], "auto"),
        (vec!["render".into(), "--method".into(), "ssdo:layers=3".into()], "layers=3"),
        (vec!["render".into(), "--method".into(), "ssdo:cameras=9".into()], "cameras=9"),
        (vec!["render".into(), "--method".into(), "instant-radiosity:vpl_clamp=2".into(), "--size".into(), "64x36".into()], "vpl_clamp 2 > radius"),
        (vec!["render".into(), "--method".into(), "instant-radiosity:rsm=8".into()], "rsm"),
        (vec!["render".into(), "--method".into(), "ssdo:steps=17".into()], "steps"),
        (vec!["compare".into(), "--methods".into(), "ssdo".into(), "--region".into(), "1,2,3".into()], "--region"),
        (vec!["compare".into(), "--methods".into(), "ssdo".into(), "--region".into(), "50,0,10,10".into()], "--region"),
        (vec!["compare".into(), "--methods".into(), "ssdo".into(), "--strip".into(), d.join("strip.jpg").to_str().unwrap().into()], "must be a .png"),
        (vec!["compare".into(), "--methods".into(), "ssdo".into(), "--strip".into(), d.join("no/such/dir/s.png").to_str().unwrap().into()], "does not exist"),
        (vec!["compare".into(), "--methods".into(), "ssdo".into(), "--strip-errors".into()], "--strip"),
        (vec!["render".into(), "--aov".into(), "magic".into()], "unknown AOV"),
        (vec!["render".into(), "--aov".into(), "ao".into(), "-o".into(), "x.png".into()], ".exr"),
        (vec!["render".into(), "-o".into(), d.join("no/such/dir/x.png").to_str().unwrap().into()], "does not exist"),
        (vec!["render".into(), "--camera".into(), write(&d, "cam.json", br#"{"target":[0,0,0],"yfov_deg":45}"#)], "missing field `eye`"),
        (vec!["render".into(), "--camera".into(), write(&d, "cam2.json", br#"{"eye":[0,0,0],"target":[0,0,0],"yfov_deg":45}"#)], "coincide"),
        (vec!["render".into(), "--camera".into(), "7".into()], "camera(s)"),
        (vec!["render".into(), "--fov".into(), "0".into()], "--fov"),
        (vec!["render".into(), "--radius".into(), "-1".into()], "--radius"),
        (vec!["render".into(), "--radius".into(), "nan".into()], "--radius"),
        (vec!["render".into(), "--samples".into(), "0".into()], "--samples"),
        (vec!["render".into(), "--set".into(), "radius".into()], "KEY=VALUE"),
        (vec!["render".into(), "--set".into(), "foo=1".into()], "unknown setting"),
        (vec!["render".into(), "--frames".into(), "0".into()], "--frames"),
        (vec!["render".into(), "--exposure".into(), "nan".into()], "--exposure"),
        (vec!["render".into(), "--tonemap".into(), "magic".into()], "--tonemap"),
        (vec!["render".into(), "--env-intensity".into(), "-1".into()], "--env-intensity"),
        (vec!["bake".into(), "--env-intensity".into(), "0".into()], "--env-intensity 0: must be a finite number > 0"),
        (vec!["render".into(), "builtin:nope".into()], "unknown built-in scene"),
        (vec!["render".into(), "--sun".into(), "maybe".into()], "--sun maybe: expected auto or off"),
        (vec!["reference".into(), "--sun".into(), "maybe".into()], "--sun maybe"),
        (vec!["view".into(), "--sun".into(), "maybe".into()], "--sun maybe"),
        (vec!["reference".into(), "--senders".into(), "shady".into()], "--senders shady: expected physical or unshadowed"),
        (vec!["render".into(), "--adapter".into(), "no-such-gpu-xyz".into()], "no GPU adapter"),
        (vec!["bench".into(), "--methods".into(), "none,magic".into()], "unknown technique"),
        (vec!["bench".into(), "--json".into(), d.join("no/such/dir/b.json").to_str().unwrap().into()], "does not exist"),
        (vec!["bench".into(), "--ablate".into(), "--methods".into(), "none,gtao".into()], "--ablate times one method"),
        (vec!["render".into(), "--no-such-flag".into()], "--no-such-flag"),
        (vec!["reference".into(), "--radius".into(), "-1".into()], "--radius"),
        (vec!["reference".into(), "--radius".into(), "nan".into()], "--radius"),
        (vec!["reference".into(), "--spp".into(), "0".into()], "--spp"),
        (vec!["reference".into(), "--max-depth".into(), "0".into()], "--max-depth"),
        (vec!["reference".into(), "--aov".into(), "final".into()], "does not compute"),
        (vec!["reference".into(), "-o".into(), "ref.png".into()], ".exr"),
        (vec!["reference".into(), "--size".into(), "0x0".into()], "at least 1"),
        (vec!["reference".into(), d.join("nope.obj").to_str().unwrap().into()], "no such file"),
        (vec!["reference".into(), "--camera".into(), write(&d, "cam3.json", b"{}")], "missing field"),
        (vec!["compare".into(), "--reference".into(), d.join("missing.exr").to_str().unwrap().into(), "--out".into(), d.join("c1").to_str().unwrap().into()], "no such file"),
        (vec!["compare".into(), "--reference".into(), write(&d, "notexr.exr", b"hello"), "--out".into(), d.join("c2").to_str().unwrap().into()], "not a readable OpenEXR"),
        (vec!["compare".into(), "--size".into(), "32x16".into(), "--reference".into(), exr_with(&d, "small.exr", 1.0), "--out".into(), d.join("c3").to_str().unwrap().into()], "reference is 8x4"),
        (vec!["compare".into(), "--methods".into(), "magic".into()], "unknown technique"),
        (vec!["compare".into(), "--aov".into(), "motion".into()], "does not compute"),
        (vec!["compare".into(), "--spp".into(), "0".into()], "--spp"),
        (vec!["render".into(), "--size".into(), "16x16".into(), "--method".into(), "ssdo".into(), "--set".into(), "mode=magic".into()], "mode=magic"),
        (vec!["render".into(), "--size".into(), "16x16".into(), "--method".into(), "ssdo".into(), "--radius".into(), "inf".into()], "radius=inf: must be a finite number"),
        (vec!["render".into(), "--size".into(), "16x16".into(), "--method".into(), "ssao".into(), "--set".into(), "lod=99".into()], "lod=99"),
        (vec!["render".into(), "--size".into(), "16x16".into(), "--method".into(), "ssdo".into(), "--set".into(), "bounce=maybe".into()], "on or off"),
        (vec!["bench".into(), "--size".into(), "16x16".into(), "--methods".into(), "ssdo:nosuch=1".into()], "unknown setting"),
        (vec!["render".into(), "--size".into(), "16x16".into(), "--method".into(), "s3ho".into(), "--set".into(), "steps=0".into()], "steps=0"),
        (vec!["render".into(), "--size".into(), "16x16".into(), "--method".into(), "s3ho".into(), "--set".into(), "lambda=-1".into()], "lambda=-1"),
        (vec!["render".into(), "--size".into(), "16x16".into(), "--method".into(), "ssbn".into(), "--set".into(), "indirect=maybe".into()], "on or off"),
        (vec!["render".into(), "--size".into(), "16x16".into(), "--method".into(), "hbil".into(), "--set".into(), "slices=0".into()], "slices=0"),
        (vec!["render".into(), "--size".into(), "16x16".into(), "--method".into(), "gtao".into(), "--set".into(), "steps=999".into()], "steps=999"),
        (vec!["render".into(), "--size".into(), "16x16".into(), "--method".into(), "hbil".into(), "--radius".into(), "inf".into()], "radius=inf: must be a finite number"),
        (vec!["render".into(), "--size".into(), "16x16".into(), "--method".into(), "hbil".into(), "--set".into(), "reprojection=teleport".into()], "scatter or gather"),
        (vec!["render".into(), "--size".into(), "16x16".into(), "--method".into(), "hbil".into(), "--set".into(), "far=moon".into()], "sh, envmap or slices"),
        (vec!["render".into(), "--size".into(), "16x16".into(), "--method".into(), "gtao".into(), "--set".into(), "resolution=quarter".into()], "full or half"),
        (vec!["render".into(), "--size".into(), "16x16".into(), "--method".into(), "hbil".into(), "--set".into(), "quality=insane".into()], "low, medium, high, ultra"),
        (vec!["render".into(), "--size".into(), "16x16".into(), "--method".into(), "hbil".into(), "--set".into(), "temporal=sometimes".into()], "on or off"),
        (vec!["render".into(), "--size".into(), "16x16".into(), "--method".into(), "hbil".into(), "--set".into(), "reject_a=0.5".into()], "reject_a"),
        (vec!["render".into(), "--size".into(), "16x16".into(), "--method".into(), "hbil".into(), "--aov".into(), "nosuch".into()], "unknown AOV for hbil"),
        (vec!["render".into(), "--size".into(), "16x16".into(), "--method".into(), "hbil".into(), "--set".into(), "aperture=wide".into()], "eq12 or matched"),
        (vec!["render".into(), "--size".into(), "16x16".into(), "--method".into(), "hbil".into(), "--set".into(), "source=magic".into()], "previous or direct"),
        (vec!["render".into(), "--size".into(), "16x16".into(), "--method".into(), "vbgi".into(), "--set".into(), "sectors=7".into()], "expected 8, 16 or 32"),
        (vec!["render".into(), "--size".into(), "16x16".into(), "--method".into(), "vbgi".into(), "--set".into(), "thickness=thin".into()], "layer, constant or adaptive"),
        (vec!["render".into(), "--size".into(), "16x16".into(), "--method".into(), "vbgi".into(), "--set".into(), "thickness_m=0".into()], "thickness_m=0"),
        (vec!["render".into(), "--size".into(), "16x16".into(), "--method".into(), "vbgi".into(), "--set".into(), "thickness_ratio=-1".into()], "thickness_ratio=-1"),
        (vec!["render".into(), "--size".into(), "16x16".into(), "--method".into(), "vbgi".into(), "--set".into(), "far=slices".into()], "sectors, sh or envmap"),
        (vec!["render".into(), "--size".into(), "16x16".into(), "--method".into(), "vbgi".into(), "--set".into(), "denoise=magic".into()], "svgf, bilateral or off"),
        (vec!["render".into(), "--size".into(), "16x16".into(), "--method".into(), "vbgi".into(), "--set".into(), "svgf_iterations=9".into()], "svgf_iterations=9"),
        (vec!["render".into(), "--size".into(), "16x16".into(), "--method".into(), "vbgi".into(), "--set".into(), "svgf_luminance=nan".into()], "svgf_luminance=nan"),
        (vec!["render".into(), "--size".into(), "16x16".into(), "--method".into(), "hbil".into(), "--set".into(), "denoise=maybe".into()], "svgf, bilateral or off"),
        (vec!["render".into(), "--size".into(), "16x16".into(), "--method".into(), "ssdo".into(), "--set".into(), "svgf_depth=0".into()], "svgf_depth=0"),
        (vec!["render".into(), "--size".into(), "16x16".into(), "--method".into(), "vbgi".into(), "--set".into(), "svgf_motion=0".into()], "svgf_motion=0: must be in 0.001..=100"),
        (vec!["render".into(), "--size".into(), "16x16".into(), "--method".into(), "vbgi".into(), "--set".into(), "svgf_reach=0".into()], "svgf_reach=0: must be in 0.01..=1000000"),
        (vec!["render".into(), "--size".into(), "16x16".into(), "--method".into(), "hbil:hidden=bogus".into()], "expected last, volume or unbaked"),
        (vec!["render".into(), "--size".into(), "16x16".into(), "--method".into(), "vbgi".into(), "--set".into(), "slices=0".into()], "slices=0"),
        (vec!["render".into(), "--size".into(), "16x16".into(), "--method".into(), "vbgi".into(), "--set".into(), "steps=999".into()], "steps=999"),
        (vec!["render".into(), "--size".into(), "16x16".into(), "--method".into(), "vbgi".into(), "--set".into(), "reject_a=0.5".into()], "reject_a"),
        (vec!["render".into(), "--size".into(), "16x16".into(), "--method".into(), "hbil".into(), "--set".into(), "blur=off".into()], "unknown setting 'blur'"),
        (vec!["render".into(), "--size".into(), "16x16".into(), "--orbit".into(), "nan".into()], "--orbit"),
        (vec!["render".into(), "--size".into(), "16x16".into(), "--orbit".into(), "720".into()], "--orbit"),
        (vec!["bench".into(), "--size".into(), "16x16".into(), "--methods".into(), "gtao".into(), "--orbit".into(), "inf".into()], "--orbit"),
        (vec!["compare".into(), "--size".into(), "16x16".into(), "--methods".into(), "hbil".into(), "--orbit".into(), "-999".into()], "--orbit"),
        // The viewer checks everything typed before a window opens.
        (vec!["view".into(), "--frames".into(), "0".into()], "--frames 0"),
        (vec!["view".into(), "--screenshot".into(), "v.png".into()], "needs --frames"),
        (vec!["view".into(), "--frames".into(), "2".into(), "--screenshot".into(), "v.jpg".into()], ".png"),
        (vec!["view".into(), "--script".into(), "/nonexistent/view.txt".into()], "--script"),
        (vec!["view".into(), "--script".into(), view_script.clone()], "line 2: unknown command 'teleport'"),
        (vec!["view".into(), "--method".into(), "magic".into()], "unknown technique"),
        (vec!["view".into(), "--split-with".into(), "ssdo:samples=0".into()], "samples=0"),
        (vec!["view".into(), "--method".into(), "hbil".into(), "--set".into(), "quality=insane".into()], "low, medium, high, ultra"),
        (vec!["view".into(), "--method".into(), "ssdo".into(), "--radius".into(), "inf".into()], "radius=inf"),
        (vec!["view".into(), "--size".into(), "0x0".into()], "--size"),
        (vec!["view".into(), "/nonexistent/scene.glb".into()], "scene.glb"),
        // fit: everything is checked before a scene is loaded or a reference rendered.
        (fit(&["--params", "nosuch", "--scenes", "builtin:cornell"]), "has no setting 'nosuch'"),
        (fit(&["--params", "mode", "--scenes", "builtin:cornell"]), "not a numeric setting"),
        (fit(&["--params", "bounce", "--scenes", "builtin:cornell"]), "not a numeric setting"),
        (fit(&["--params", "", "--scenes", "builtin:cornell"]), "names no setting"),
        (fit(&["--params", "strength,strength", "--scenes", "builtin:cornell"]), "named twice"),
        (fit(&["--params", "strength=5..1", "--scenes", "builtin:cornell"]), "LO..HI"),
        (fit(&["--params", "strength=0..99", "--scenes", "builtin:cornell"]), "LO..HI"),
        (fit(&["--params", "strength=a..b", "--scenes", "builtin:cornell"]), "KEY=LO..HI"),
        (fit(&["--params", "strength", "--scenes", ""]), "names no scene"),
        (fit(&["--params", "strength", "--scenes", ",,"]), "names no scene"),
        (fit(&["--params", "strength", "--scenes", "builtin:cornell", "--budget", "0"]), "--budget 0"),
        (fit(&["--params", "strength,fade", "--scenes", "builtin:cornell", "--budget", "2"]), "at least 3"),
        (fit(&["--params", "strength", "--scenes", "builtin:cornell", "--metric", "mse"]), "--metric mse"),
        (fit(&["--params", "strength", "--scenes", "builtin:cornell", "--aov", "motion"]), "does not compute"),
        (fit(&["--params", "strength", "--scenes", "builtin:cornell", "--holdout", "builtin:cornell"]), "also a training scene"),
        (fit(&["--params", "strength", "--scenes", "builtin:cornell:env="]), "names no environment"),
        (fit(&["--params", "strength", "--scenes", "builtin:cornell", "--radius", "inf"]), "finite"),
        (fit(&["--params", "strength", "--scenes", "builtin:cornell", "--frames", "0"]), "--frames 0"),
        (fit(&["--params", "strength", "--scenes", "builtin:cornell", "--out", "/nonexistent/dir/fit.json"]), "does not exist"),
        (vec!["fit".into(), "magic".into(), "--params".into(), "strength".into(), "--scenes".into(), "builtin:cornell".into()], "unknown technique"),
        (fit(&["--params", "strength", "--scenes", "/nonexistent/scene.glb", "--holdout", "none", "--size", "16x16"]), "scene.glb"),
        (fit(&["--params", "strength", "--scenes", "builtin:nosuch", "--holdout", "none", "--size", "16x16"]), "nosuch"),
        // pareto: the sweep is checked before anything is loaded.
        (pareto(&["--methods", "magic"]), "unknown technique"),
        (pareto(&["--methods", "gtao:nosuch=1"]), "nosuch"),
        (pareto(&["--methods", "gtao:slices=0"]), "slices"),
        (pareto(&["--methods", "none"]), "empty sweep"),
        (pareto(&["--methods", ","]), "no technique"),
        (pareto(&["--methods", "gtao", "--vary", "steps="]), "empty sweep"),
        (pareto(&["--methods", "gtao", "--vary", "steps"]), "KEY=V1,V2"),
        (pareto(&["--methods", "gtao", "--vary", "nosuch=1,2"]), "empty sweep"),
        (pareto(&["--methods", "gtao", "--vary", "steps=1", "--vary", "steps=2"]), "named twice"),
        (pareto(&["--methods", "gtao", "--radius", "inf"]), "finite"),
        (pareto(&["--methods", "gtao", "--timed", "0"]), "--timed 0"),
        (pareto(&["--methods", "gtao", "--frames", "0"]), "--frames 0"),
        (pareto(&["--methods", "gtao", "--aov", "motion"]), "motion"),
        (pareto(&["--methods", "gtao", "--size", "0x10"]), "--size"),
        (pareto(&["/nonexistent/scene.glb", "--methods", "gtao", "--size", "16x16"]), "scene.glb"),
        // export and compare --image.
        (args(&["export", "builtin:cornell", "--out", "/tmp/x.obj"]), ".glb or .gltf"),
        (args(&["export", "builtin:cornell", "--out", "/nonexistent/dir/x.glb"]), "does not exist"),
        (args(&["export", "builtin:nosuch", "--out", "/tmp/nearfield-x.glb"]), "nosuch"),
        (args(&["compare", "--methods", "gtao", "--image", "noequals"]), "NAME=FILE.exr"),
        (args(&["compare", "--methods", "gtao", "--image", "gtao=x.exr"]), "is taken"),
        (args(&["compare", "--methods", "gtao", "--image", "a/b=x.exr"]), "may hold"),
        (args(&["compare", "--methods", "gtao", "--image", "peer=/nonexistent/ao.exr"]), "ao.exr"),
        // The probe volume: grids beyond the budget, no rays, bad spacings, bad files.
        (args(&["bake", "builtin:cornell", "--spacing", "0.001"]), "probe budget is 65536"),
        (args(&["bake", "builtin:cornell", "--probes", "100,100,100"]), "probe budget is 65536"),
        (args(&["bake", "builtin:cornell", "--probes", "0,2,2"]), "--probes 0,2,2"),
        (args(&["bake", "builtin:cornell", "--rays", "0"]), "--rays 0"),
        (args(&["bake", "builtin:cornell", "--spacing", "0"]), "--spacing 0"),
        (args(&["bake", "builtin:cornell", "--spacing=-0.5"]), "--spacing -0.5"),
        (args(&["bake", "builtin:cornell", "--spacing", "NaN"]), "--spacing NaN"),
        (args(&["bake", "builtin:cornell", "--out", "/tmp/volume.png"]), ".nfv"),
        (args(&["bake", "builtin:cornell", "--out", "/nonexistent/dir/v.nfv"]), "does not exist"),
        (args(&["bake", "builtin:cornell", "--format", "unity"]), "expected nfv or bevy"),
        (args(&["bake", "builtin:cornell", "--format", "bevy", "--out", "/tmp/v.nfv"]), "written as .ktx2"),
        (args(&["bake", "builtin:cornell", "--format", "nfv", "--out", "/tmp/v.ktx2"]), "written as .nfv"),
        (args(&["render", "builtin:cornell", "--size", "16x16", "--volume", "/nonexistent/v.nfv"]), "no such file"),
        // Camera paths: unreadable, no keyframes, times out of order, NaN, absurd rates.
        (vec!["render".into(), "--path".into(), d.join("nopath.json").to_str().unwrap().into()], "no such file"),
        (vec!["render".into(), "--path".into(), write(&d, "p0.json", br#"{"fps":30,"keyframes":[]}"#)], "no keyframes"),
        (vec!["compare".into(), "--path".into(), write(&d, "p1.json", br#"{"fps":30,"keyframes":[{"t":1,"eye":[0,1,4],"target":[0,1,0],"yfov_deg":45},{"t":0,"eye":[1,1,4],"target":[0,1,0],"yfov_deg":45}]}"#)], "does not come after"),
        (vec!["render".into(), "--path".into(), write(&d, "p2.json", br#"{"fps":30,"keyframes":[{"t":0,"eye":[0,1,4],"target":[0,1,0],"yfov_deg":NaN}]}"#)], "invalid camera path"),
        (vec!["render".into(), "--path".into(), write(&d, "p3.json", b"\xff\xfe")], "invalid camera path"),
        (args(&["render", "--walk", "--fps", "0"]), "--fps 0"),
        (args(&["render", "--walk", "--orbit", "2"]), "moves the camera already"),
        (args(&["compare", "--walk", "--every", "0"]), "--every 0"),
    ];
    for (args, needle) in cases {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let (code, stderr) = nearfield(&args);
        let lines: Vec<&str> = stderr.lines().filter(|l| !l.trim().is_empty()).collect();
        assert_eq!(code, 2, "{args:?}: exit {code}, stderr:\n{stderr}");
        assert!(!stderr.contains("panicked"), "{args:?} panicked:\n{stderr}");
        assert_eq!(
            lines.len(),
            1,
            "{args:?}: expected one line, got:\n{stderr}"
        );
        assert!(
            stderr.contains(needle),
            "{args:?}: '{needle}' not in:\n{stderr}"
        );
    }
}

/// `pareto builtin:cornell ARGS…`.
fn pareto(a: &[&str]) -> Vec<String> {
    ["pareto", "builtin:cornell"]
        .iter()
        .chain(a)
        .map(|s| s.to_string())
        .collect()
}

fn args(a: &[&str]) -> Vec<String> {
    a.iter().map(|s| s.to_string()).collect()
}

/// `fit ssdo ARGS…`.
fn fit(args: &[&str]) -> Vec<String> {
    ["fit", "ssdo"]
        .iter()
        .chain(args)
        .map(|s| s.to_string())
        .collect()
}

/// The one-triangle glTF of [`gltf`] as JSON, changed by `edit`.
fn gltf_with(edit: impl FnOnce(&mut serde_json::Value)) -> Vec<u8> {
    let mut v: serde_json::Value = serde_json::from_str(&gltf(&triangle_data_uri(), "")).unwrap();
    edit(&mut v);
    serde_json::to_vec(&v).unwrap()
}

/// A PNG data URI whose header claims `w`×`h` pixels and holds none.
/// The one-triangle glTF with its node translated by an animation (its key times [0, 1] and
/// values the triangle's first two vertices, from the triangle's buffer), changed by `edit`.
/// Accessor 3 holds the times [1, 0]; accessor 4 three VEC3 values.
fn animated(edit: impl FnOnce(&mut serde_json::Value)) -> Vec<u8> {
    use serde_json::json;
    gltf_with(|v| {
        let accessors = v["accessors"].as_array_mut().unwrap();
        accessors.extend([
            json!({"bufferView":0,"byteOffset":8,"componentType":5126,"count":2,"type":"SCALAR","min":[0],"max":[1]}),
            json!({"bufferView":0,"componentType":5126,"count":2,"type":"VEC3"}),
            json!({"bufferView":0,"byteOffset":12,"componentType":5126,"count":2,"type":"SCALAR","min":[0],"max":[1]}),
            json!({"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"}),
        ]);
        let mut a = json!({
            "samplers": [{"input": 1, "output": 2}],
            "channels": [{"sampler": 0, "target": {"node": 0, "path": "translation"}}],
        });
        edit(&mut a);
        v["animations"] = json!([a]);
    })
}

fn png_header_uri(w: u32, h: u32) -> String {
    let mut png = b"\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR".to_vec();
    png.extend(w.to_be_bytes());
    png.extend(h.to_be_bytes());
    png.extend([8, 6, 0, 0, 0]);
    let crc = png[12..].iter().fold(!0u32, |mut c, &b| {
        c ^= b as u32;
        for _ in 0..8 {
            c = if c & 1 != 0 {
                (c >> 1) ^ 0xEDB8_8320
            } else {
                c >> 1
            };
        }
        c
    });
    png.extend((!crc).to_be_bytes());
    // An empty IDAT chunk (CRC of "IDAT") so that the header can be read through.
    png.extend(b"\0\0\0\0IDAT\x35\xaf\x06\x1e");
    const A: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::new();
    for c in png.chunks(3) {
        let n = (c[0] as u32) << 16
            | (*c.get(1).unwrap_or(&0) as u32) << 8
            | *c.get(2).unwrap_or(&0) as u32;
        for i in 0..4 {
            s.push(if i <= c.len() {
                A[(n >> (18 - 6 * i) & 63) as usize] as char
            } else {
                '='
            });
        }
    }
    format!("data:image/png;base64,{s}")
}

/// Files whose structure is hostile (a node graph that is not a tree, accessors past their
/// buffers, image headers beyond the limits, absurd numbers, devices instead of files): every
/// command that loads a scene exits 2 with one line naming the problem, within a second.
#[test]
fn structurally_bad_files_exit_2_with_one_line_within_a_second() {
    use serde_json::json;
    let d = scratch().join("structure");
    std::fs::create_dir_all(&d).unwrap();
    let cycle = write(
        &d,
        "cycle.gltf",
        &gltf_with(|v| {
            v["nodes"] = json!([{"mesh":0,"children":[1]},{"children":[0]}]);
        }),
    );
    let mut cases: Vec<(Vec<String>, &str)> = Vec::new();
    // The non-tree glTF, for every command that loads a scene.
    for cmd in ["render", "reference", "compare", "bench", "view"] {
        let mut args = vec![
            cmd.to_string(),
            cycle.clone(),
            "--size".into(),
            "16x16".into(),
        ];
        if cmd == "compare" {
            args.extend(["--out".into(), d.join("cmp").to_str().unwrap().into()]);
        }
        cases.push((args, "not a tree"));
    }
    let scene = |name: &str, bytes: Vec<u8>| {
        vec![
            "render".to_string(),
            write(&d, name, &bytes),
            "--size".into(),
            "16x16".into(),
        ]
    };
    cases.extend([
        (scene("self.gltf", gltf_with(|v| v["nodes"] = json!([{"mesh":0,"children":[0]}]))), "its own child"),
        (scene("twoparents.gltf", gltf_with(|v| {
            v["nodes"] = json!([{"children":[2]},{"children":[2]},{"mesh":0}]);
            v["scenes"] = json!([{"nodes":[0,1]}]);
        })), "node 2 has two parents"),
        (scene("rootchild.gltf", gltf_with(|v| {
            v["nodes"] = json!([{"children":[1]},{"mesh":0}]);
            v["scenes"] = json!([{"nodes":[0,1]}]);
        })), "lists node 1 as a root"),
        (scene("count.gltf", gltf_with(|v| v["accessors"][0]["count"] = json!(1000))), "do not fit in buffer view 0"),
        (scene("offset.gltf", gltf_with(|v| v["accessors"][0]["byteOffset"] = json!(4294967290u64))), "do not fit"),
        (scene("stride.gltf", gltf_with(|v| v["bufferViews"][0]["byteStride"] = json!(4))), "stride"),
        (scene("view.gltf", gltf_with(|v| v["bufferViews"][0]["byteLength"] = json!(360))), "outside buffer 0"),
        (scene("sparse.gltf", gltf_with(|v| {
            v["bufferViews"] = json!([{"buffer":0,"byteLength":36},{"buffer":0,"byteLength":4}]);
            v["accessors"][0]["sparse"] = json!({"count":2,"indices":{"bufferView":1,"componentType":5125},"values":{"bufferView":1}});
        })), "sparse"),
        (scene("index.gltf", gltf_with(|v| {
            v["buffers"][0]["byteLength"] = json!(36);
            v["bufferViews"] = json!([{"buffer":0,"byteLength":36},{"buffer":0,"byteOffset":12,"byteLength":12}]);
            v["accessors"] = json!([v["accessors"][0].clone(),{"bufferView":1,"componentType":5125,"count":3,"type":"SCALAR"}]);
            v["meshes"][0]["primitives"][0]["indices"] = json!(1);
        })), "references vertex"),
        (scene("bigimage.gltf", gltf_with(|v| {
            v["images"] = json!([{"uri": png_header_uri(100_000, 100_000)}]);
            v["textures"] = json!([{"source":0}]);
            v["materials"] = json!([{"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}}]);
        })), "100000×100000"),
        (scene("translate.gltf", gltf_with(|v| v["nodes"][0]["translation"] = json!([1e30, 0, 0]))), "absurd transform"),
        (scene("overflow.gltf", gltf_with(|v| {
            v["nodes"] = json!([{"scale":[1e19,1e19,1e19],"children":[1]},{"scale":[1e19,1e19,1e19],"mesh":0}]);
        })), "world transform overflows"),
        (scene("zeroscale.gltf", gltf_with(|v| v["nodes"][0]["scale"] = json!([1, 0, 1]))), "zero-scale"),
        (scene("camera.gltf", gltf_with(|v| {
            v["cameras"] = json!([{"type":"perspective","perspective":{"yfov":4.0,"znear":0.1}}]);
            v["nodes"] = json!([{"mesh":0},{"camera":0,"translation":[0,0,3]}]);
            v["scenes"] = json!([{"nodes":[0,1]}]);
        })), "camera 0 at node 1: field of view"),
        (scene("light.gltf", gltf_with(|v| {
            v["extensionsUsed"] = json!(["KHR_lights_punctual"]);
            v["extensions"] = json!({"KHR_lights_punctual":{"lights":[{"type":"point","intensity":-5}]}});
            v["nodes"] = json!([{"mesh":0},{"extensions":{"KHR_lights_punctual":{"light":0}}}]);
            v["scenes"] = json!([{"nodes":[0,1]}]);
        })), "light intensity -5"),
        (scene("light-inf.gltf", gltf_with(|v| {
            v["extensionsUsed"] = json!(["KHR_lights_punctual"]);
            v["extensions"] = json!({"KHR_lights_punctual":{"lights":[{"type":"directional","intensity":1e39}]}});
            v["nodes"] = json!([{"mesh":0},{"extensions":{"KHR_lights_punctual":{"light":0}}}]);
            v["scenes"] = json!([{"nodes":[0,1]}]);
        })), "light intensity inf"),
        (scene("device.gltf", gltf_with(|v| v["buffers"][0]["uri"] = json!("/dev/zero"))), "not a regular file"),
        (scene("percent.gltf", gltf_with(|v| v["buffers"][0]["uri"] = json!("%ff%fe.bin"))), "not valid UTF-8"),
        // Animations: a channel whose sampler is missing, none at all, key times that go back,
        // more values than times, values of the wrong type.
        (scene("nosampler.gltf", animated(|a| a["channels"][0]["sampler"] = json!(3))), "sampler"),
        (scene("nosamplers.gltf", animated(|a| a["samplers"] = json!([]))), "sampler"),
        (scene("backwards.gltf", animated(|a| a["samplers"][0]["input"] = json!(3))), "not increasing"),
        (scene("counts.gltf", animated(|a| a["samplers"][0]["output"] = json!(4))), "2 key times but 3 values"),
        (scene("rotation.gltf", animated(|a| a["channels"][0]["target"]["path"] = json!("rotation"))), "not a type"),
        (scene("position.obj", b"v 0 0 0\nv 1e30 0 0\nv 0 1 0\nf 1 2 3\n".to_vec()), "absurd vertex position"),
        (scene("huge.ply", b"ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000\nproperty float x\nproperty float y\nproperty float z\nend_header\n".to_vec()), "beyond the limit"),
        (scene("lying.ply", b"ply\nformat ascii 1.0\nelement vertex 1000000\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n".to_vec()), "more than a"),
        (vec!["render".into(), "--env".into(), write(&d, "huge.hdr", b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 100000 +X 200000\n")], "beyond the limit"),
        (vec!["render".into(), "--camera".into(), "/dev/zero".into()], "not a regular file"),
        (vec!["render".into(), "/dev/zero.obj".into()], "no such file"),
        (vec!["view".into(), "--script".into(), "/dev/zero".into()], "not a regular file"),
    ]);
    // More memory than a CPU adapter has (the system's): refused before anything is made. The
    // side is chosen from this machine's available memory; beyond 8192 (the size limit) a
    // machine with that much memory has no such case.
    let available = std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|t| {
            t.lines()
                .find(|l| l.starts_with("MemAvailable:"))
                .and_then(|l| l.split_whitespace().nth(1)?.parse::<u64>().ok())
        })
        .unwrap_or(0)
        * 1024;
    let side = ((available as f64 / 512.0).sqrt() * 1.2).ceil() as u64;
    if available > 0 && side <= 8192 {
        cases.push((
            vec!["render".into(), "--size".into(), format!("{side}x{side}")],
            "MiB of GPU memory",
        ));
    }
    for (args, needle) in cases {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let start = std::time::Instant::now();
        let (code, stderr) = nearfield(&args);
        let secs = start.elapsed().as_secs_f64();
        let lines: Vec<&str> = stderr.lines().filter(|l| !l.trim().is_empty()).collect();
        assert_eq!(code, 2, "{args:?}: exit {code}, stderr:\n{stderr}");
        assert_eq!(
            lines.len(),
            1,
            "{args:?}: expected one line, got:\n{stderr}"
        );
        assert!(
            stderr.contains(needle),
            "{args:?}: '{needle}' not in:\n{stderr}"
        );
        assert!(secs < 1.0, "{args:?}: took {secs:.2} s");
    }
}

/// `--volume` files that cannot be read: a truncated file, another version, no volume at all,
/// a directory. Each exits 2 with one line within a second and writes no image; a stale or
/// damaged cache entry is baked again, never read.
#[test]
fn bad_volume_files_exit_2_and_stale_cache_entries_are_rebuilt() {
    let d = scratch().join("volume");
    std::fs::create_dir_all(&d).unwrap();
    let cache = d.join("cache");
    let run = |args: &[&str]| nearfield_with(args, &[("NEARFIELD_CACHE", &cache)]);
    let good = d.join("good.nfv");
    let bake = [
        "bake",
        "builtin:plane",
        "--probes",
        "3,2,3",
        "--rays",
        "8",
        "--bounces",
        "1",
        "--out",
        good.to_str().unwrap(),
    ];
    // The first bake writes the cache entry, the second reads it.
    let (code, err) = run(&bake);
    assert_eq!(code, 0, "{err}");
    assert!(!err.contains("from the cache"), "{err}");
    let bytes = std::fs::read(&good).unwrap();
    let mut other_version = bytes.clone();
    other_version[8..12].copy_from_slice(&2u32.to_le_bytes());
    let cases = [
        (
            write(&d, "truncated.nfv", &bytes[..bytes.len() - 7]),
            "truncated",
        ),
        (write(&d, "version.nfv", &other_version), "version 2"),
        (
            write(&d, "garbage.nfv", b"a probe volume, it says"),
            "not a nearfield probe volume",
        ),
        (d.to_str().unwrap().to_string(), "volume"),
    ];
    for (file, needle) in cases {
        let image = d.join("out.png");
        let started = std::time::Instant::now();
        let (code, err) = run(&[
            "render",
            "builtin:plane",
            "--size",
            "16x16",
            "--volume",
            &file,
            "-o",
            image.to_str().unwrap(),
        ]);
        let lines: Vec<&str> = err.lines().filter(|l| !l.trim().is_empty()).collect();
        assert_eq!(code, 2, "{file}: exit {code}:\n{err}");
        assert_eq!(lines.len(), 1, "{file}: one line:\n{err}");
        assert!(err.contains(needle), "{file}: '{needle}' not in:\n{err}");
        assert!(
            started.elapsed().as_secs_f32() < 1.0,
            "{file}: {:?}",
            started.elapsed()
        );
        assert!(!image.exists(), "{file}: an image was written");
    }
    // A damaged cache entry is baked again, and the entry rewritten.
    let (_, err) = run(&bake);
    assert!(err.contains("from the cache"), "{err}");
    let entries: Vec<_> = std::fs::read_dir(cache.join("volume"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    assert_eq!(entries.len(), 1, "{entries:?}");
    for damage in [&bytes[..100], &other_version[..]] {
        std::fs::write(&entries[0], damage).unwrap();
        let (code, err) = run(&bake);
        assert_eq!(code, 0, "{err}");
        assert!(
            !err.contains("from the cache"),
            "a damaged entry was read: {err}"
        );
        let (_, err) = run(&bake);
        assert!(
            err.contains("from the cache"),
            "the entry was rebuilt: {err}"
        );
    }
}
