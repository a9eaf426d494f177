// layers.wgsl — direct radiance of the extra layers (passes/layers/): for every texel of a
// peeled layer or an additional camera, ρ × (unoccluded SH irradiance of the environment +
// (1/π) Σ E_l · shadow-map visibility) + emission: the senders' outgoing diffuse radiance, an
// estimate of the physical direct light of x′ (docs/src/aovs.md) whose environment part is
// unoccluded (the sun, split out with `--sun auto`, is a shadow-mapped light here). With a probe
// volume the environment part is the volume's irradiance (far.wgsl), as in direct_lighting.wgsl.

struct ShadeParams {
    // Index in `layer_views` of this set's first layer, and the number of layers.
    first_view: u32,
    count: u32,
    _pad0: u32,
    _pad1: u32,
}

@group(1) @binding(1) var<storage, read> layer_views: array<LayerView>;
@group(1) @binding(0) var<uniform> shade_params: ShadeParams;
@group(1) @binding(2) var layer_normal: texture_2d_array<f32>;
@group(1) @binding(3) var layer_albedo: texture_2d_array<f32>;
@group(1) @binding(4) var layer_emissive: texture_2d_array<f32>;
@group(1) @binding(5) var layer_depth: texture_2d_array<f32>;
@group(1) @binding(6) var layer_radiance: texture_storage_2d_array<rgba16float, write>;
@group(1) @binding(7) var<storage, read> lights: array<GpuLight>;
@group(1) @binding(8) var<storage, read> shadow_clip_from_world: array<mat4x4<f32>>;
@group(1) @binding(9) var shadow_maps: texture_depth_2d_array;
@group(1) @binding(10) var shadow_sampler: sampler_comparison;
@group(1) @binding(11) var shadow_depths: texture_2d_array<f32>;

// lights.wgsl's shadow_visibility of light l at world p with normal n, from this pass's shadow
// maps: the layer that sees p, its matrix, the frame's normal offset.
fn shadow_map_visibility(l: GpuLight, p: vec3<f32>, n: vec3<f32>) -> f32 {
    let layer = shadow_layer(l, p);
    return shadow_visibility(shadow_maps, shadow_depths, shadow_sampler, frame.shadow_normal_offset, l, layer, shadow_clip_from_world[layer], p, n);
}

@compute @workgroup_size(8, 8, 1)
fn shade(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(layer_normal);
    if id.x >= size.x || id.y >= size.y || id.z >= shade_params.count {
        return;
    }
    let pixel = id.xy;
    let k = id.z;
    let nw = textureLoad(layer_normal, pixel, k, 0);
    let depth = textureLoad(layer_depth, pixel, k, 0).r;
    if nw.w == 0.0 || depth <= 0.0 {
        textureStore(layer_radiance, pixel, k, vec4<f32>(0.0));
        return;
    }
    let n = normalize(nw.xyz);
    let p = layer_position(layer_views[shade_params.first_view + k], pixel, depth);
    var irradiance = vec3<f32>(0.0);
    if far_volume(far_probes) {
        irradiance = far_irradiance_here(far_probes, far_visibility, far_irradiance_atlas, env_sampler, view, p, n);
    } else {
        irradiance = env_irradiance_sh(env, n);
    }
    for (var li = 0u; li < frame.light_count; li++) {
        let l = lights[li];
        let inc = incident(l, p);
        let n_l = dot(n, inc.to_light);
        if n_l <= 0.0 {
            continue;
        }
        irradiance += inc.irradiance * (n_l * shadow_map_visibility(l, p, n) / PI);
    }
    let albedo = textureLoad(layer_albedo, pixel, k, 0).rgb;
    let emissive = textureLoad(layer_emissive, pixel, k, 0).rgb;
    textureStore(layer_radiance, pixel, k, vec4<f32>(albedo * irradiance + emissive, 1.0));
}
