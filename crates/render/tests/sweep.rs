//! The settings sweep: for every registered technique, random combinations of valid settings
//! (each setting at its lower or upper bound, its default or a random value in range; presets
//! among them) rendered at 32×32 for 2 frames: no panic, no GPU validation error, no NaN or
//! infinity in any AOV, `ao` within [0, 1]. A combination the technique refuses as a whole
//! (settings that constrain each other) must be refused with one line. Then random invalid
//! values: refused with one line naming the setting, and the renderer keeps working.
//!
//! `SWEEP_COMBOS` sets the number of valid combinations over all techniques (default below, what
//! CI runs); `SWEEP_SEED` the seed; `SWEEP_TECHNIQUES` a comma-separated subset. `cargo test --release -p nearfield-render --test sweep --
//! --nocapture` with `SWEEP_COMBOS=10000` is the full sweep.

mod common;

use nearfield_render::settings::SettingKind;
use nearfield_render::technique::{REGISTRY, TechniqueDesc};
use nearfield_render::{Aov, RenderSettings, Renderer, TechniqueParams};
use std::sync::{Arc, Mutex};

/// Valid combinations CI renders (over all techniques).
const CI_COMBOS: usize = 600;

fn env_or<T: std::str::FromStr>(key: &str, default: T) -> T {
    std::env::var(key)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

fn number_text(x: f32) -> String {
    format!("{x}")
}

/// A valid value of one setting: a bound, the default or a random value in range.
fn valid_value(rng: &mut fastrand::Rng, kind: &SettingKind, default: &str) -> String {
    match *kind {
        SettingKind::Number {
            lo,
            hi,
            integer,
            log,
        } => {
            // Counts are pipeline constants: mostly their bounds and default (compiled once,
            // then cached), sometimes any value in range.
            let x = match rng.u32(0..if integer { 4 } else { 6 }) {
                0 => lo,
                1 => hi,
                2 => return default.to_string(),
                3 if integer && rng.u32(0..20) != 0 => return default.to_string(),
                _ if log && lo > 0.0 => (lo.ln() + rng.f32() * (hi.ln() - lo.ln())).exp(),
                _ => lo + rng.f32() * (hi - lo),
            };
            let x = if integer { x.round() } else { x };
            number_text(x.clamp(lo, hi))
        }
        SettingKind::Toggle => if rng.bool() { "on" } else { "off" }.into(),
        SettingKind::Choice(options) => options[rng.usize(..options.len())].into(),
    }
}

/// An invalid value of one setting (None when the kind has none of that sort).
fn invalid_value(rng: &mut fastrand::Rng, kind: &SettingKind) -> Option<String> {
    match *kind {
        SettingKind::Number {
            lo, hi, integer, ..
        } => {
            let mut options = vec![
                number_text(lo - (lo.abs() * 0.5 + 1.0)),
                "nan".to_string(),
                "-inf".to_string(),
                "twelve".to_string(),
                String::new(),
            ];
            if hi.is_finite() {
                options.push(number_text(hi * 2.0 + 1.0));
                options.push("inf".into());
            }
            if integer && lo + 0.5 < hi {
                options.push(number_text(lo + 0.5));
            }
            Some(options[rng.usize(..options.len())].clone())
        }
        SettingKind::Toggle => Some("maybe".into()),
        SettingKind::Choice(_) => Some("magic".into()),
    }
}

fn combination(rng: &mut fastrand::Rng, desc: &TechniqueDesc) -> Vec<(String, String)> {
    let mut set = Vec::new();
    if !desc.presets.is_empty() && rng.u32(0..4) == 0 {
        let p = &desc.presets[rng.usize(..desc.presets.len())];
        set.push(("quality".to_string(), p.name.to_string()));
    }
    for s in desc.settings {
        if s.key == "quality" || rng.u32(0..3) == 0 {
            continue;
        }
        set.push((s.key.to_string(), valid_value(rng, &s.kind, s.default)));
    }
    set
}

/// Every float AOV: finite everywhere; `ao` within [0, 1].
fn check_aovs(r: &mut Renderer, what: &str) -> Result<(), String> {
    for aov in Aov::ALL {
        if aov == Aov::Final {
            continue;
        }
        let img = r.read_aov(aov);
        for (i, p) in img.pixels.iter().enumerate() {
            if !p.iter().all(|c| c.is_finite()) {
                return Err(format!("{what}: {} pixel {} is {p:?}", aov.name(), i));
            }
            if aov == Aov::Ao && !(0.0..=1.0).contains(&p[0]) {
                return Err(format!("{what}: ao pixel {i} is {}", p[0]));
            }
        }
    }
    Ok(())
}

#[test]
fn random_valid_settings_render_finite_aovs_and_invalid_ones_are_refused() {
    let Some(ctx) = common::context() else { return };
    let total: usize = env_or("SWEEP_COMBOS", CI_COMBOS);
    let seed: u64 = env_or("SWEEP_SEED", 1);
    let errors = Arc::new(Mutex::new(Vec::<String>::new()));
    let sink = errors.clone();
    ctx.device
        .on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
            sink.lock().unwrap().push(e.to_string());
        }));
    let scene = nearfield_scene::builtin::scene("cornell").unwrap();
    let env = nearfield_scene::Environment::constant(glam::Vec3::splat(0.8));
    let camera = scene.default_camera();
    let settings = RenderSettings {
        size: (32, 32),
        ..Default::default()
    };
    // ssdo-vpl renders up to 256 shadow maps per frame: a third of the others' share.
    let weight = |name: &str| if name == "ssdo-vpl" { 1.0 / 3.0 } else { 1.0 };
    let weights: f64 = REGISTRY.iter().map(|d| weight(d.name)).sum();
    let mut report = Vec::new();
    let (mut total_rendered, mut total_refused, mut total_invalid) = (0, 0, 0);
    let mut failures = Vec::new();
    // `SWEEP_TECHNIQUES=a,b` sweeps only those (each with its share of SWEEP_COMBOS).
    let only: Option<Vec<String>> = std::env::var("SWEEP_TECHNIQUES")
        .ok()
        .map(|v| v.split(',').map(str::to_string).collect());
    for (t, desc) in REGISTRY.iter().enumerate() {
        if only
            .as_ref()
            .is_some_and(|o| !o.iter().any(|n| n == desc.name))
        {
            continue;
        }
        let start = std::time::Instant::now();
        let mut rng = fastrand::Rng::with_seed(seed ^ (t as u64) << 32);
        let mut r = Renderer::new(
            &ctx,
            &scene,
            &env,
            None,
            camera,
            &nearfield_render::technique::Spec::resolve(desc.name, &TechniqueParams::default())
                .unwrap(),
            settings,
        )
        .unwrap();
        let (mut rendered, mut refused, mut invalid) = (0, 0, 0);
        let per = ((total as f64 * weight(desc.name) / weights).ceil() as usize).max(1);
        for i in 0..per {
            let set = combination(&mut rng, desc);
            let spec = format!(
                "{}:{}",
                desc.name,
                set.iter()
                    .map(|(k, v)| format!("{k}={v}"))
                    .collect::<Vec<_>>()
                    .join("+")
            );
            let params = TechniqueParams {
                set: set.clone(),
                ..Default::default()
            };
            let what = format!("{} combination {i} ({spec})", desc.name);
            if let Err(e) = r.set_technique(desc.name, &params) {
                let msg = e.to_string();
                if msg.contains("GPU error") || msg.contains('\n') {
                    failures.push(format!("{what}: {msg}"));
                } else {
                    refused += 1;
                }
                continue;
            }
            r.render_frame();
            r.render_frame();
            if let Err(e) = check_aovs(&mut r, &what) {
                failures.push(e);
            }
            rendered += 1;
            let mut errs = errors.lock().unwrap();
            if !errs.is_empty() {
                failures.push(format!("{what}: GPU errors: {}", errs.join("; ")));
                errs.clear();
            }
        }
        // Invalid values, one setting at a time on top of the defaults.
        for _ in 0..per / 4 + 1 {
            if desc.settings.is_empty() {
                break;
            }
            let s = &desc.settings[rng.usize(..desc.settings.len())];
            let Some(v) = invalid_value(&mut rng, &s.kind) else {
                continue;
            };
            let params = TechniqueParams {
                set: vec![(s.key.to_string(), v.clone())],
                ..Default::default()
            };
            match r.set_technique(desc.name, &params) {
                Ok(()) => failures.push(format!("{}: {}={v} was accepted", desc.name, s.key)),
                Err(e) => {
                    let msg = e.to_string();
                    if msg.contains('\n') || !msg.contains(s.key) {
                        failures.push(format!("{}: {}={v} refused as: {msg}", desc.name, s.key));
                    }
                }
            }
            invalid += 1;
        }
        // Unknown keys too; then the renderer still renders.
        assert!(
            r.set_technique(
                desc.name,
                &TechniqueParams {
                    set: vec![("nosuch".into(), "1".into())],
                    ..Default::default()
                }
            )
            .is_err()
        );
        r.render_frame();
        if let Err(e) = check_aovs(&mut r, &format!("{} after refusals", desc.name)) {
            failures.push(e);
        }
        total_rendered += rendered;
        total_refused += refused;
        total_invalid += invalid;
        eprintln!(
            "sweep {}: {rendered} rendered, {refused} refused, {invalid} invalid refused, {:.1} s",
            desc.name,
            start.elapsed().as_secs_f64()
        );
        report.push(format!(
            "sweep {}: {rendered} rendered, {refused} refused as combinations, {invalid} invalid values refused, {:.1} s",
            desc.name,
            start.elapsed().as_secs_f64()
        ));
    }
    for line in &report {
        println!("{line}");
    }
    println!(
        "sweep: {total_rendered} combinations rendered, {total_refused} refused as combinations, {total_invalid} invalid values refused; {} failures",
        failures.len()
    );
    assert!(
        failures.is_empty(),
        "{} failures:\n{}",
        failures.len(),
        failures.join("\n")
    );
}
