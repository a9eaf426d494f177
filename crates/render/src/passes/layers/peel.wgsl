// peel.wgsl — the extra layers of passes/layers/ (raster): depth peeling of the main view and
// additional cameras.
// One `LayerView` (common.wgsl) per pass (dynamic offset); `prev_depth` is the depth buffer of the layer before
// (peeling only). Targets: 0 normal (rgba16float: xyz oriented as layers.rs documents, w = 1),
// 1 albedo (rgba8unorm-srgb), 2 emissive (rgba16float), 3 view depth (r32float, 0 = none).

@group(1) @binding(0) var<storage, read> materials: array<GpuMaterial>;
@group(1) @binding(1) var srgb_textures: texture_2d_array<f32>;
@group(1) @binding(2) var linear_textures: texture_2d_array<f32>;
@group(1) @binding(3) var material_sampler: sampler;
@group(1) @binding(4) var<uniform> layer_view: LayerView;
@group(1) @binding(5) var prev_depth: texture_2d<f32>;

@vertex
fn vs_layer(v: VertexIn) -> VertexOut {
    return transform_vertex(v, layer_view.clip_from_world);
}

struct LayerOut {
    @location(0) normal: vec4<f32>,
    @location(1) albedo: vec4<f32>,
    @location(2) emissive: vec4<f32>,
    @location(3) view_depth: vec4<f32>,
}

@fragment
fn fs_layer(in: VertexOut, @builtin(front_facing) front_facing: bool) -> LayerOut {
    let duv_dx = dpdx(in.uv);
    let duv_dy = dpdy(in.uv);
    let depth = -(layer_view.view_from_world * vec4<f32>(in.world, 1.0)).z;
    if layer_view.peel == 1u {
        // View depth of the layer before, from its depth buffer (directx-style perspective:
        // d = f (t − n) / ((f − n) t)  ⇔  t = f n / (f − d (f − n))).
        let d = textureLoad(prev_depth, vec2<u32>(in.clip.xy), 0).r;
        let near = layer_view.near;
        let far = layer_view.far;
        let before = far * near / (far - d * (far - near));
        // The layer before is re-rasterized with the same matrix, so its fragments land on the
        // stored depth to within a few ulps; a relative view-depth tolerance alone fails where the
        // buffer's resolution (≈ t² ulp / near) is coarser than it (small near planes).
        // With `after_front` (vbgi at half resolution), a back face behind the G-buffer's layer,
        // which culls single-sided back faces, is never that layer again: it needs only to lie
        // behind it, so that the exit through a thin chord (a solid's outermost pixel, seen from
        // far with a small near plane) is not taken for the layer before.
        let exempt = layer_view.after_front == 1u && !front_facing;
        let same = in.clip.z <= d + 4.0 * 1.2e-7 || depth <= before * (1.0 + 1e-4) + 1e-6;
        if d >= 1.0 || in.clip.z <= d || (same && !exempt) {
            discard;
        }
    }
    let m = surface_material(materials[in.material], srgb_textures, linear_textures, material_sampler, in, duv_dx, duv_dy);
    let eye = layer_view.world_from_view[3].xyz;
    var n = normalize(in.normal);
    if dot(n, eye - in.world) < 0.0 {
        n = -n;
    }
    if layer_view.exit == 1u {
        n = -n;
    }
    var o: LayerOut;
    o.normal = vec4<f32>(n, 1.0);
    o.albedo = vec4<f32>(m.base, 1.0);
    o.emissive = vec4<f32>(m.emissive, 1.0);
    o.view_depth = vec4<f32>(depth, 0.0, 0.0, 0.0);
    return o;
}
