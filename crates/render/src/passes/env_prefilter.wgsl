// env_prefilter.wgsl — builds the environment's two mip chains once per environment.
//
// `downsample`: mip k+1 of the radiance chain = mean of the 2×2 texels of mip k (a box filter in
//   texel space; it ignores that texels shrink towards the poles, which blurs polar rows a
//   little more than equatorial ones).
// `prefilter`: mip k of the specular chain = the radiance map convolved with the GGX lobe for
//   perceptual roughness r = k / (levels − 1), under the split-sum assumption n = v = r (Karis,
//   "Real Shading in Unreal Engine 4", 2013), with N = 128 Hammersley samples of the GGX normal
//   distribution, weighted by n·l, each read from the radiance chain at the mip whose texel solid
//   angle matches the sample's (filtered importance sampling, Křivánek & Colbert 2008). Mip 0 of
//   the specular chain (r = 0) is a copy of the map. The lat-long convention is the unrotated
//   one of env.wgsl: rotation is applied at lookup time.

struct PrefilterParams {
    // perceptual roughness of the level being written, source width, source height, source mips.
    roughness: f32,
    source_width: f32,
    source_height: f32,
    source_mips: f32,
}

@group(1) @binding(0) var<uniform> params: PrefilterParams;
@group(1) @binding(1) var source: texture_2d<f32>;
@group(1) @binding(2) var source_sampler: sampler;
@group(1) @binding(3) var destination: texture_storage_2d<rgba16float, write>;

const PI: f32 = 3.14159265358979;
const SAMPLES: u32 = 128u;

@compute @workgroup_size(8, 8, 1)
fn downsample(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(destination);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    // `source` is a view of the one mip being reduced.
    let src = vec2<i32>(id.xy) * 2;
    var sum = vec4<f32>(0.0);
    for (var j = 0; j < 2; j++) {
        for (var i = 0; i < 2; i++) {
            sum += textureLoad(source, src + vec2<i32>(i, j), 0);
        }
    }
    textureStore(destination, id.xy, sum * 0.25);
}

fn uv_to_dir(uv: vec2<f32>) -> vec3<f32> {
    let theta = uv.y * PI;
    let phi = uv.x * 2.0 * PI;
    let s = sin(theta);
    return vec3<f32>(s * sin(phi), cos(theta), -s * cos(phi));
}

fn dir_to_uv(d: vec3<f32>) -> vec2<f32> {
    var u = atan2(d.x, -d.z) / (2.0 * PI);
    u = select(u, u + 1.0, u < 0.0);
    return vec2<f32>(u, acos(clamp(d.y, -1.0, 1.0)) / PI);
}

fn radical_inverse(i: u32) -> f32 {
    return f32(reverseBits(i)) * 2.3283064365386963e-10;
}

@compute @workgroup_size(8, 8, 1)
fn prefilter(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(destination);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let uv = (vec2<f32>(id.xy) + 0.5) / vec2<f32>(size);
    let n = uv_to_dir(uv);
    if params.roughness == 0.0 {
        // A copy, read from the source mip of the destination's resolution.
        let lod = log2(params.source_width / f32(size.x));
        textureStore(destination, id.xy, vec4<f32>(textureSampleLevel(source, source_sampler, uv, lod).rgb, 1.0));
        return;
    }
    let a = params.roughness * params.roughness;
    let up = select(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), abs(n.y) < 0.999);
    let t = normalize(cross(up, n));
    let b = cross(n, t);
    // Solid angle of one source texel at the equator.
    let texel_solid_angle = 4.0 * PI / (params.source_width * params.source_height);
    var sum = vec3<f32>(0.0);
    var weight = 0.0;
    for (var i = 0u; i < SAMPLES; i++) {
        let xi = vec2<f32>((f32(i) + 0.5) / f32(SAMPLES), radical_inverse(i));
        let phi = 2.0 * PI * xi.x;
        let cos_theta = sqrt((1.0 - xi.y) / (1.0 + (a * a - 1.0) * xi.y));
        let sin_theta = sqrt(1.0 - cos_theta * cos_theta);
        let h = t * (sin_theta * cos(phi)) + b * (sin_theta * sin(phi)) + n * cos_theta;
        let l = 2.0 * dot(n, h) * h - n;
        let n_l = dot(n, l);
        if n_l > 0.0 {
            // pdf of l with n = v: D(h) (n·h) / (4 v·h) = D(h) / 4.
            let a2 = a * a;
            let f = cos_theta * cos_theta * (a2 - 1.0) + 1.0;
            let d = a2 / (PI * f * f);
            let sample_solid_angle = 1.0 / (f32(SAMPLES) * d * 0.25 + 1e-6);
            let lod = clamp(0.5 * log2(sample_solid_angle / texel_solid_angle) + 1.0, 0.0, params.source_mips - 1.0);
            sum += textureSampleLevel(source, source_sampler, dir_to_uv(l), lod).rgb * n_l;
            weight += n_l;
        }
    }
    textureStore(destination, id.xy, vec4<f32>(sum / max(weight, 1e-6), 1.0));
}
