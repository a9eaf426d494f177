//! The image the session shows from a renderer, and what the display pass is given.

use nearfield_render::passes::display::{DisplayMode, DisplaySide};
use nearfield_render::{Aov, Renderer};

pub(super) fn display_side(
    s: &(nearfield_render::wgpu::TextureView, DisplayMode, bool),
) -> DisplaySide<'_> {
    DisplaySide {
        view: &s.0,
        mode: s.1,
        coverage: s.2,
    }
}

pub(super) fn wgpu_encoder_label() -> nearfield_render::wgpu::CommandEncoderDescriptor<'static> {
    nearfield_render::wgpu::CommandEncoderDescriptor {
        label: Some("display"),
    }
}

/// The image to show for `name` from one renderer: (view, mode, alpha is coverage). A name the
/// renderer does not have (a technique image of the other side) shows its frame.
pub(super) fn source(
    r: &mut Renderer,
    name: &str,
) -> (nearfield_render::wgpu::TextureView, DisplayMode, bool) {
    use nearfield_render::wgpu::{TextureFormat as F, TextureViewDescriptor, TextureViewDimension};
    match Aov::parse(name) {
        Some(Aov::Final) => (
            r.targets.final_ldr.view.clone(),
            DisplayMode::Encoded,
            false,
        ),
        Some(aov) => {
            r.extract_aov(aov);
            (r.targets.aov.view.clone(), DisplayMode::for_aov(aov), true)
        }
        None => match r.extra_texture(name) {
            Some(t) if matches!(t.format(), F::Rgba16Float | F::Rgba32Float | F::R32Float) => {
                let view = t.create_view(&TextureViewDescriptor {
                    dimension: Some(TextureViewDimension::D2),
                    base_mip_level: 0,
                    mip_level_count: Some(1),
                    base_array_layer: 0,
                    array_layer_count: Some(1),
                    ..Default::default()
                });
                let mode = if t.format() == F::R32Float {
                    DisplayMode::Scalar
                } else {
                    DisplayMode::Colour
                };
                (view, mode, false)
            }
            _ => (
                r.targets.final_ldr.view.clone(),
                DisplayMode::Encoded,
                false,
            ),
        },
    }
}
