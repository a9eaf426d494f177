// bevy_nearfield's glue: the only shader of the plugin. It turns Bevy's prepass images into
// nearfield's documented inputs (docs/src/architecture.md, "Lifting a pass into another engine"),
// hands nearfield's ao to Bevy's PBR, keeps Bevy's lit colour as next frame's radiance, adds
// the near-field indirect light as a diffuse term, and reads the camera's environment map as the
// technique's sky (docs/src/bevy.md).

struct Glue {
    // Bevy's inverse projection (clip → view), infinite reverse-z, with the frame's TAA jitter.
    view_from_clip: mat4x4<f32>,
    // This frame's view → last frame's clip (unjittered): the camera's own motion, used where
    // Bevy's motion vectors are not bound.
    previous_clip_from_view: mat4x4<f32>,
    size: vec2<f32>,
    // 1 where Bevy's motion-vector prepass is bound.
    has_motion: u32,
    // Scale of the indirect light added.
    indirect_intensity: f32,
    // 0: Bevy's ambient light is not darkened (the ao written is 1).
    ambient_occlusion: u32,
    // How the technique's light meets Bevy's volume (cs_ao): FAR_PLAIN, FAR_OCCLUSION,
    // FAR_REPLACE.
    far_rule: u32,
    // 1 where Bevy's deferred G-buffer is bound (ρ for the multi-bounce curve).
    has_gbuffer: u32,
    _pad: u32,
}

@group(0) @binding(0) var<uniform> glue: Glue;

@vertex
fn vs_fullscreen(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 0.0, 1.0);
}

// --- Bevy's prepass → nearfield's inputs -------------------------------------------------------

// Bevy's depth prepass, read as an unfilterable float texture (reverse-z: 0 = nothing drawn).
@group(1) @binding(0) var bevy_depth: texture_2d<f32>;
// Bevy's normal prepass: world normal × 0.5 + 0.5 (rgb10a2unorm).
@group(1) @binding(1) var bevy_normal: texture_2d<f32>;
// Bevy's motion vectors: current − previous position in uv units (rg16float), when bound.
@group(1) @binding(2) var bevy_motion: texture_2d<f32>;
// Bevy's lit colour of the frame before (rgb) and that frame's view depth (a; 0: none), as
// fs_capture kept it.
@group(1) @binding(3) var captured: texture_2d<f32>;

struct Inputs {
    // nearfield's view depth (r32float): metres along the view direction, 0 on background.
    @location(0) view_depth: vec4<f32>,
    // nearfield's world normal (rgba16float), w = 1 on surfaces.
    @location(1) normal: vec4<f32>,
    // nearfield's motion (rg16float): previous − current pixel position.
    @location(2) motion: vec4<f32>,
    // The radiance the technique gathers (rgba16float): last frame's colour where this
    // surface point was (below).
    @location(3) gathered: vec4<f32>,
}

// Relative depth tolerance of the reprojection's same-surface test.
const SAME_SURFACE: f32 = 0.05;

@fragment
fn fs_inputs(@builtin(position) p: vec4<f32>) -> Inputs {
    let px = vec2<i32>(p.xy);
    let d = textureLoad(bevy_depth, px, 0).r;
    var o: Inputs;
    o.view_depth = vec4<f32>(0.0);
    o.normal = vec4<f32>(0.0);
    o.motion = vec4<f32>(0.0);
    o.gathered = vec4<f32>(0.0);
    if d <= 0.0 {
        return o;
    }
    let ndc = vec2<f32>(p.x / glue.size.x * 2.0 - 1.0, 1.0 - p.y / glue.size.y * 2.0);
    let v = glue.view_from_clip * vec4<f32>(ndc, d, 1.0);
    o.view_depth = vec4<f32>(-v.z / v.w, 0.0, 0.0, 0.0);
    let n = textureLoad(bevy_normal, px, 0).xyz * 2.0 - 1.0;
    o.normal = vec4<f32>(normalize(n), 1.0);
    if glue.has_motion != 0u {
        let mv = textureLoad(bevy_motion, px, 0).xy;
        o.motion = vec4<f32>(-mv * glue.size, 0.0, 0.0);
    }
    // Where the camera's motion alone takes this point (a still world) and its depth there.
    let c = glue.previous_clip_from_view * vec4<f32>(v.xyz / v.w, 1.0);
    if glue.has_motion == 0u {
        // No motion prepass: the camera's motion, as Bevy would write it.
        let prev_ndc = c.xy / c.w;
        let prev = vec2<f32>(prev_ndc.x + 1.0, 1.0 - prev_ndc.y) * 0.5 * glue.size;
        o.motion = vec4<f32>(prev - p.xy, 0.0, 0.0);
    }
    // The gathered colour, reprojected: last frame's colour where this surface point was
    // (through the motion), bilinearly from the four texels around it that showed this surface
    // (their depth within SAME_SURFACE of the depth the camera's motion gives this point); where
    // none did (a disocclusion), last frame's colour at this pixel as it was (one frame's lag).
    let here = textureLoad(captured, px, 0);
    o.gathered = vec4<f32>(here.rgb, 1.0);
    let q = p.xy + o.motion.xy - 0.5;
    let base = vec2<i32>(floor(q));
    let f = q - floor(q);
    var sum = vec3<f32>(0.0);
    var weight = 0.0;
    for (var k = 0; k < 4; k++) {
        let o_k = vec2<i32>(k & 1, k >> 1u);
        let t = base + o_k;
        if any(t < vec2<i32>(0)) || any(t >= vec2<i32>(glue.size)) {
            continue;
        }
        let there = textureLoad(captured, t, 0);
        if there.a <= 0.0 || abs(there.a - c.w) > SAME_SURFACE * c.w {
            continue;
        }
        let w = select(1.0 - f.x, f.x, o_k.x == 1) * select(1.0 - f.y, f.y, o_k.y == 1);
        sum += w * there.rgb;
        weight += w;
    }
    if weight > 1e-3 {
        o.gathered = vec4<f32>(sum / weight, 1.0);
    }
    return o;
}

// --- Bevy's lit colour → next frame's radiance -------------------------------------------------

@group(1) @binding(0) var bevy_colour: texture_2d<f32>;
// nearfield's view depth of this frame (fs_inputs'): kept in alpha for next frame's
// same-surface test.
@group(1) @binding(1) var view_depth: texture_2d<f32>;

@fragment
fn fs_capture(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {
    let px = vec2<i32>(p.xy);
    return vec4<f32>(textureLoad(bevy_colour, px, 0).rgb, textureLoad(view_depth, px, 0).r);
}

// --- the indirect light as a diffuse term ------------------------------------------------------

// Bevy's deferred G-buffer (rgba32uint): x = base colour (sRGB-ish, γ 2.2) and roughness,
// z = reflectance, metallic, diffuse occlusion, clearcoat (4 × unorm8).
@group(1) @binding(0) var bevy_gbuffer: texture_2d<u32>;
// nearfield's indirect-irradiance: (1/π) ∫ (1 − V_R) L_o cos θ dω.
@group(1) @binding(1) var indirect_irradiance: texture_2d<f32>;

@fragment
fn fs_add_indirect(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {
    let px = vec2<i32>(p.xy);
    let g = textureLoad(bevy_gbuffer, px, 0);
    let base_rough = unpack4x8unorm(g.x);
    let props = unpack4x8unorm(g.z);
    let albedo = pow(base_rough.rgb, vec3<f32>(2.2));
    let metallic = props.y;
    let e = textureLoad(indirect_irradiance, px, 0).rgb;
    // Outgoing diffuse radiance of the irradiance E/π: ρ (1 − metallic) · E/π.
    return vec4<f32>(glue.indirect_intensity * (1.0 - metallic) * albedo * e, 0.0);
}

// --- nearfield's ao → Bevy's PBR ---------------------------------------------------------------
// (compiled after nearfield's common.wgsl, env.wgsl and far.wgsl)

// Bevy multiplies the diffuse light of its irradiance volume, environment map and ambient
// light by ssao_multibounce(s, ρ) of the s written here. Without a baked volume (or for a rule
// of its own) s is the technique's ao. With one, the technique read the same volume as its far
// field, and s keeps of Bevy's volume light only what the technique does not draw itself
// (docs/src/bevy.md, "Counted once"):
// - FAR_OCCLUSION (gtao, ssao): the occlusion the volume does not hold already,
//   F(v)/F(ao_far), ao_far the volume's own visibility within R (far_ao_at);
// - FAR_REPLACE (hbil, vbgi): the share of the volume's light that reaches the point through
//   the directions the technique finds free, its env-irradiance over the volume's whole
//   E/π; its near light is added after the main pass.
// - FAR_REPLACE_SKY (hbil, vbgi without a volume, the view's environment map read as the
//   technique's sky): the share of the environment's light that reaches the point through the
//   free directions, its env-irradiance over the environment's unoccluded E/π.
// s is that share through the inverse of Bevy's curve at the receiver's ρ (its G-buffer's;
// 0.5 where the materials are drawn forward and there is none).
const FAR_PLAIN: u32 = 0u;
const FAR_OCCLUSION: u32 = 1u;
const FAR_REPLACE: u32 = 2u;
const FAR_REPLACE_SKY: u32 = 3u;

@group(1) @binding(0) var near_field_ao: texture_2d<f32>;
@group(1) @binding(1) var bevy_ao: texture_storage_2d<AO_FORMAT, write>;
@group(1) @binding(2) var ao_view_depth: texture_2d<f32>;
@group(1) @binding(3) var ao_normal: texture_2d<f32>;
// The technique's env-irradiance (FAR_REPLACE), else any image.
@group(1) @binding(4) var ao_env_irradiance: texture_2d<f32>;
// Bevy's deferred G-buffer (`has_gbuffer`), else a 1×1 image.
@group(1) @binding(5) var ao_gbuffer: texture_2d<u32>;

// nearfield's view of the frame and its far field, as the technique read them.
@group(2) @binding(0) var<uniform> ao_cam: View;
@group(2) @binding(1) var ao_far_probes: texture_2d<f32>;
@group(2) @binding(2) var ao_far_visibility: texture_2d<f32>;
@group(2) @binding(3) var ao_far_atlas: texture_2d<f32>;
@group(2) @binding(4) var ao_far_sampler: sampler;
// The technique's environment (FAR_REPLACE_SKY: its SH, for the unoccluded E/π).
@group(2) @binding(5) var<uniform> ao_env: EnvUniforms;

// Bevy's ssao_multibounce at a scalar ρ (Jimenez et al. 2016, Eq. 10).
fn bevy_multibounce(x: f32, rho: f32) -> f32 {
    let a = 2.0404 * rho - 0.3324;
    let b = -4.7951 * rho + 0.6417;
    let c = 2.7552 * rho + 0.6903;
    return max(x, ((x * a + b) * x + c) * x);
}

// The s in [0, 1] with bevy_multibounce(s, rho) = y (the curve rises on [0, 1]; bisection).
fn inverse_multibounce(y: f32, rho: f32) -> f32 {
    var lo = 0.0;
    var hi = 1.0;
    for (var i = 0u; i < 16u; i++) {
        let mid = 0.5 * (lo + hi);
        if bevy_multibounce(mid, rho) < y {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return 0.5 * (lo + hi);
}

@compute @workgroup_size(8, 8)
fn cs_ao(@builtin(global_invocation_id) id: vec3<u32>) {
    if any(id.xy >= textureDimensions(bevy_ao)) {
        return;
    }
    var ao = 1.0;
    let depth = textureLoad(ao_view_depth, id.xy, 0).r;
    if glue.ambient_occlusion != 0u {
        ao = textureLoad(near_field_ao, id.xy, 0).r;
    }
    if glue.far_rule != FAR_PLAIN && depth > 0.0 {
        let p = world_position(ao_cam, id.xy, depth);
        let n = normalize(textureLoad(ao_normal, id.xy, 0).xyz);
        let v = normalize(ao_cam.camera_position.xyz - p);
        var rho = 0.5;
        if glue.has_gbuffer != 0u {
            let base = pow(unpack4x8unorm(textureLoad(ao_gbuffer, id.xy, 0).x).rgb, vec3<f32>(2.2));
            rho = luminance(base);
        }
        var share = 1.0;
        if glue.far_rule == FAR_OCCLUSION {
            let far_ao = far_ao_at(ao_far_probes, ao_far_visibility, ao_far_sampler, p, n, v);
            share = min(1.0, bevy_multibounce(ao, rho) / max(bevy_multibounce(far_ao, rho), 1e-3));
        } else {
            var whole: vec3<f32>;
            if glue.far_rule == FAR_REPLACE_SKY {
                whole = env_irradiance_sh(ao_env, n);
            } else {
                whole = far_irradiance_at(ao_far_probes, ao_far_visibility, ao_far_atlas, ao_far_sampler, p, n, v);
            }
            let free = textureLoad(ao_env_irradiance, id.xy, 0).rgb;
            share = clamp(luminance(free) / max(luminance(whole), 1e-6), 0.0, 1.0);
        }
        ao = inverse_multibounce(share, rho);
    }
    textureStore(bevy_ao, id.xy, vec4<f32>(ao, 0.0, 0.0, 1.0));
}

// --- Bevy's environment map → nearfield's environment ------------------------------------------

// The view's environment map (its radiance cube), read once into a lat-long map in nearfield's
// convention (docs/src/conventions.md): world direction d sees the cube at
// cube_from_world · d, Bevy's lookup (the map's rotation undone, z negated: environment_map.wesl).
struct EnvRead {
    cube_from_world: mat4x4<f32>,
    size: vec2<f32>,
    _pad: vec2<f32>,
}

@group(1) @binding(0) var<uniform> env_read: EnvRead;
@group(1) @binding(1) var env_cube: texture_cube<f32>;
@group(1) @binding(2) var env_cube_sampler: sampler;
@group(1) @binding(3) var env_latlong: texture_storage_2d<rgba32float, write>;

// Taps per side of each lat-long texel (its mean over the texel's footprint on the cube).
const ENV_TAPS: u32 = 4u;
const ENV_PI: f32 = 3.14159265358979;

@compute @workgroup_size(8, 8)
fn cs_env(@builtin(global_invocation_id) id: vec3<u32>) {
    if any(vec2<f32>(id.xy) >= env_read.size) {
        return;
    }
    var sum = vec3<f32>(0.0);
    for (var j = 0u; j < ENV_TAPS; j++) {
        for (var i = 0u; i < ENV_TAPS; i++) {
            let tap = (vec2<f32>(f32(i), f32(j)) + 0.5) / f32(ENV_TAPS);
            let uv = (vec2<f32>(id.xy) + tap) / env_read.size;
            let theta = uv.y * ENV_PI;
            let phi = uv.x * 2.0 * ENV_PI;
            let d = vec3<f32>(sin(theta) * sin(phi), cos(theta), -sin(theta) * cos(phi));
            let c = (env_read.cube_from_world * vec4<f32>(d, 0.0)).xyz;
            sum += textureSampleLevel(env_cube, env_cube_sampler, c, 0.0).rgb;
        }
    }
    textureStore(env_latlong, id.xy, vec4<f32>(sum / f32(ENV_TAPS * ENV_TAPS), 1.0));
}
