//! The virtual point lights of ssdo-vpl (the environment as shadow-mapped directional lights)
//! and instant-radiosity (cosine emitters from reflective shadow maps), each with a shadow map.

use super::Settings;
use crate::contract::io::SceneInputs;
use crate::passes::shadow::{LightResources, ShadowPass};
use crate::technique::TechniqueContext;
use bytemuck::Zeroable;
use wgpu::util::DeviceExt;

/// The virtual point lights of ssdo-vpl or instant-radiosity: their table (`GpuLight`s with
/// their shadow layers) and shadow maps.
pub struct Vpls {
    table: wgpu::Buffer,
    pub count: u32,
    pub shadows: ShadowPass,
}

impl Vpls {
    /// ssdo-vpl: the environment as directional lights.
    pub fn environment(ctx: &TechniqueContext, scene: SceneInputs, settings: &Settings) -> Self {
        let env = ctx.env;
        let lights = crate::vpl::environment_lights(
            env.source(),
            env.rotation,
            env.intensity,
            settings.vpls,
        );
        Self::new(ctx, scene, settings, &lights, "environment lights")
    }

    /// instant-radiosity: cosine emitters drawn from the reflective shadow maps of the scene's
    /// lights, as spot lights about their normals (shadow maps over 160°; shadow_visibility
    /// counts receivers beyond 80° from the normal, where cos θ < 0.18, as unshadowed), with
    /// colour Φ/π (bounce.wgsl `radiosity_bounce`).
    pub fn radiosity(ctx: &TechniqueContext, scene: SceneInputs, settings: &Settings) -> Self {
        let texels = crate::passes::rsm::render(
            ctx.device,
            ctx.queue,
            scene.scene,
            &scene.scene.scene_lights,
            settings.rsm,
        );
        // Lift each light off its surface by a thousandth of the scene's radius.
        let lift = 1e-3 * scene.scene.bounds.radius();
        let lights: Vec<nearfield_scene::Light> =
            crate::vpl::radiosity_lights(&texels, settings.vpls)
                .iter()
                .map(|v| nearfield_scene::Light {
                    kind: nearfield_scene::LightKind::Spot {
                        position: v.position + v.normal * lift,
                        direction: v.normal,
                        inner_cone: std::f32::consts::FRAC_PI_2,
                        outer_cone: std::f32::consts::FRAC_PI_2,
                    },
                    color: v.flux / std::f32::consts::PI,
                    intensity: 1.0,
                    range: None,
                })
                .collect();
        log::info!(
            "instant-radiosity: {} virtual point lights from {} lit reflective-shadow-map texels",
            lights.len(),
            texels.len()
        );
        Self::new(ctx, scene, settings, &lights, "radiosity lights")
    }

    /// The light bindings (lights.wgsl) with the VPLs as the light table.
    pub fn light_resources(&self) -> LightResources<'_> {
        self.shadows.light_resources(&self.table)
    }

    fn new(
        ctx: &TechniqueContext,
        scene: SceneInputs,
        settings: &Settings,
        lights: &[nearfield_scene::Light],
        label: &'static str,
    ) -> Self {
        let kinds: Vec<_> = lights.iter().map(|l| l.kind).collect();
        let shadows = ShadowPass::for_lights(
            ctx.device,
            scene.scene,
            &kinds,
            crate::passes::shadow::ShadowSettings {
                size: settings.vpl_map,
                max_layers: crate::vpl::MAX_VPLS,
                ..Default::default()
            },
            "vpl shadows",
        );
        let table: Vec<crate::gpu_scene::GpuLight> = lights
            .iter()
            .zip(&shadows.light_layers)
            .map(|(l, &(layer, texel))| crate::gpu_scene::gpu_light(l, layer, texel))
            .collect();
        let table = if table.is_empty() {
            vec![crate::gpu_scene::GpuLight::zeroed()]
        } else {
            table
        };
        Vpls {
            table: ctx
                .device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(label),
                    contents: bytemuck::cast_slice(&table),
                    usage: wgpu::BufferUsages::STORAGE,
                }),
            count: lights.len() as u32,
            shadows,
        }
    }
}
