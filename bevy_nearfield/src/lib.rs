//! nearfield's vbgi, hbil and gtao inside Bevy 0.20.
//!
//! Add [`NearFieldPlugin`] to the app and a [`NearField`] component to a `Camera3d`. Each frame
//! the plugin turns Bevy's depth and normal prepasses into nearfield's documented inputs, runs
//! the technique's own kernels (the `nearfield-render` crate, on Bevy's wgpu device), and
//!
//! - feeds its ambient occlusion to Bevy's PBR, where Bevy's own SSAO would (Bevy multiplies the
//!   ambient, environment-map and irradiance-volume light by it);
//! - adds its near-field indirect light as a diffuse term `ρ (1 − metallic) E/π` after the opaque
//!   pass, where the camera has a `DeferredPrepass` and the materials are drawn deferred (the
//!   base colour comes from Bevy's G-buffer). The light it gathers is Bevy's lit colour of the
//!   frame before;
//! - with a baked far field ([`far::BakedVolume`], `nearfield bake --format bevy`: Bevy's
//!   `IrradianceVolume` in Bevy's units, and nearfield's volume beside it), reads that volume
//!   beyond R, and keeps of Bevy's volume light only what the technique does not draw itself,
//!   so that near and far are counted once. Without one, it reads the camera's environment map
//!   (`EnvironmentMapLight`, `GeneratedEnvironmentMapLight`) as its sky. [`scene`] spawns a
//!   nearfield scene's meshes, lights, environment map and exposure as `nearfield render` draws
//!   them.
//!
//! Settings that are out of range (or NaN) are refused with one logged line; the camera then
//! renders without the effect. The book's page `docs/src/bevy.md` has the setup, the settings,
//! the cost beside Bevy's SSAO, and pictures.

pub mod far;
pub mod readback;
pub mod render;
pub mod scene;

use bevy::app::{App, Plugin};
use bevy::core_pipeline::prepass::{DepthPrepass, NormalPrepass};
use bevy::ecs::query::QueryItem;
use bevy::log::error;
use bevy::pbr::{
    ScreenSpaceAmbientOcclusion, ScreenSpaceAmbientOcclusionResources, SsaoBindGroups,
    SsaoPipelineId,
};
use bevy::prelude::*;
use bevy::render::RenderApp;
use bevy::render::extract_component::{ExtractComponent, ExtractComponentPlugin};
use bevy::render::extract_resource::ExtractResourcePlugin;
use bevy::render::sync_component::SyncComponent;
use bevy::render::view::Msaa;
use nearfield_render::technique::{self, TechniqueParams};
use std::collections::HashSet;
use std::sync::{Arc, Mutex};

pub use readback::{NearFieldImages, NearFieldReadback, ReadbackImages};

/// The technique a [`NearField`] runs: a name from nearfield's registry
/// (`nearfield_render::technique::REGISTRY`), checked with the rest of the settings. `GTAO`,
/// `HBIL` and `VBGI` are the ones the book measures in Bevy; every registered technique that
/// needs no nearfield scene (its lights and geometry) runs, the others are refused with one line.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Reflect)]
pub struct NearFieldTechnique(&'static str);

impl NearFieldTechnique {
    /// Ground-truth-based ambient occlusion (Jimenez et al. 2016): ao only.
    pub const GTAO: Self = Self::registered("gtao");
    /// Horizon-based indirect lighting (Mayaux 2018): ao and one bounce from last frame's colour.
    pub const HBIL: Self = Self::registered("hbil");
    /// Visibility-bitmask GI (horizon slices with thickness): ao and one bounce, denoised.
    pub const VBGI: Self = Self::registered("vbgi");

    /// The technique registered as `name`; a name the registry does not hold fails to compile
    /// where it is a constant.
    pub const fn registered(name: &'static str) -> Self {
        let mut i = 0;
        while i < technique::REGISTRY.len() {
            if str_eq(technique::REGISTRY[i].name, name) {
                return NearFieldTechnique(technique::REGISTRY[i].name);
            }
            i += 1;
        }
        panic!("not a registered technique");
    }

    /// The technique named `name` (`nearfield render --method NAME`), or the registry's error.
    pub fn named(name: &str) -> Result<Self, String> {
        technique::find(name)
            .map(|d| NearFieldTechnique(d.name))
            .map_err(|e| e.to_string())
    }

    /// Every registered technique.
    pub fn all() -> impl Iterator<Item = Self> {
        technique::REGISTRY
            .iter()
            .map(|d| NearFieldTechnique(d.name))
    }

    /// nearfield's name of the technique.
    pub fn name(self) -> &'static str {
        self.0
    }

    /// Whether it computes indirect light (gtao writes only ao): what its registration declares.
    pub fn has_indirect(self) -> bool {
        technique::find(self.0)
            .is_ok_and(|d| d.writes.contains(&technique::Output::IndirectIrradiance))
    }

    /// Whether it has the setting `key`.
    fn has_setting(self, key: &str) -> bool {
        technique::find(self.0).is_ok_and(|d| d.settings.iter().any(|s| s.key == key))
    }
}

impl Default for NearFieldTechnique {
    fn default() -> Self {
        NearFieldTechnique::VBGI
    }
}

const fn str_eq(a: &str, b: &str) -> bool {
    let (a, b) = (a.as_bytes(), b.as_bytes());
    if a.len() != b.len() {
        return false;
    }
    let mut i = 0;
    while i < a.len() {
        if a[i] != b[i] {
            return false;
        }
        i += 1;
    }
    true
}

/// Quality presets in Bevy's style: nearfield's `quality=low|medium|high|ultra` (slices and steps
/// per pixel; vbgi also its sectors). `Custom` keeps the technique's own defaults, refined by
/// [`NearField::settings`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Reflect)]
pub enum NearFieldQuality {
    Low,
    Medium,
    #[default]
    High,
    Ultra,
    Custom,
}

impl NearFieldQuality {
    fn preset(self) -> Option<&'static str> {
        match self {
            NearFieldQuality::Low => Some("low"),
            NearFieldQuality::Medium => Some("medium"),
            NearFieldQuality::High => Some("high"),
            NearFieldQuality::Ultra => Some("ultra"),
            NearFieldQuality::Custom => None,
        }
    }
}

/// Screen-space near-field light on a `Camera3d`: ambient occlusion into Bevy's PBR and indirect
/// light added as a diffuse term. Requires `Msaa::Off`; the indirect term needs a
/// `DeferredPrepass` (and the camera's `Hdr` for a colour that is radiance, not display values).
/// Do not combine it with Bevy's own `ScreenSpaceAmbientOcclusion` on the same camera.
#[derive(Component, Clone, Debug, PartialEq, Reflect)]
#[require(DepthPrepass, NormalPrepass)]
pub struct NearField {
    pub technique: NearFieldTechnique,
    pub quality: NearFieldQuality,
    /// The near-field radius R in metres (nearfield's `--radius`); `None`: the technique's
    /// default. Bevy's SSAO `radius` is the same quantity.
    pub radius: Option<f32>,
    /// Whether the ao darkens Bevy's ambient light (false: only the indirect light is added).
    pub ambient_occlusion: bool,
    /// Scale of the indirect light added (1: the one bounce as computed; 0: none).
    pub indirect_intensity: f32,
    /// Further settings of the technique, as `nearfield render --set key=value` takes them
    /// (the book's settings pages list every key with its range).
    pub settings: Vec<(String, String)>,
}

impl Default for NearField {
    fn default() -> Self {
        NearField {
            technique: NearFieldTechnique::default(),
            quality: NearFieldQuality::default(),
            radius: None,
            ambient_occlusion: true,
            indirect_intensity: 1.0,
            settings: Vec::new(),
        }
    }
}

impl NearField {
    /// The technique's parameters, checked as `nearfield render` checks them: the first error
    /// names the setting and its range.
    pub fn params(&self) -> Result<TechniqueParams, String> {
        if let Some(r) = self.radius
            && !(r.is_finite() && r > 0.0)
        {
            return Err(format!("radius={r}: must be a finite number > 0"));
        }
        if !(self.indirect_intensity.is_finite() && self.indirect_intensity >= 0.0) {
            return Err(format!(
                "indirect_intensity={}: must be a finite number >= 0",
                self.indirect_intensity
            ));
        }
        let mut set = Vec::new();
        if let Some(q) = self.quality.preset() {
            set.push(("quality".to_string(), q.to_string()));
        }
        // A default thickness from a second depth layer (vbgi's), which Bevy does not render:
        // the plugin's default is the thickness proportional to depth.
        if self.technique.has_setting("thickness")
            && !self.settings.iter().any(|(k, _)| k == "thickness")
        {
            set.push(("thickness".to_string(), "adaptive".to_string()));
        }
        // The radiance gathered is Bevy's lit colour of the frame before, which the plugin hands
        // in as the technique's direct radiance: nearfield's own feedback (`source=previous`)
        // would rebuild it from albedo, which Bevy's prepasses do not give.
        if self.technique.has_setting("source") && !self.settings.iter().any(|(k, _)| k == "source")
        {
            set.push(("source".to_string(), "direct".to_string()));
        }
        set.extend(self.settings.iter().cloned());
        let params = TechniqueParams {
            samples: None,
            radius: self.radius,
            set,
        };
        let name = self.technique.name();
        technique::check_spec(name, &params).map_err(|e| e.to_string())?;
        let (_, resolved) = technique::resolve_params(name, &params).map_err(|e| e.to_string())?;
        Ok(resolved)
    }
}

/// The plugin: add it once; it does nothing for cameras without [`NearField`].
pub struct NearFieldPlugin;

impl Plugin for NearFieldPlugin {
    fn build(&self, app: &mut App) {
        app.register_type::<NearField>()
            .add_plugins(ExtractComponentPlugin::<NearField>::default())
            .add_plugins(ExtractResourcePlugin::<far::NearFieldVolume>::default())
            .add_systems(
                Update,
                (check_settings, apply_refusals.after(check_settings)),
            );
        let refusals = Refusals::default();
        app.insert_resource(refusals.clone());
        if let Some(render_app) = app.get_sub_app_mut(RenderApp) {
            render_app.insert_resource(refusals);
        }
        readback::build(app);
    }

    fn finish(&self, app: &mut App) {
        let Some(render_app) = app.get_sub_app_mut(RenderApp) else {
            return;
        };
        render::build(render_app);
    }
}

/// A camera's [`NearField`] as checked: the resolved parameters, or `None` when refused.
#[derive(Component, Clone, Debug)]
pub struct NearFieldChecked {
    /// The component as checked (a camera whose component changed since is not extracted
    /// until it is checked again).
    of: NearField,
    params: Option<TechniqueParams>,
}

impl NearFieldChecked {
    /// Whether the settings were refused (the camera renders without the effect).
    pub fn is_refused(&self) -> bool {
        self.params.is_none()
    }
}

/// Cameras whose technique the render world could not make (it logged why), by main-world
/// entity: they go without the effect until their [`NearField`] changes.
#[derive(Resource, Clone, Default)]
pub(crate) struct Refusals(pub(crate) Arc<Mutex<HashSet<Entity>>>);

fn apply_refusals(refusals: Res<Refusals>, mut checked: Query<&mut NearFieldChecked>) {
    let list: Vec<Entity> = refusals.0.lock().unwrap().iter().copied().collect();
    for entity in list {
        if let Ok(mut c) = checked.get_mut(entity)
            && !c.is_refused()
        {
            c.params = None;
        }
    }
}

/// Checks every new or changed [`NearField`] once: a refused one logs one line and leaves the
/// camera without the effect.
#[allow(clippy::type_complexity)]
fn check_settings(
    mut commands: Commands,
    refusals: Res<Refusals>,
    cameras: Query<
        (
            Entity,
            &NearField,
            Option<&Msaa>,
            Has<ScreenSpaceAmbientOcclusion>,
        ),
        Or<(Changed<NearField>, Changed<Msaa>)>,
    >,
) {
    for (entity, near_field, msaa, bevy_ssao) in &cameras {
        refusals.0.lock().unwrap().remove(&entity);
        let checked = near_field.params().and_then(|p| {
            if msaa.is_some_and(|m| *m != Msaa::Off) {
                Err("needs Msaa::Off on the camera (the prepasses are read per pixel)".into())
            } else if bevy_ssao {
                Err("the camera also has Bevy's ScreenSpaceAmbientOcclusion: use one".into())
            } else {
                Ok(p)
            }
        });
        let checked = match checked {
            Ok(p) => Some(p),
            Err(e) => {
                error!(
                    "NearField ({}) on camera {entity}: {e}; the camera renders without it",
                    near_field.technique.name()
                );
                None
            }
        };
        commands.entity(entity).insert(NearFieldChecked {
            of: near_field.clone(),
            params: checked,
        });
    }
}

/// What the render world knows of a camera's [`NearField`].
#[derive(Component, Clone, Debug)]
pub struct ExtractedNearField {
    technique: NearFieldTechnique,
    params: TechniqueParams,
    ambient_occlusion: bool,
    indirect_intensity: f32,
    /// The camera's environment map (read as the technique's sky where there is no volume).
    environment: Option<render::ViewEnvironment>,
}

impl SyncComponent<RenderApp> for NearField {
    // Bevy's SSAO components on the render-world view go with it: the view's mesh bind group
    // is laid out with an ao image exactly while they are there.
    type Target = (
        ExtractedNearField,
        render::NearFieldView,
        ScreenSpaceAmbientOcclusion,
        ScreenSpaceAmbientOcclusionResources,
        SsaoPipelineId,
        SsaoBindGroups,
    );
}

impl ExtractComponent<RenderApp> for NearField {
    type QueryData = (
        &'static NearField,
        &'static NearFieldChecked,
        Option<&'static bevy::light::EnvironmentMapLight>,
        Option<&'static bevy::light::GeneratedEnvironmentMapLight>,
        Option<&'static bevy::light::AtmosphereEnvironmentMapLight>,
    );
    type QueryFilter = ();
    type Out = (ExtractedNearField, ScreenSpaceAmbientOcclusion);

    fn extract_component(
        (near_field, checked, light, generated, atmosphere): QueryItem<'_, '_, Self::QueryData>,
    ) -> Option<Self::Out> {
        if checked.of != *near_field {
            return None;
        }
        let params = checked.params.clone()?;
        let extracted = ExtractedNearField {
            technique: near_field.technique,
            params,
            ambient_occlusion: near_field.ambient_occlusion,
            indirect_intensity: near_field.indirect_intensity,
            environment: render::ViewEnvironment::of_camera(light, generated, atmosphere),
        };
        // Bevy's PBR reads a view's ao image where the view has ScreenSpaceAmbientOcclusion;
        // the plugin skips Bevy's own SSAO passes and writes nearfield's ao there (1 where
        // `ambient_occlusion` is off).
        Some((extracted, ScreenSpaceAmbientOcclusion::default()))
    }
}
