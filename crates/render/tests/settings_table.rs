//! The settings tables (what the viewer and the book show) agree with the parsers (what
//! `--set key=value` accepts): every default, bound and choice is accepted, values outside the
//! documented range and unknown words are rejected, and the defaults parse to `Default`.
//! CPU only.

use nearfield_render::TechniqueParams;
use nearfield_render::technique::{self, SettingKind, TechniqueDesc, horizon, s3ho, ssdo, vbgi};

type Parse = fn(&TechniqueParams) -> Result<String, String>;

/// The families' typed parsers, for the defaults' comparison with `Default` (the ranges are
/// checked for every registered technique through the registry's `check`).
fn parsers() -> Vec<(&'static TechniqueDesc, Parse, String)> {
    vec![
        (
            &ssdo::SSDO,
            |p| ssdo::Settings::from_params(p).map(|s| format!("{s:?}")),
            format!("{:?}", ssdo::Settings::default()),
        ),
        (
            &s3ho::S3HO,
            |p| s3ho::Settings::from_params(p).map(|s| format!("{s:?}")),
            format!("{:?}", s3ho::Settings::default()),
        ),
        (
            &horizon::HBIL,
            |p| horizon::Settings::from_params(p).map(|s| format!("{s:?}")),
            format!("{:?}", horizon::Settings::default()),
        ),
        (
            &vbgi::VBGI,
            |p| vbgi::Settings::from_params(p).map(|s| format!("{s:?}")),
            format!("{:?}", vbgi::Settings::default()),
        ),
    ]
}

fn with(key: &str, value: &str) -> TechniqueParams {
    TechniqueParams {
        set: vec![(key.to_string(), value.to_string())],
        ..Default::default()
    }
}

#[test]
fn every_technique_with_settings_has_a_table() {
    for desc in technique::REGISTRY {
        let has_table = !desc.settings.is_empty();
        assert_eq!(
            has_table,
            desc.name != "none",
            "{}: settings table present = {has_table}",
            desc.name
        );
    }
}

/// Every default of `desc`'s table, set explicitly.
fn all_defaults(desc: &TechniqueDesc) -> TechniqueParams {
    TechniqueParams {
        set: desc
            .settings
            .iter()
            .map(|s| (s.key.to_string(), s.default.to_string()))
            .collect(),
        ..Default::default()
    }
}

#[test]
fn defaults_in_the_table_parse_to_the_default_settings() {
    for desc in technique::REGISTRY {
        (desc.check)(&all_defaults(desc)).unwrap_or_else(|e| panic!("{}: {e}", desc.name));
        for s in desc.settings {
            s.check(s.default).unwrap();
        }
    }
    for (desc, parse, default) in parsers() {
        assert_eq!(
            parse(&all_defaults(desc)).unwrap(),
            default,
            "{}",
            desc.name
        );
    }
}

#[test]
fn parser_accepts_exactly_the_documented_range() {
    // reject_a < reject_b is a constraint between two settings, not a range.
    let paired = |key: &str| key == "reject_a" || key == "reject_b";
    // Every registered technique, through the check its commands run before anything loads
    // (the registry's `check`: the settings parsed as `create` parses them).
    for desc in technique::REGISTRY {
        for s in desc.settings {
            let values: Vec<String> = match s.kind {
                SettingKind::Number {
                    lo, hi, integer, ..
                } => {
                    let mut v = vec![
                        lo.to_string(),
                        hi.to_string(),
                        (lo - 1.0).to_string(),
                        (hi * 2.0 + 1.0).to_string(),
                        "nan".into(),
                        "x".into(),
                    ];
                    if integer {
                        v.push((lo + 0.5).to_string());
                    }
                    v
                }
                SettingKind::Toggle => vec!["on".into(), "off".into(), "maybe".into()],
                SettingKind::Choice(options) => {
                    let mut v: Vec<String> = options.iter().map(|o| o.to_string()).collect();
                    v.push("bogus".into());
                    v
                }
            };
            for v in values {
                let spec_ok = s.check(&v).is_ok();
                let mut params = with(s.key, &v);
                // instant-radiosity's clamp is bound by R only while its screen-space bounce
                // adds back what the clamp removes: a constraint between two settings.
                if s.key == "vpl_clamp" {
                    params.set.push(("bounce".into(), "off".into()));
                }
                let parsed = (desc.check)(&params);
                if paired(s.key) && spec_ok {
                    continue;
                }
                assert_eq!(
                    parsed.is_ok(),
                    spec_ok,
                    "{} {}={v}: table says {spec_ok}, parser says {parsed:?}",
                    desc.name,
                    s.key
                );
            }
        }
    }
}

#[test]
fn presets_name_settings_of_the_table_with_valid_values() {
    for desc in technique::REGISTRY {
        for p in desc.presets {
            for (k, v) in p.set {
                let s = desc
                    .settings
                    .iter()
                    .find(|s| s.key == *k)
                    .unwrap_or_else(|| panic!("{} preset {}: unknown {k}", desc.name, p.name));
                s.check(v).unwrap();
            }
        }
    }
}

#[test]
fn quality_expands_first_and_explicit_settings_refine_it() {
    let params = TechniqueParams {
        samples: Some(3),
        set: vec![
            ("slices".into(), "5".into()),
            ("quality".into(), "ultra".into()),
        ],
        ..Default::default()
    };
    let hbil = technique::expand_presets(&horizon::HBIL, &params).unwrap();
    let s = horizon::Settings::from_params(&hbil).unwrap();
    // ultra = 8 slices, 32 steps; the explicit slices=5 and --samples 3 win.
    assert_eq!((s.march.slices, s.march.steps), (5, 3));
    let ssdo = technique::expand_presets(&ssdo::SSDO, &with("quality", "high")).unwrap();
    assert_eq!(ssdo::Settings::from_params(&ssdo).unwrap().samples, 32);
    let bad = technique::expand_presets(&ssdo::SSDO, &with("quality", "insane"));
    assert!(
        bad.unwrap_err()
            .to_string()
            .contains("low, medium, high, ultra")
    );
}

#[test]
fn every_technique_with_settings_has_a_generated_table() {
    // Every technique with settings is named on its family's generated page, whose table holds
    // every one of its keys; the techniques of one family share their keys.
    let pages = technique::book_pages();
    for desc in technique::REGISTRY
        .iter()
        .filter(|d| !d.settings.is_empty())
    {
        let (_, page) = pages
            .iter()
            .find(|(name, _)| *name == format!("settings-{}.md", desc.family))
            .unwrap_or_else(|| panic!("{}: no page for family {}", desc.name, desc.family));
        assert!(page.contains(&format!("`{}`", desc.name)), "{}", desc.name);
        for s in desc.settings {
            assert!(
                page.contains(&format!("| `{}` |", s.key)),
                "{}: {}",
                desc.name,
                s.key
            );
        }
    }
    for (family, descs) in technique::families() {
        for d in &descs {
            assert!(
                d.settings
                    .iter()
                    .map(|s| s.key)
                    .eq(descs[0].settings.iter().map(|s| s.key)),
                "{family}: {} and {} differ",
                d.name,
                descs[0].name
            );
        }
    }
}
