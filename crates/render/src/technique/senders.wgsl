// senders.wgsl — the screen-space bounce's sender patches (SSDO Sec. 3), shared by the passes
// that gather indirect light from occluding pixels (ssdo `bounce`, s3ho `sample`), a library
// (after samples.wgsl). It declares no bindings: layer_sender_radiance takes the textures it
// reads, which such a pass declares in its group 1 and passes on:
//   peel_radiance, cam_radiance: texture_2d_array<f32> — the direct radiance of the peeled layers
//   and additional cameras (passes/layers/ `shade`).

// Distance d from a receiver to a sender patch and the product of their cosines cos θ_s cos θ_r
// (0 when either surface faces away).
fn patch_cosines(receiver: Surface, sender: Surface) -> vec2<f32> {
    let to_sender = sender.p - receiver.p;
    let d = length(to_sender);
    if d <= 0.0 {
        return vec2<f32>(0.0);
    }
    let dir = to_sender / d;
    let cos_s = max(0.0, dot(sender.n, -dir));
    let cos_r = max(0.0, dot(receiver.n, dir));
    return vec2<f32>(d, cos_s * cos_r);
}

// Transfer from a sender patch (a pixel that occludes a sample, SSDO Sec. 3) to the receiver,
// per unit sender radiance, in irradiance/π units: area · cos θ_s · cos θ_r · falloff /
// (π · max(d, distance_clamp)²) with falloff 1 − d/R; 0 when either surface faces away.
fn sender_transfer(receiver: Surface, sender: Surface, area: f32, radius: f32, distance_clamp: f32) -> f32 {
    let g = patch_cosines(receiver, sender);
    if g.y <= 0.0 {
        return 0.0;
    }
    let falloff = max(0.0, 1.0 - g.x / radius);
    let dc = max(distance_clamp, g.x);
    return area * g.y * falloff / (PI * dc * dc);
}

// The part of a sender patch's transfer that a virtual point light at the patch, clamped at
// `vpl_clamp`, leaves out: area · cos θ_s cos θ_r (1/max(d, distance_clamp)² −
// 1/max(d, vpl_clamp)²) / π (0 beyond vpl_clamp; no falloff, since vpl_clamp ≤ R).
fn clamp_remainder_transfer(receiver: Surface, sender: Surface, area: f32, distance_clamp: f32, vpl_clamp: f32) -> f32 {
    let g = patch_cosines(receiver, sender);
    if g.y <= 0.0 {
        return 0.0;
    }
    let near = max(distance_clamp, g.x);
    let far = max(vpl_clamp, g.x);
    return area * g.y * max(0.0, 1.0 / (near * near) - 1.0 / (far * far)) / PI;
}

// Direct radiance of a sender that a peeled layer (e.g. the back face of a solid) or an
// additional camera (e.g. a surface hidden in the main view) supplies: `occ.source` > 0.
fn layer_sender_radiance(peel_radiance: texture_2d_array<f32>, cam_radiance: texture_2d_array<f32>, occ: Occlusion) -> vec3<f32> {
    if occ.source < CAMERA_SOURCE {
        return textureLoad(peel_radiance, occ.pixel, occ.source - 1u, 0).rgb;
    }
    return textureLoad(cam_radiance, occ.pixel, occ.source - CAMERA_SOURCE, 0).rgb;
}
