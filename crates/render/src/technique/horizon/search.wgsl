// search.wgsl — the horizon search in slices (the `horizon` kernel): ao, bent cone, near-field light and the far field through each slice's visible arcs.
// Sources: technique/horizon/mod.rs; the derivations sit beside the code (slice.wgsl, march.wgsl).

// horizon: one invocation per pixel of one layer. The 16 layers are stacked vertically in one
// 2D dispatch (rows of workgroups [l·G, (l+1)·G) with G = ⌈layer height / 8⌉ serve layer l);
// without interleaving there is one full-size layer.
// Inputs: with interleaving `in_normal` is the split geometry (xyz normal, w depth) and
// `in_depth` is not read; without, they are the G-buffer's normal and view depth. The results
// go straight to the layer texel's full-resolution pixel (no re-interleaving pass). With HALF
// (`resolution=half`) there is one invocation per 2×2 block instead (slice.wgsl's `march_at`).
// Everything is computed in view space (positions from depth and pixel, no matrix per sample);
// the bent normal and the far field's directions go back to world space.
// NEAR (hbil's near-field light) and FAR (the far field through the arcs) are override
// constants: gtao's pipeline has neither, and writes only the cone.

@group(1) @binding(0) var<uniform> params: HorizonParams;
@group(1) @binding(1) var in_depth: texture_2d_array<f32>;
@group(1) @binding(2) var in_normal: texture_2d_array<f32>;
@group(1) @binding(3) var in_radiance: texture_2d_array<f32>;
@group(1) @binding(4) var out_cone: texture_storage_2d<rgba16float, write>;
@group(1) @binding(5) var out_near: texture_storage_2d<rgba16float, write>;
@group(1) @binding(6) var out_far: texture_storage_2d<rgba16float, write>;
// The G-buffer's albedo (hbil's `hidden=volume`: a sender's hidden face).
@group(1) @binding(7) var in_albedo: texture_2d<f32>;
// The G-buffer's material (hbil's `hidden=unbaked`: b = 1 on a sender the bake never saw).
@group(1) @binding(8) var in_material: texture_2d<f32>;

@compute @workgroup_size(8, 8, 1)
fn horizon(@builtin(global_invocation_id) id: vec3<u32>) {
    let at = march_at(view, params, id.xy);
    if !at.valid {
        return;
    }
    let store_at = at.store_at;
    let centre = geometry(in_depth, in_normal, params, vec2<i32>(at.texel), at.layer);
    var r: Horizon;
    r.cone = vec4<f32>(0.0, 0.0, 0.0, 1.0);
    if centre.w > 0.0 {
        r = search_pixel(in_depth, in_normal, in_radiance, in_albedo, in_material, env_radiance, env_irradiance_map, far_probes, far_visibility, env_sampler, view, env, params, at.texel, at.layer, at.pixel, at.pattern, centre);
    }
    textureStore(out_cone, store_at, r.cone);
    if NEAR {
        textureStore(out_near, store_at, vec4<f32>(r.near, 1.0));
    }
    if FAR {
        textureStore(out_far, store_at, r.far);
    }
}
