//! The `quality=fitted` preset of every technique: its free constants fitted against the
//! reference by `nearfield fit` (scripts/fits.sh; the runs are docs/src/fits/TECHNIQUE.json and
//! the book's results page). Written by scripts/fitted-presets.py from those runs: each preset
//! quotes its command, and its error before (the defaults) and after on the training scenes and
//! on held-out scenes it never saw. A held-out error that rose says the constant does not carry
//! over; such presets stay presets, not defaults.

use super::Preset;

/// `quality=fitted` appended to a family's presets.
pub const fn with_fitted<const N: usize>(base: &[Preset], fitted: Preset) -> [Preset; N] {
    let mut out = [fitted; N];
    let mut i = 0;
    while i < base.len() {
        out[i] = base[i];
        i += 1;
    }
    assert!(base.len() + 1 == N, "one fitted preset after the family's");
    out
}

/// `gtao` fitted on `ao` (rel, 16 frames, 96×54, R = 1 m):
/// training 0.0688 → 0.0636, held out 0.0607 → 0.0558 (-8.0 %),
/// 24 evaluations (budget spent).
///
/// ```text
/// nearfield fit gtao --params falloff,step_power --aov ao --frames 16 --budget 24 --scenes builtin:cornell,builtin:boxes,../shared/assets/scenes/crytek_sponza/Sponza.gltf@docs/src/fits/sponza-camera.json:env=../shared/assets/env/rooitou_park_1k.hdr --size 96x54 --radius 1 --spp 256 --holdout builtin:columns,builtin:city,builtin:closed-box,builtin:gap,builtin:contact,builtin:wall,../shared/assets/scenes/stanford_dragon/dragon.obj,../shared/assets/scenes/cornell_box_suzanne_gltf/cornell-box.glb --out docs/src/fits/gtao.json
/// ```
pub const GTAO: Preset = Preset {
    name: "fitted",
    set: &[("falloff", "0.0"), ("step_power", "1.837")],
};

/// `hbil` fitted on `diffuse` (rel, 16 frames, 96×54, R = 1 m):
/// training 0.0986 → 0.0982, held out 0.0284 → 0.0290 (+2.2 %),
/// 20 evaluations (converged).
///
/// ```text
/// nearfield fit hbil --params falloff,step_power --aov diffuse --frames 16 --budget 24 --scenes builtin:cornell,builtin:boxes,../shared/assets/scenes/crytek_sponza/Sponza.gltf@docs/src/fits/sponza-camera.json:env=../shared/assets/env/rooitou_park_1k.hdr --size 96x54 --radius 1 --spp 256 --holdout builtin:columns,builtin:city,builtin:closed-box,builtin:gap,builtin:contact,builtin:wall,../shared/assets/scenes/stanford_dragon/dragon.obj,../shared/assets/scenes/cornell_box_suzanne_gltf/cornell-box.glb --out docs/src/fits/hbil.json
/// ```
pub const HBIL: Preset = Preset {
    name: "fitted",
    set: &[("falloff", "0.1879"), ("step_power", "2.293")],
};

/// `instant-radiosity` fitted on `indirect-irradiance` (rel, 1 frame, 96×54, R = 1 m):
/// training 0.9007 → 0.8974, held out 4.1125 → 4.1217 (+0.2 %),
/// 18 evaluations (converged).
///
/// ```text
/// nearfield fit instant-radiosity --params strength,vpl_clamp=0.01..0.5 --aov indirect-irradiance --frames 1 --budget 24 --scenes builtin:cornell,builtin:boxes,../shared/assets/scenes/cornell_box_mcguire/CornellBox-Original.obj --size 96x54 --radius 1 --spp 256 --holdout builtin:columns,builtin:city,builtin:closed-box,builtin:gap,builtin:contact,builtin:wall,../shared/assets/scenes/stanford_dragon/dragon.obj,../shared/assets/scenes/cornell_box_suzanne_gltf/cornell-box.glb --out docs/src/fits/instant-radiosity.json
/// ```
pub const INSTANT_RADIOSITY: Preset = Preset {
    name: "fitted",
    set: &[("strength", "1.376"), ("vpl_clamp", "0.5")],
};

/// `s3ho` fitted on `indirect-irradiance` (rel, 1 frame, 96×54, R = 1 m):
/// training 0.6259 → 0.5444, held out 0.9258 → 0.8197 (-11.5 %),
/// 24 evaluations (budget spent).
///
/// ```text
/// nearfield fit s3ho --params strength,distance_clamp --aov indirect-irradiance --frames 1 --budget 24 --scenes builtin:cornell,builtin:boxes,../shared/assets/scenes/cornell_box_mcguire/CornellBox-Original.obj --size 96x54 --radius 1 --spp 256 --holdout builtin:columns,builtin:city,builtin:closed-box,builtin:gap,builtin:contact,builtin:wall,../shared/assets/scenes/stanford_dragon/dragon.obj,../shared/assets/scenes/cornell_box_suzanne_gltf/cornell-box.glb --out docs/src/fits/s3ho.json
/// ```
pub const S3HO: Preset = Preset {
    name: "fitted",
    set: &[("distance_clamp", "0.4146"), ("strength", "1.409")],
};

/// `ssao` fitted on `env-irradiance` (rel, 1 frame, 96×54, R = 1 m):
/// training 0.0923 → 0.0745, held out 0.0651 → 0.0667 (+2.3 %),
/// 16 evaluations (converged).
///
/// ```text
/// nearfield fit ssao --params scale,contrast --aov env-irradiance --frames 1 --budget 24 --scenes builtin:cornell,builtin:boxes,../shared/assets/scenes/crytek_sponza/Sponza.gltf@docs/src/fits/sponza-camera.json:env=../shared/assets/env/rooitou_park_1k.hdr --size 96x54 --radius 1 --spp 256 --holdout builtin:columns,builtin:city,builtin:closed-box,builtin:gap,builtin:contact,builtin:wall,../shared/assets/scenes/stanford_dragon/dragon.obj,../shared/assets/scenes/cornell_box_suzanne_gltf/cornell-box.glb --out docs/src/fits/ssao.json
/// ```
pub const SSAO: Preset = Preset {
    name: "fitted",
    set: &[("contrast", "2.116"), ("scale", "0.8961")],
};

/// `ssbn` fitted on `env-irradiance` (rel, 1 frame, 96×54, R = 1 m):
/// training 0.1755 → 0.1702, held out 0.1155 → 0.1076 (-6.8 %),
/// 11 evaluations (converged).
///
/// ```text
/// nearfield fit ssbn --params lambda,fade --aov env-irradiance --frames 1 --budget 24 --scenes builtin:cornell,builtin:boxes,../shared/assets/scenes/crytek_sponza/Sponza.gltf@docs/src/fits/sponza-camera.json:env=../shared/assets/env/rooitou_park_1k.hdr --size 96x54 --radius 1 --spp 256 --holdout builtin:columns,builtin:city,builtin:closed-box,builtin:gap,builtin:contact,builtin:wall,../shared/assets/scenes/stanford_dragon/dragon.obj,../shared/assets/scenes/cornell_box_suzanne_gltf/cornell-box.glb --out docs/src/fits/ssbn.json
/// ```
pub const SSBN: Preset = Preset {
    name: "fitted",
    set: &[("fade", "0.0"), ("lambda", "1000.0")],
};

/// `ssdo-vpl` fitted on `indirect-irradiance` (rel, 1 frame, 96×54, R = 1 m):
/// training 0.8505 → 0.6017, held out 0.9231 → 0.8407 (-8.9 %),
/// 7 evaluations (converged).
///
/// ```text
/// nearfield fit ssdo-vpl --params strength,vpl_clamp=0.01..0.5 --aov indirect-irradiance --frames 1 --budget 24 --scenes builtin:cornell,builtin:boxes,../shared/assets/scenes/cornell_box_mcguire/CornellBox-Original.obj --size 96x54 --radius 1 --spp 256 --holdout builtin:columns,builtin:city,builtin:closed-box,builtin:gap,builtin:contact,builtin:wall,../shared/assets/scenes/stanford_dragon/dragon.obj,../shared/assets/scenes/cornell_box_suzanne_gltf/cornell-box.glb --out docs/src/fits/ssdo-vpl.json
/// ```
pub const SSDO_VPL: Preset = Preset {
    name: "fitted",
    set: &[("strength", "5.0"), ("vpl_clamp", "0.5")],
};

/// `ssdo` fitted on `indirect-irradiance` (rel, 1 frame, 96×54, R = 1 m):
/// training 0.8300 → 0.5934, held out 0.9176 → 0.8729 (-4.9 %),
/// 13 evaluations (converged).
///
/// ```text
/// nearfield fit ssdo --params strength,distance_clamp --aov indirect-irradiance --frames 1 --budget 24 --scenes builtin:cornell,builtin:boxes,../shared/assets/scenes/cornell_box_mcguire/CornellBox-Original.obj --size 96x54 --radius 1 --spp 256 --holdout builtin:columns,builtin:city,builtin:closed-box,builtin:gap,builtin:contact,builtin:wall,../shared/assets/scenes/stanford_dragon/dragon.obj,../shared/assets/scenes/cornell_box_suzanne_gltf/cornell-box.glb --out docs/src/fits/ssdo.json
/// ```
pub const SSDO: Preset = Preset {
    name: "fitted",
    set: &[("distance_clamp", "0.07384"), ("strength", "4.0")],
};

/// `vbgi` fitted on `diffuse` (rel, 16 frames, 96×54, R = 1 m):
/// training 0.0930 → 0.0920, held out 0.0263 → 0.0264 (+0.2 %),
/// 24 evaluations (budget spent).
///
/// ```text
/// nearfield fit vbgi --params step_power,reject_b --aov diffuse --frames 16 --budget 24 --scenes builtin:cornell,builtin:boxes,../shared/assets/scenes/crytek_sponza/Sponza.gltf@docs/src/fits/sponza-camera.json:env=../shared/assets/env/rooitou_park_1k.hdr --size 96x54 --radius 1 --spp 256 --holdout builtin:columns,builtin:city,builtin:closed-box,builtin:gap,builtin:contact,builtin:wall,../shared/assets/scenes/stanford_dragon/dragon.obj,../shared/assets/scenes/cornell_box_suzanne_gltf/cornell-box.glb --out docs/src/fits/vbgi.json
/// ```
pub const VBGI: Preset = Preset {
    name: "fitted",
    set: &[("reject_b", "0.368"), ("step_power", "1.386")],
};
