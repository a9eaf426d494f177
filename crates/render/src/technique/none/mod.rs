//! `none`: no occlusion (ao = 1), the unoccluded far field's irradiance the direct pass left in
//! `env-irradiance`, no indirect light.
//! The baseline every other technique is compared with. See none.wgsl.

use crate::RenderError;
use crate::bindings::{PassLayout, kind};
use crate::contract::technique::FarRule;
use crate::contract::technique::{
    Output, Technique, TechniqueContext, TechniqueDesc, TechniqueParams,
};
use crate::passes::{ComputeStep, ScreenPass};
use crate::profiler::GpuProfiler;
use crate::targets::{AO_FORMAT, HDR_FORMAT};
use crate::util;

pub const SHADER: &str = include_str!("none.wgsl");

pub fn source() -> String {
    util::compose(&[
        util::COMMON_WGSL,
        util::ENV_WGSL,
        util::FRAME_BINDINGS_WGSL,
        SHADER,
    ])
}

crate::bind_group! {
    /// Group 1 of `none`: the normal in, the three outputs every technique writes.
    pub struct NoneBindings: COMPUTE {
        /// World normal (rgba16float, xyz unit).
        gb_normal: view = kind::TEXTURE,
        /// `ao` (r32float): 1.
        out_ao: view = kind::write(AO_FORMAT),
        /// `env-irradiance` (rgba16float): on surfaces it keeps what it holds on entry (the far
        /// field's unoccluded irradiance, the sky's SH or the probe volume's); 0 on background.
        out_env_irradiance: view = kind::write(HDR_FORMAT),
        /// `indirect-irradiance` (rgba16float): 0.
        out_indirect_irradiance: view = kind::write(HDR_FORMAT),
    }
}

/// The binding declaration the reflection test checks.
pub fn pass_layout() -> PassLayout {
    PassLayout {
        name: "technique/none",
        source: source(),
        entry_point: "main",
        group1: NoneBindings::SLOTS,
    }
}

pub const DESC: TechniqueDesc = TechniqueDesc {
    family: "none",
    name: "none",
    summary: "no occlusion: ao = 1, the unoccluded far field (sky SH or probe volume), no indirect light",
    create,
    check,
    settings: &[],
    presets: &[],
    denoise: None,
    pass_layouts: || vec![pass_layout()],
    writes: &[
        Output::Ao,
        Output::EnvIrradiance,
        Output::IndirectIrradiance,
    ],
    far_rule: FarRule::Own,
    with_volume: &[],
};

struct NoneTechnique {
    pass: ScreenPass,
    size: (u32, u32),
}

/// `none` has no settings.
fn check(params: &TechniqueParams) -> Result<(), String> {
    crate::contract::technique::reject_unknown_keys("none", params, &[]).map_err(|e| match e {
        RenderError::Setting { msg, .. } => msg,
        e => e.to_string(),
    })
}

fn create(
    ctx: &TechniqueContext,
    params: &TechniqueParams,
) -> Result<Box<dyn Technique>, RenderError> {
    crate::contract::technique::reject_unknown_keys("none", params, &[])?;
    let device = ctx.device;
    let (i, o) = (ctx.inputs, ctx.outputs);
    let layout = NoneBindings::layout(device);
    let module = crate::pipeline_cache::shader_module(device, "none", &source());
    let own = NoneBindings {
        gb_normal: i.normal,
        out_ao: o.ao,
        out_env_irradiance: o.require("none", Output::EnvIrradiance)?,
        out_indirect_irradiance: o.require("none", Output::IndirectIrradiance)?,
    }
    .bind_group(device, &layout);
    Ok(Box::new(NoneTechnique {
        pass: ScreenPass::single(
            ComputeStep::new(
                device,
                "none",
                &module,
                "main",
                ctx.frame_group,
                &layout,
                &[],
            ),
            own,
        ),
        size: i.size,
    }))
}

impl Technique for NoneTechnique {
    fn name(&self) -> &'static str {
        "none"
    }

    fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        profiler: &mut GpuProfiler,
        _frame: crate::contract::technique::FrameInfo,
    ) {
        self.pass.encode(encoder, profiler, self.size, 0);
    }
}
