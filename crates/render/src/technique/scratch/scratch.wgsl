// scratch.wgsl — the test build's scratch technique (feature `scratch`, tests/scratch.rs): a
// constant occlusion, ao = 1 − occlusion / TAPS on surfaces, no indirect light, the far field's
// irradiance as the direct pass left it. It exists to show that a family's folder and its one
// registry line reach every consumer.

struct ScratchParams {
    occlusion: f32,
    _pad0: f32,
    _pad1: f32,
    _pad2: f32,
}

// The count `taps`, specialised from the declaration (settings::count_constants).
override TAPS: u32 = 1u;

@group(1) @binding(0) var<uniform> params: ScratchParams;
@group(1) @binding(1) var gb_normal: texture_2d<f32>;
@group(1) @binding(2) var out_ao: texture_storage_2d<r32float, write>;
@group(1) @binding(3) var out_indirect_irradiance: texture_storage_2d<rgba16float, write>;

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let pixel = id.xy;
    if !in_bounds(view, pixel) {
        return;
    }
    if textureLoad(gb_normal, pixel, 0).w == 0.0 {
        textureStore(out_ao, pixel, vec4<f32>(0.0));
        textureStore(out_indirect_irradiance, pixel, vec4<f32>(0.0));
        return;
    }
    textureStore(out_ao, pixel, vec4<f32>(1.0 - params.occlusion / f32(TAPS)));
    textureStore(out_indirect_irradiance, pixel, vec4<f32>(0.0, 0.0, 0.0, 1.0));
}
