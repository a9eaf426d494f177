// push_pull.wgsl — hole filling of the reprojected radiance (passes/reproject.rs): `push`
// averages each 2×2 block of the finer level weighted by alpha into the next coarser level;
// `pull` fills level k from level k + 1 (bilinear) where its alpha is below 1, coarsest first.
// Level sizes come from the textures.

@group(1) @binding(0) var fine: texture_2d<f32>;
@group(1) @binding(1) var level_out: texture_storage_2d<rgba16float, write>;
@group(1) @binding(2) var coarse: texture_2d<f32>;
@group(1) @binding(3) var coarse_sampler: sampler;

@compute @workgroup_size(8, 8, 1)
fn push(@builtin(global_invocation_id) id: vec3<u32>) {
    let c = id.xy;
    if any(c >= textureDimensions(level_out)) {
        return;
    }
    let fine_size = textureDimensions(fine);
    var sum = vec3<f32>(0.0);
    var alpha = 0.0;
    for (var k = 0u; k < 4u; k++) {
        let q = 2u * c + vec2<u32>(k % 2u, k / 2u);
        if any(q >= fine_size) {
            continue;
        }
        let v = textureLoad(fine, q, 0);
        sum += v.rgb * v.a;
        alpha += v.a;
    }
    var out = vec4<f32>(0.0);
    if alpha > 0.0 {
        out = vec4<f32>(sum / alpha, min(alpha, 1.0));
    }
    textureStore(level_out, c, out);
}

@compute @workgroup_size(8, 8, 1)
fn pull(@builtin(global_invocation_id) id: vec3<u32>) {
    let p = id.xy;
    let size = textureDimensions(level_out);
    if any(p >= size) {
        return;
    }
    let v = textureLoad(fine, p, 0);
    let uv = (vec2<f32>(p) + 0.5) / vec2<f32>(size);
    let c = textureSampleLevel(coarse, coarse_sampler, uv, 0.0);
    textureStore(level_out, p, vec4<f32>(v.rgb * v.a + c.rgb * (1.0 - v.a), v.a + c.a * (1.0 - v.a)));
}
