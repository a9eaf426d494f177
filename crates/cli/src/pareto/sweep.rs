//! The configurations `pareto` measures: the defaults, the quality presets, and each setting
//! the declarations mark for sweeping (counts scaled, denoisers' every value), or `--vary`.

use crate::BadInput;
use anyhow::Result;
use nearfield_render::settings::{Role, SettingKind};
use nearfield_render::technique::TechniqueDesc;

/// One configuration of a technique: what it is called in the plot and its spec.
#[derive(Clone, Debug, PartialEq)]
pub struct Config {
    pub label: String,
    pub spec: String,
}

/// `name:key=value+key=value` with `extra` appended.
fn spec_plus(base: &str, extra: &str) -> String {
    if base.contains(':') {
        format!("{base}+{extra}")
    } else {
        format!("{base}:{extra}")
    }
}

/// The values `key` takes in the base spec, or its default.
fn current(desc: &TechniqueDesc, base: &str, key: &str) -> Option<String> {
    let (_, pairs) = nearfield_render::technique::split_spec(base);
    pairs
        .iter()
        .rev()
        .find(|(k, _)| k == key)
        .map(|(_, v)| v.clone())
        .or_else(|| {
            desc.settings
                .iter()
                .find(|s| s.key == key)
                .map(|s| s.default.to_string())
        })
}

/// `--vary KEY=V1,V2`: the keys and their values, checked for emptiness.
pub fn parse_vary(vary: &[String]) -> Result<Vec<(String, Vec<String>)>> {
    let mut out: Vec<(String, Vec<String>)> = Vec::new();
    for v in vary {
        let (k, list) = v
            .split_once('=')
            .ok_or_else(|| BadInput(format!("--vary {v}: expected KEY=V1,V2,...")))?;
        let k = k.trim();
        let values: Vec<String> = list
            .split(',')
            .map(str::trim)
            .filter(|s| !s.is_empty())
            .map(String::from)
            .collect();
        if k.is_empty() || values.is_empty() {
            return Err(
                BadInput(format!("--vary {v}: empty sweep (expected KEY=V1,V2,...)")).into(),
            );
        }
        if out.iter().any(|(o, _)| o == k) {
            return Err(BadInput(format!("--vary: {k} is named twice")).into());
        }
        out.push((k.to_string(), values));
    }
    Ok(out)
}

/// The configurations of technique spec `base` (defaults first).
pub fn sweep(base: &str, vary: &[(String, Vec<String>)]) -> Result<Vec<Config>> {
    let desc = nearfield_render::technique::find(base)?;
    let mut configs = vec![Config {
        label: "default".into(),
        spec: base.to_string(),
    }];
    let mut push = |label: String, spec: String| {
        if !configs.iter().any(|c| c.spec == spec) {
            configs.push(Config { label, spec });
        }
    };
    let has = |key: &str| desc.settings.iter().any(|s| s.key == key);
    if !vary.is_empty() {
        for (key, values) in vary {
            if !has(key) {
                continue;
            }
            for v in values {
                push(format!("{key}={v}"), spec_plus(base, &format!("{key}={v}")));
            }
        }
    } else {
        for p in desc.presets {
            push(
                format!("quality={}", p.name),
                spec_plus(base, &format!("quality={}", p.name)),
            );
        }
        // What the declarations say: counts are scaled, every value of a denoising toggle or
        // choice is tried, for the settings that apply to this technique.
        for s in desc.settings.iter().filter(|s| s.applies(desc.name)) {
            let Some(now) = current(desc, base, s.key) else {
                continue;
            };
            match s.kind {
                SettingKind::Number {
                    lo,
                    hi,
                    integer: true,
                    ..
                } if s.role == Role::Count => {
                    let Ok(d) = now.parse::<f64>() else { continue };
                    for f in [0.25, 0.5, 2.0] {
                        let v = (d * f).round().clamp(lo as f64, hi as f64);
                        if v != d && v >= 1.0 {
                            push(
                                format!("{}={v}", s.key),
                                spec_plus(base, &format!("{}={v}", s.key)),
                            );
                        }
                    }
                }
                SettingKind::Toggle if s.role == Role::Denoiser => {
                    let other = if now == "on" { "off" } else { "on" };
                    push(
                        format!("{}={other}", s.key),
                        spec_plus(base, &format!("{}={other}", s.key)),
                    );
                }
                SettingKind::Choice(values) if s.role == Role::Denoiser => {
                    for v in values.iter().filter(|v| **v != now) {
                        push(
                            format!("{}={v}", s.key),
                            spec_plus(base, &format!("{}={v}", s.key)),
                        );
                    }
                }
                _ => {}
            }
        }
    }
    if configs.len() < 2 {
        return Err(BadInput(format!(
            "{}: empty sweep: {} has no quality presets, count or denoising settings{}",
            base,
            desc.name,
            if vary.is_empty() {
                ""
            } else {
                " named by --vary"
            }
        ))
        .into());
    }
    Ok(configs)
}

/// Every setting of technique spec `spec` with its value (defaults, then the preset's and the
/// spec's own values; numbers compared as numbers): what two specs must share to be one
/// configuration.
pub(super) fn effective_settings(
    spec: &str,
    params: &nearfield_render::TechniqueParams,
) -> Result<Vec<(String, String)>> {
    let (desc, resolved) = nearfield_render::technique::resolve_params(spec, params)?;
    let mut values: Vec<(String, String)> = desc
        .settings
        .iter()
        .map(|s| (s.key.to_string(), s.default.to_string()))
        .collect();
    for (k, v) in &resolved.set {
        if let Some(slot) = values.iter_mut().find(|(key, _)| key == k) {
            slot.1 = v.clone();
        } else {
            values.push((k.clone(), v.clone()));
        }
    }
    if let Some(n) = resolved.samples {
        values.push(("--samples".into(), n.to_string()));
    }
    for (_, v) in &mut values {
        if let Ok(x) = v.parse::<f64>() {
            *v = format!("{x}");
        }
    }
    Ok(values)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_automatic_sweep_scales_counts_and_tries_the_denoisers() {
        let c = sweep("gtao", &[]).unwrap();
        let specs: Vec<&str> = c.iter().map(|c| c.spec.as_str()).collect();
        assert_eq!(specs[0], "gtao");
        for want in [
            "gtao:quality=low",
            "gtao:quality=fitted",
            "gtao:slices=1",
            "gtao:slices=4",
            "gtao:steps=4",
            "gtao:steps=8",
            "gtao:steps=32",
            "gtao:denoise=off",
            "gtao:denoise=svgf",
            "gtao:temporal=off",
        ] {
            assert!(specs.contains(&want), "{want} missing from {specs:?}");
        }
        // slices=2 × ½ = 1 and × ¼ = 0.5 → 1 (once); nothing equals the default.
        assert_eq!(specs.iter().filter(|s| **s == "gtao:slices=1").count(), 1);
        assert!(!specs.contains(&"gtao:slices=2"));
        // On top of a base spec.
        let c = sweep("gtao:denoise=off", &[]).unwrap();
        assert!(c.iter().any(|c| c.spec == "gtao:denoise=off+slices=4"));
        assert!(
            c.iter()
                .any(|c| c.spec == "gtao:denoise=off+denoise=bilateral")
        );
    }

    #[test]
    fn settings_of_other_techniques_are_not_swept() {
        let specs: Vec<String> = sweep("ssao", &[])
            .unwrap()
            .into_iter()
            .map(|c| c.spec)
            .collect();
        assert!(specs.contains(&"ssao:samples=8".to_string()), "{specs:?}");
        assert!(
            !specs
                .iter()
                .any(|s| s.contains("vpls") || s.contains("light_samples")),
            "{specs:?}"
        );
        let specs: Vec<String> = sweep("ssdo-vpl", &[])
            .unwrap()
            .into_iter()
            .map(|c| c.spec)
            .collect();
        assert!(specs.iter().any(|s| s.contains("vpls=")), "{specs:?}");
    }

    #[test]
    fn a_preset_equal_to_the_defaults_is_one_configuration() {
        let p = nearfield_render::TechniqueParams::default();
        // gtao's medium preset is its defaults (2 slices × 16 steps).
        assert_eq!(
            effective_settings("gtao", &p).unwrap(),
            effective_settings("gtao:quality=medium", &p).unwrap()
        );
        assert_eq!(
            effective_settings("gtao:steps=16.0", &p).unwrap(),
            effective_settings("gtao", &p).unwrap()
        );
        assert_ne!(
            effective_settings("gtao:quality=low", &p).unwrap(),
            effective_settings("gtao", &p).unwrap()
        );
    }

    #[test]
    fn vary_replaces_the_sweep_and_an_empty_sweep_is_refused() {
        let vary = parse_vary(&["steps=2,3".into()]).unwrap();
        let c = sweep("gtao", &vary).unwrap();
        let specs: Vec<&str> = c.iter().map(|c| c.spec.as_str()).collect();
        assert_eq!(specs, ["gtao", "gtao:steps=2", "gtao:steps=3"]);
        assert!(sweep("none", &[]).is_err());
        let other = parse_vary(&["nosuch=1".into()]).unwrap();
        assert!(sweep("gtao", &other).is_err(), "gtao has no setting nosuch");
        assert!(parse_vary(&["steps=".into()]).is_err());
        assert!(parse_vary(&["steps".into()]).is_err());
    }
}
