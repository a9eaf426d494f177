// env.wgsl — the environment, a library (after common.wgsl): lat-long lookups and SH
// irradiance. It declares no bindings: its functions take the maps, the sampler and the
// environment's uniform (`EnvUniforms`) they read; nearfield binds them in group 0
// (shaders/frame_bindings.wgsl, crate::bindings::FrameBindings).
//
// Lat-long convention (docs/src/conventions.md), bit-for-bit the same as
// nearfield_scene::environment:
//   v = acos(d.y) / π (row 0 = zenith), u = atan2(d.x, −d.z) / (2π) wrapped to [0, 1),
// with d first turned by −rotation about +Y. The sampler repeats in u and clamps in v.
//
// The maps the functions take: the radiance map with box-filtered mips (background, blurred
// lookups); the GGX-prefiltered radiance, mip k holding roughness k / (count − 1) (split-sum,
// Karis 2013); the pre-convolved diffuse map E(n)/π (lat-long; Environment::irradiance_map).
// Textures are raw: the lookups multiply by the intensity.

// The environment's uniform (crate::gpu_env::EnvUniforms).
struct EnvUniforms {
    // Rotation about +Y (rad), intensity (already in `sh`), mip counts of the prefiltered
    // specular and of the radiance chain.
    rotation: f32,
    intensity: f32,
    specular_mips: f32,
    radiance_mips: f32,
    // Order-3 SH projection of the radiance (16 RGB coefficients in .xyz), intensity applied.
    sh: array<vec4<f32>, 16>,
}

fn env_uv(rotation: f32, d: vec3<f32>) -> vec2<f32> {
    let a = -rotation;
    let s = sin(a);
    let c = cos(a);
    let r = normalize(vec3<f32>(c * d.x + s * d.z, d.y, -s * d.x + c * d.z));
    var u = atan2(r.x, -r.z) / (2.0 * PI);
    u = select(u, u + 1.0, u < 0.0);
    return vec2<f32>(u, acos(clamp(r.y, -1.0, 1.0)) / PI);
}

// Rows of the pre-convolved diffuse map (gpu_env::IRRADIANCE_SIZE): row y at polar angle
// π y / (rows − 1), the poles included (Environment::irradiance_map).
const ENV_IRRADIANCE_ROWS: f32 = 32.0;

// E(n)/π from the pre-convolved diffuse map (not band-limited, unlike env_irradiance_sh).
fn env_irradiance_exact(irradiance_map: texture_2d<f32>, smp: sampler, e: EnvUniforms, n: vec3<f32>) -> vec3<f32> {
    let uv = env_uv(e.rotation, n);
    let v = (uv.y * (ENV_IRRADIANCE_ROWS - 1.0) + 0.5) / ENV_IRRADIANCE_ROWS;
    return textureSampleLevel(irradiance_map, smp, vec2<f32>(uv.x, v), 0.0).rgb * e.intensity;
}

// Radiance from direction d at mip `lod` of the box-filtered chain.
fn env_radiance_at(radiance: texture_2d<f32>, smp: sampler, e: EnvUniforms, d: vec3<f32>, lod: f32) -> vec3<f32> {
    return textureSampleLevel(radiance, smp, env_uv(e.rotation, d), lod).rgb * e.intensity;
}

// Prefiltered GGX radiance for perceptual roughness r.
fn env_specular_at(specular: texture_2d<f32>, smp: sampler, e: EnvUniforms, d: vec3<f32>, roughness: f32) -> vec3<f32> {
    let lod = roughness * (e.specular_mips - 1.0);
    return textureSampleLevel(specular, smp, env_uv(e.rotation, d), lod).rgb * e.intensity;
}

// The 16 real SH basis functions (nearfield_scene::sh::basis16, same order and constants).
fn sh_basis(d: vec3<f32>) -> array<f32, 16> {
    let x = d.x;
    let y = d.y;
    let z = d.z;
    return array<f32, 16>(
        0.2820948,
        0.4886025 * y, 0.4886025 * z, 0.4886025 * x,
        1.0925484 * x * y, 1.0925484 * y * z, 0.31539157 * (3.0 * z * z - 1.0),
        1.0925484 * x * z, 0.5462742 * (x * x - y * y),
        0.5900436 * y * (3.0 * x * x - y * y), 2.8906114 * x * y * z,
        0.4570458 * y * (5.0 * z * z - 1.0), 0.37317633 * z * (5.0 * z * z - 3.0),
        0.4570458 * x * (5.0 * z * z - 1.0), 1.4453057 * z * (x * x - y * y),
        0.5900436 * x * (x * x - 3.0 * y * y));
}

// Unoccluded diffuse irradiance over π, E(n)/π, from bands 0..2 (Ramamoorthi & Hanrahan 2001:
// Â_l/π = 1, 2/3, 1/4; band 3 does not contribute to irradiance).
fn env_irradiance_sh(e: EnvUniforms, n: vec3<f32>) -> vec3<f32> {
    let b = sh_basis(n);
    var sum = e.sh[0].rgb * b[0];
    for (var i = 1u; i < 4u; i++) {
        sum += e.sh[i].rgb * (b[i] * (2.0 / 3.0));
    }
    for (var i = 4u; i < 9u; i++) {
        sum += e.sh[i].rgb * (b[i] * 0.25);
    }
    return max(sum, vec3<f32>(0.0));
}

// Irradiance over π through a cone of half-angle α = acos(t) about the unit axis `a` (Mayaux
// 2016, HBIL Sec. 2.2.4): Ramamoorthi's Â_l with the upper bound θ_max = α in place of π/2,
//   Â_l(t)/π = 2 ∫_t^1 P_l(μ) μ dμ = 1 − t², (2/3)(1 − t³), (1/4)(1 + 2t² − 3t⁴), t³(1 − t²)
// for l = 0..3 (the HBIL text's c0, c1, c2 divided by π and by Y_l0's constant; band 3, zero for
// the full hemisphere, contributes for narrower cones). t = 0 gives env_irradiance_sh.
fn env_irradiance_cone(e: EnvUniforms, a: vec3<f32>, t: f32) -> vec3<f32> {
    let b = sh_basis(a);
    let t2 = t * t;
    let k = vec4<f32>(1.0 - t2, (2.0 / 3.0) * (1.0 - t2 * t), 0.25 * (1.0 + 2.0 * t2 - 3.0 * t2 * t2),
        t2 * t * (1.0 - t2));
    var sum = e.sh[0].rgb * (b[0] * k.x);
    for (var i = 1u; i < 4u; i++) {
        sum += e.sh[i].rgb * (b[i] * k.y);
    }
    for (var i = 4u; i < 9u; i++) {
        sum += e.sh[i].rgb * (b[i] * k.z);
    }
    for (var i = 9u; i < 16u; i++) {
        sum += e.sh[i].rgb * (b[i] * k.w);
    }
    return max(sum, vec3<f32>(0.0));
}
