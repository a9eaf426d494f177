//! Every declared setting reaches every place that shows or uses settings, from its declaration
//! alone: the command line (`--set`, `--methods` specs), the viewer's panel, the book's table,
//! `pareto`'s sweep and `fit`'s parameters. A setting added to a family's declaration (for example
//! `technique/horizon/settings.rs` or the shared `settings/march.rs`) is covered by this test
//! without another edit anywhere.

use super::technique_state::TechniqueState;
use nearfield_render::settings::{Role, Setting, SettingKind};
use nearfield_render::technique::{self, TechniqueParams};

/// A valid value of `s` other than its default.
fn other_value(s: &Setting) -> String {
    match s.kind {
        SettingKind::Number {
            lo, hi, integer, ..
        } => {
            let d: f32 = s.default.parse().unwrap();
            let v = if d != lo { lo } else { hi };
            if integer {
                format!("{}", v as i64)
            } else {
                format!("{v}")
            }
        }
        SettingKind::Toggle => if s.default == "on" { "off" } else { "on" }.into(),
        SettingKind::Choice(words) => words.iter().find(|w| **w != s.default).unwrap().to_string(),
    }
}

#[test]
fn every_declared_setting_reaches_the_cli_viewer_book_pareto_and_fit() {
    let pages = technique::book_pages();
    let none = TechniqueParams::default();
    let mut checked = 0;
    for desc in technique::REGISTRY {
        let page = pages
            .iter()
            .find(|(name, _)| *name == format!("settings-{}.md", desc.family))
            .map(|(_, p)| p.as_str());
        let state = TechniqueState::from_command_line(desc.name, &none).unwrap();
        for s in desc.settings.iter().filter(|s| s.applies(desc.name)) {
            let what = format!("{}: {}", desc.name, s.key);
            // The command line: its default and another value parse in a spec.
            for v in [s.default.to_string(), other_value(s)] {
                let spec = format!("{}:{}={v}", desc.name, s.key);
                // A value may be refused in combination (reject_a = 1 above reject_b): only a
                // range error would mean the declaration and the parser disagree.
                if let Err(e) = technique::check_spec(&spec, &none) {
                    assert!(!e.to_string().contains("unknown setting"), "{what}: {e}");
                }
            }
            // The viewer: a value of its own, shown on the panel (which lists the settings that
            // apply, hover text from the doc line and the role).
            assert_eq!(state.value(s.key), Some(s.default), "{what}");
            // The book: a row of the family's table with its role.
            let row = format!("| `{}` |", s.key);
            let line = page
                .and_then(|p| p.lines().find(|l| l.starts_with(&row)))
                .unwrap_or_else(|| panic!("{what}: not in the book's table"));
            assert!(
                line.ends_with(&format!("| {} |", s.role_text())),
                "{what}: {line}"
            );
            // pareto: `--vary KEY=V` sweeps it; a count is scaled without being named.
            let vary = vec![(s.key.to_string(), vec![other_value(s)])];
            let configs = crate::pareto::sweep(desc.name, &vary).unwrap();
            assert!(
                configs
                    .iter()
                    .any(|c| c.spec.ends_with(&format!("{}={}", s.key, other_value(s)))),
                "{what}: not swept by --vary"
            );
            // (A count that is 0 by default, a feature switched off, scales to 0.)
            let on = s.default.parse::<f64>().is_ok_and(|d| d > 0.0);
            if on
                && s.role == Role::Count
                && matches!(s.kind, SettingKind::Number { integer: true, .. })
            {
                let auto = crate::pareto::sweep(desc.name, &[]).unwrap();
                assert!(
                    auto.iter()
                        .any(|c| c.label.starts_with(&format!("{}=", s.key))),
                    "{what}: a count the automatic sweep does not scale"
                );
            }
            // fit: every number is a parameter; `--params uniform` holds exactly the uniforms.
            if let SettingKind::Number { .. } = s.kind {
                let dims = crate::fit::parse_params(s.key, desc, &none).unwrap();
                assert_eq!(dims[0].key, s.key, "{what}");
            }
            checked += 1;
        }
        if let Ok(dims) = crate::fit::parse_params("uniform", desc, &none) {
            let keys: Vec<&str> = dims.iter().map(|d| d.key.as_str()).collect();
            let want: Vec<&str> = desc
                .settings
                .iter()
                .filter(|s| {
                    s.role == Role::Uniform
                        && s.applies(desc.name)
                        && matches!(s.kind, SettingKind::Number { .. })
                })
                .map(|s| s.key)
                .collect();
            assert_eq!(keys, want, "{}", desc.name);
        }
    }
    assert!(checked > 100, "{checked} settings checked");
}

#[test]
fn a_setting_of_another_technique_is_refused_by_fit() {
    let gtao = technique::find("gtao").unwrap();
    let e = crate::fit::parse_params("fresnel", gtao, &TechniqueParams::default()).unwrap_err();
    assert!(e.to_string().contains("does not change gtao"), "{e}");
}
