//! The passes that bind the frame targets, the environment or the technique (rebuilt together),
//! and the error scopes around resource creation.

use crate::RenderError;
use crate::contract::io::SceneInputs;
use crate::gpu_env::GpuEnvironment;
use crate::gpu_scene::GpuScene;
use crate::passes::{self, FrameGroup, ScreenPass, shadow::ShadowPass};
use crate::targets::FrameTargets;
use crate::technique::{self, Output, Technique, TechniqueContext};

/// The passes that bind the frame targets, the environment or the technique: rebuilt together.
pub(super) struct Passes {
    pub direct: ScreenPass,
    pub technique: Box<dyn Technique>,
    pub composite: ScreenPass,
    pub tonemap: ScreenPass,
    pub aov: passes::aov::AovPass,
}

impl Passes {
    #[allow(clippy::too_many_arguments)]
    pub(super) fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        frame_group: &FrameGroup,
        targets: &FrameTargets,
        scene: &GpuScene,
        env: &GpuEnvironment,
        shadows: &ShadowPass,
        pack_half: bool,
        spec: &technique::Spec,
    ) -> Result<Self, RenderError> {
        let (desc, params) = (spec.desc, spec.params_for(frame_group.far_volume()));
        let direct = passes::direct_lighting::new(device, frame_group, targets, scene, shadows);
        let technique = technique::create(
            desc,
            &TechniqueContext {
                device,
                queue,
                frame_group,
                inputs: &targets.near_field_inputs(),
                outputs: &targets.near_field_outputs(),
                env,
                scene: Some(SceneInputs {
                    scene,
                    lights: shadows.light_resources(&scene.lights),
                }),
                pack_half,
            },
            &params,
        )?;
        // A technique that writes only ao (gtao): composite and aov form its env- and
        // indirect-irradiance.
        let ao_scales_far = !desc.writes.contains(&Output::EnvIrradiance);
        let far_rule = desc.far_rule;
        Ok(Passes {
            direct,
            technique,
            composite: passes::composite::new(
                device,
                frame_group,
                targets,
                ao_scales_far,
                far_rule,
            ),
            tonemap: passes::tonemap::new(device, frame_group, targets),
            aov: passes::aov::new(device, frame_group, targets, ao_scales_far, far_rule),
        })
    }
}

/// Validation and out-of-memory error scopes around resource creation: a failure becomes a
/// [`RenderError::Gpu`] instead of an uncaptured error.
pub(super) struct ErrorScopes {
    // Dropped in this order (the reverse of pushing) when a `?` leaves before `pop`.
    validation: wgpu::ErrorScopeGuard,
    oom: wgpu::ErrorScopeGuard,
}

impl ErrorScopes {
    pub(super) fn push(device: &wgpu::Device) -> Self {
        let oom = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let validation = device.push_error_scope(wgpu::ErrorFilter::Validation);
        ErrorScopes { validation, oom }
    }

    pub(super) fn pop(self) -> Result<(), RenderError> {
        if let Some(e) = pollster::block_on(self.validation.pop()) {
            return Err(RenderError::Gpu(e.to_string()));
        }
        if let Some(e) = pollster::block_on(self.oom.pop()) {
            return Err(RenderError::Memory(format!(
                "the adapter ran out of memory making the frame's targets and passes ({e}); \
                 a smaller --size fits"
            )));
        }
        Ok(())
    }
}
