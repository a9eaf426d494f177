//! Near-field techniques and their registry.
//!
//! A technique reads the G-buffer, the direct radiance (this frame's and last frame's) and the
//! environment, and writes `ao`, `env_irradiance` and `indirect_irradiance` (the AOV
//! definitions of docs/src/aovs.md; the API in [`crate::contract::technique`]). The registry is
//! the one list that the command line, the viewer, `bench` and `compare` enumerate; [`create`]
//! makes a technique, with the shared denoiser around it where its declaration asks for it.

pub mod horizon;
pub mod none;
pub mod s3ho;
pub mod samples;
#[cfg(feature = "scratch")]
pub mod scratch;
pub mod ssdo;
pub mod vbgi;

use crate::RenderError;
pub use crate::contract::technique::{
    CheckFn, CreateFn, DenoiseFn, FarRule, FrameInfo, Output, Technique, TechniqueContext,
    TechniqueDesc, layered_texture, reject_unknown_keys, screen_texture,
};
use crate::passes::denoise;
pub use crate::settings::{
    Preset, Setting, SettingKind, TechniqueParams, keys, parse_integer, parse_number, parse_on_off,
};

/// Replaces `quality=NAME` in `params.set` by the preset's settings, placed first so that
/// explicit settings (and `--samples`, `--radius`) refine it. A technique without presets keeps
/// the key (and rejects it as unknown).
pub fn expand_presets(
    desc: &TechniqueDesc,
    params: &TechniqueParams,
) -> Result<TechniqueParams, RenderError> {
    if desc.presets.is_empty() {
        return Ok(params.clone());
    }
    let mut preset_set = Vec::new();
    let mut rest = Vec::new();
    for (k, v) in &params.set {
        if k != "quality" {
            rest.push((k.clone(), v.clone()));
            continue;
        }
        let preset =
            desc.presets
                .iter()
                .find(|p| p.name == v)
                .ok_or_else(|| RenderError::Setting {
                    technique: desc.name.into(),
                    msg: format!(
                        "quality={v}: expected {}",
                        desc.presets
                            .iter()
                            .map(|p| p.name)
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                })?;
        preset_set.clear();
        for (pk, pv) in preset.set {
            // `--samples` is `steps` for the horizon techniques.
            let overridden = (matches!(*pk, "samples" | "steps") && params.samples.is_some())
                || (*pk == "radius" && params.radius.is_some());
            if !overridden {
                preset_set.push((pk.to_string(), pv.to_string()));
            }
        }
    }
    preset_set.extend(rest);
    Ok(TechniqueParams {
        samples: params.samples,
        radius: params.radius,
        set: preset_set,
    })
}

/// Every technique, in the order shown to users. Adding a technique is its folder
/// `technique/<name>/` and one line here (docs/src/architecture.md).
pub const REGISTRY: &[TechniqueDesc] = &[
    none::DESC,
    ssdo::SSAO,
    ssdo::SSDO,
    ssdo::SSDO_VPL,
    ssdo::INSTANT_RADIOSITY,
    s3ho::S3HO,
    s3ho::SSBN,
    horizon::GTAO,
    horizon::HBIL,
    vbgi::VBGI,
    #[cfg(feature = "scratch")]
    scratch::DESC,
];

/// Names of all registered techniques.
pub fn names() -> Vec<&'static str> {
    REGISTRY.iter().map(|t| t.name).collect()
}

/// Splits a method spec `name` or `name:key=value+key=value` (a technique with settings, as
/// `bench` and `compare` accept in `--methods`) into the name and its settings.
pub fn split_spec(spec: &str) -> (&str, Vec<(String, String)>) {
    match spec.split_once(':') {
        None => (spec, Vec::new()),
        Some((name, rest)) => (
            name,
            rest.split('+')
                .map(|kv| match kv.split_once('=') {
                    Some((k, v)) => (k.trim().to_string(), v.trim().to_string()),
                    None => (kv.trim().to_string(), String::new()),
                })
                .collect(),
        ),
    }
}

/// The parameters a technique is made with from a spec (`name` or `name:key=value+…`) and the
/// command line's: the spec's settings after the others, `quality` expanded first.
pub fn resolve_params(
    spec: &str,
    params: &TechniqueParams,
) -> Result<(&'static TechniqueDesc, TechniqueParams), RenderError> {
    let desc = find(spec)?;
    let mut params = params.clone();
    params.set.extend(split_spec(spec).1);
    let params = expand_presets(desc, &params)?;
    Ok((desc, params))
}

/// A technique resolved once: its declaration, the spec and parameters as given (to show and to
/// compare), and the parameters it is made with, checked. What [`crate::Renderer::new`] takes.
#[derive(Clone)]
pub struct Spec {
    pub desc: &'static TechniqueDesc,
    /// `name` or `name:key=value+…`, as named.
    pub spec: String,
    /// The command line's parameters, as given.
    pub given: TechniqueParams,
    /// The spec's settings after the given ones, `quality` expanded ([`resolve_params`]).
    pub params: TechniqueParams,
}

impl Spec {
    /// Resolves `spec` against the command line's parameters and parses its settings without a
    /// device: the error `create` would give for a refused setting, before anything is loaded.
    pub fn resolve(spec: &str, given: &TechniqueParams) -> Result<Spec, RenderError> {
        let (desc, params) = resolve_params(spec, given)?;
        (desc.check)(&params).map_err(RenderError::setting(desc.name))?;
        Ok(Spec {
            desc,
            spec: spec.to_string(),
            given: given.clone(),
            params,
        })
    }

    /// The near-field radius R (m): its `radius` setting (`--radius`, `--set radius=`, a preset,
    /// the spec), else the technique's default; `None` for a technique without one (`none`).
    pub fn radius(&self) -> Option<f32> {
        radius_in(self.desc, &self.params)
    }

    /// The parameters it is made with in a frame with a probe volume (`volume`) or under the sky:
    /// with a volume its declaration's `with_volume` settings go first (so that the given ones
    /// refine them), unless the first one's key is given.
    pub fn params_for(&self, volume: bool) -> std::borrow::Cow<'_, TechniqueParams> {
        let given = |key: &str| self.params.set.iter().any(|(k, _)| k == key);
        if !(volume && self.desc.takes_with_volume(given)) {
            return std::borrow::Cow::Borrowed(&self.params);
        }
        let mut params = self.params.clone();
        params.set.splice(
            0..0,
            self.desc
                .with_volume
                .iter()
                .map(|(k, v)| (k.to_string(), v.to_string())),
        );
        std::borrow::Cow::Owned(params)
    }
}

/// The radius of `desc` under resolved `params` ([`Spec::radius`]).
fn radius_in(desc: &TechniqueDesc, params: &TechniqueParams) -> Option<f32> {
    let setting = desc.settings.iter().find(|s| s.key == "radius")?;
    let typed = params
        .set
        .iter()
        .rev()
        .find(|(k, _)| k == "radius")
        .map(|(_, v)| v.as_str());
    match (typed, params.radius) {
        (Some(v), _) => v.parse().ok(),
        (None, Some(r)) => Some(r),
        (None, None) => setting.default.parse().ok(),
    }
}

/// The near-field radius R (m) a spec resolves to ([`Spec::radius`]). Unlike [`Spec::resolve`]
/// it does not check the other settings.
pub fn radius_of(spec: &str, given: &TechniqueParams) -> Result<Option<f32>, RenderError> {
    let (desc, params) = resolve_params(spec, given)?;
    Ok(radius_in(desc, &params))
}

/// Resolves a spec against the command line's parameters and parses its settings without a
/// device ([`Spec::resolve`]).
pub fn check_spec(spec: &str, params: &TechniqueParams) -> Result<(), RenderError> {
    Spec::resolve(spec, params).map(|_| ())
}

/// Looks a technique up by name (or by a `name:key=value` spec).
pub fn find(spec: &str) -> Result<&'static TechniqueDesc, RenderError> {
    let name = split_spec(spec).0;
    REGISTRY
        .iter()
        .find(|t| t.name == name)
        .ok_or_else(|| RenderError::UnknownTechnique {
            name: name.to_string(),
            known: names().join(", "),
        })
}

/// Makes the technique `desc` declares from `params` (resolved: see [`resolve_params`]); where
/// its declaration names a denoiser and the settings choose `denoise=svgf`, the technique writes
/// the denoiser's images and the denoiser writes `ctx.outputs`.
pub fn create(
    desc: &TechniqueDesc,
    ctx: &TechniqueContext,
    params: &TechniqueParams,
) -> Result<Box<dyn Technique>, RenderError> {
    for output in desc.writes {
        if *output != Output::BentNormal {
            ctx.outputs.require(desc.name, *output)?;
        }
    }
    match desc.denoise {
        Some(config) => {
            denoise::create_denoised(ctx, params, desc.name, desc.writes, config, |ctx| {
                (desc.create)(ctx, params)
            })
        }
        None => (desc.create)(ctx, params),
    }
}

/// Every pass of every registered technique (each name once).
pub fn pass_layouts() -> Vec<crate::bindings::PassLayout> {
    let mut out: Vec<crate::bindings::PassLayout> = Vec::new();
    for desc in REGISTRY {
        for p in (desc.pass_layouts)() {
            if !out.iter().any(|q| q.name == p.name) {
                out.push(p);
            }
        }
    }
    out
}

/// The techniques of each family with settings, in registry order: (family, its techniques).
pub fn families() -> Vec<(&'static str, Vec<&'static TechniqueDesc>)> {
    let mut out: Vec<(&'static str, Vec<&'static TechniqueDesc>)> = Vec::new();
    for desc in REGISTRY.iter().filter(|d| !d.settings.is_empty()) {
        match out.iter_mut().find(|(f, _)| *f == desc.family) {
            Some((_, v)) => v.push(desc),
            None => out.push((desc.family, vec![desc])),
        }
    }
    out
}

/// The book's generated settings pages: (file name, content) per family, e.g.
/// `settings-ssdo.md`, each naming the techniques it applies to and giving the table (the
/// family's first technique's; the `fitted` preset is described in the table's first line).
pub fn book_pages() -> Vec<(String, String)> {
    families()
        .into_iter()
        .map(|(family, descs)| {
            let names: Vec<String> = descs.iter().map(|d| format!("`{}`", d.name)).collect();
            let first = descs[0];
            let volume: String = descs
                .iter()
                .filter(|d| !d.with_volume.is_empty())
                .map(|d| {
                    let set: Vec<String> =
                        d.with_volume.iter().map(|(k, v)| format!("{k}={v}")).collect();
                    format!(
                        "\n\nWith a probe volume (`--far volume`, and `auto` for the image) `{}` \
                         takes {} over the defaults below unless `{}` is given ([Near and \
                         far](../near-far.md#counting-each-technique-once)).",
                        d.name,
                        set.join(", "),
                        d.with_volume[0].0
                    )
                })
                .collect();
            let presets: Vec<Preset> = first
                .presets
                .iter()
                .filter(|p| p.name != "fitted")
                .copied()
                .collect();
            (
                format!("settings-{family}.md"),
                format!(
                    "<!-- generated from the settings declarations (crates/render/src/technique/*/settings.rs \
                     and the shared groups in crates/render/src/settings/); \
                     regenerate with `cargo run -p nearfield-cli --example book_reference` -->\n\n\
                     Settings of {}: `--set key=value` on the command line, `technique:key=value` \
                     (joined by `+`) in `--methods`, the panel in the viewer. The role says what a \
                     setting is for: a `count` scales the work (`pareto` sweeps it), a \
                     `structural` setting shapes the passes, a `denoiser` setting chooses or \
                     shapes the denoising (a change of any of these three rebuilds the \
                     technique); a `uniform` is written in place (`fit` fits these), and so is \
                     a `filter`, a denoising filter's tuning.{volume}\n\n{}",
                    names.join(", "),
                    crate::settings::markdown_table(first.settings, &presets)
                ),
            )
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_declared_default_parses() {
        // Each technique's settings parse with nothing set (Default::default() would panic on a
        // declared default that does not parse), and every declared default passes its own
        // range check.
        for desc in REGISTRY {
            (desc.check)(&TechniqueParams::default()).unwrap();
            for s in desc.settings {
                s.check(s.default).unwrap();
            }
        }
    }

    #[test]
    fn the_settings_taken_with_a_volume_parse_and_yield_to_given_ones() {
        for desc in REGISTRY.iter().filter(|d| !d.with_volume.is_empty()) {
            let spec = Spec::resolve(desc.name, &TechniqueParams::default()).unwrap();
            let with = spec.params_for(true);
            (desc.check)(&with).unwrap();
            assert_eq!(with.set.len(), desc.with_volume.len(), "{}", desc.name);
            assert!(spec.params_for(false).set.is_empty(), "{}", desc.name);
            // The first key given by hand: none of them is taken.
            let (key, _) = desc.with_volume[0];
            let given = TechniqueParams {
                set: vec![(
                    key.to_string(),
                    desc.settings
                        .iter()
                        .find(|s| s.key == key)
                        .unwrap()
                        .default
                        .to_string(),
                )],
                ..Default::default()
            };
            let spec = Spec::resolve(desc.name, &given).unwrap();
            assert_eq!(spec.params_for(true).set, given.set, "{}", desc.name);
        }
        // ssdo peels a second layer with a volume.
        let spec = Spec::resolve("ssdo:steps=8", &TechniqueParams::default()).unwrap();
        let set = spec.params_for(true).into_owned().set;
        assert_eq!(
            set.first().map(|(k, v)| (k.as_str(), v.as_str())),
            Some(("layers", "2"))
        );
        assert_eq!(
            set.last().map(|(k, v)| (k.as_str(), v.as_str())),
            Some(("steps", "8"))
        );
    }
}
