//! `none`: no occlusion (ao = 1), unoccluded SH environment irradiance, no indirect light.
//! The baseline every other technique is compared with. See none.wgsl.

use super::{Technique, TechniqueContext, TechniqueDesc, TechniqueParams};
use crate::RenderError;
use crate::gpu_env::GpuEnvironment;
use crate::passes::ScreenPass;
use crate::profiler::GpuProfiler;
use crate::targets::{AO_FORMAT, HDR_FORMAT};
use crate::util;
use wgpu::BindingResource as R;

pub const SHADER: &str = include_str!("none.wgsl");

pub fn source() -> String {
    util::compose(&[util::COMMON_WGSL, util::ENV_WGSL, SHADER])
}

pub const DESC: TechniqueDesc = TechniqueDesc {
    name: "none",
    summary: "no occlusion: ao = 1, unoccluded SH environment irradiance, no indirect light",
    create,
    settings: &[],
    presets: &[],
};

struct NoneTechnique {
    pass: ScreenPass,
    size: (u32, u32),
}

fn create(
    ctx: &TechniqueContext,
    params: &TechniqueParams,
) -> Result<Box<dyn Technique>, RenderError> {
    super::reject_unknown_keys("none", params, &[])?;
    let c = wgpu::ShaderStages::COMPUTE;
    let mut entries = vec![util::uniform(0, c)];
    entries.extend(GpuEnvironment::layout_entries());
    entries.extend([
        util::texture(8, c, true),
        util::storage_texture(9, AO_FORMAT),
        util::storage_texture(10, HDR_FORMAT),
        util::storage_texture(11, HDR_FORMAT),
    ]);
    let layout = ctx
        .device
        .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("none"),
            entries: &entries,
        });
    let t = ctx.targets;
    let mut r = vec![(0, ctx.frame.as_entire_binding())];
    r.extend(ctx.env.bindings());
    r.extend([
        (8, R::TextureView(&t.normal.view)),
        (9, R::TextureView(&t.ao.view)),
        (10, R::TextureView(&t.env_irradiance.view)),
        (11, R::TextureView(&t.indirect_irradiance.view)),
    ]);
    Ok(Box::new(NoneTechnique {
        pass: ScreenPass {
            label: "none",
            pipeline: util::compute_pipeline(ctx.device, "none", &source(), "main", &layout),
            bind_groups: vec![util::bind_group(ctx.device, "none", &layout, &r)],
        },
        size: t.size,
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
        _frame: super::FrameInfo,
    ) {
        self.pass.encode(encoder, profiler, self.size, 0);
    }
}
