//! The render world: per view, nearfield's input and output images, its group 0 and the created
//! technique; each frame the glue passes around the technique's own passes.
//!
//! Order inside Bevy's `Core3d` schedule: after the prepasses, `nodes::inputs_and_technique` (Bevy's
//! depth, normal and motion → nearfield's inputs; the technique; its ao into Bevy's ao image);
//! after the main pass, `nodes::capture_and_add` (Bevy's lit colour kept as next frame's radiance;
//! the indirect light added where the camera has Bevy's deferred G-buffer).

mod environment;
mod nodes;
mod pipelines;
mod prepare;

use bevy::core_pipeline::schedule::{Core3d, Core3dSystems};
use bevy::prelude::*;
use bevy::render::{Render, RenderSystems};
pub use environment::ViewEnvironment;
pub use prepare::{Image, Images, NearFieldView};

pub(crate) fn build(render_app: &mut bevy::app::SubApp) {
    render_app
        .init_resource::<pipelines::GluePipelines>()
        .add_systems(
            Render,
            (
                prepare::prepare_views.in_set(RenderSystems::PrepareResources),
                prepare::skip_bevy_ssao.in_set(RenderSystems::PrepareBindGroups),
                nodes::collect.in_set(RenderSystems::Cleanup),
            ),
        )
        .add_systems(
            Core3d,
            (
                nodes::inputs_and_technique
                    .after(Core3dSystems::Prepass)
                    .before(Core3dSystems::MainPass),
                nodes::capture_and_add
                    .after(Core3dSystems::MainPass)
                    .before(Core3dSystems::EarlyPostProcess),
            ),
        );
}
