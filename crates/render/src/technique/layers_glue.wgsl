// layers_glue.wgsl — glue shared by the passes that run samples.wgsl's blocker test over the
// main view, its peeled layers and the additional cameras (ssdo `direct` and `bounce`, s3ho
// `sample`). It declares no bindings; it reads the ones those passes declare under the same
// names in their group 1: gb_normal, gb_view_depth, peel_normal, peel_depth, cam_normal,
// cam_depth, layer_views (a storage array, which WGSL cannot pass to a library function) and
// sample_sets, with group 0's `view`. samples.wgsl documents the test and the march.

fn occlusion(p: vec3<f32>, omega: vec3<f32>, lambda: f32, cfg: SampleConfig) -> Occlusion {
    let s = p + omega * lambda;
    var best = main_view_verdict(view, gb_normal, gb_view_depth, peel_normal, peel_depth, p, s, lambda, cfg);
    if best.informed && best.free {
        return best.o;
    }
    for (var c = 0u; c < cfg.cameras; c++) {
        let v = camera_verdict(layer_views[CAMERA_VIEW_BASE + c], cam_normal, cam_depth, p, s, lambda, c, cfg);
        if !v.informed {
            continue;
        }
        if v.free {
            var none: Occlusion;
            none.amount = 0.0;
            return none;
        }
        if !best.informed || v.o.amount > best.o.amount {
            best = v;
        }
    }
    return best.o;
}

fn march_occlusion(p: vec3<f32>, omega: vec3<f32>, lambda: f32, steps: u32, cfg: SampleConfig) -> Occlusion {
    var o: Occlusion;
    o.amount = 0.0;
    let at = screen_pixel(view, p);
    for (var k = 1u; k <= steps; k++) {
        let l = lambda * f32(k) / f32(steps);
        if cfg.layers > 1u && k < steps && distance(screen_pixel(view, p + omega * l), at) < MARCH_MIN_PIXELS {
            continue;
        }
        o = occlusion(p, omega, l, cfg);
        if o.amount > 0.0 {
            break;
        }
    }
    return o;
}

// Sample i of `pixel` (samples.wgsl's sample_local) with this pass's interleaved sets.
fn sample_at(i: u32, pixel: vec2<u32>, cfg: SampleConfig) -> vec4<f32> {
    return sample_local(view.seed, sample_sets[sample_set_index(i, pixel, cfg)], i, pixel, cfg);
}
