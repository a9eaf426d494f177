//! `scratch`: the test build's scratch family (feature `scratch`; tests/scratch.rs). A constant
//! occlusion, ao = 1 − `occlusion` / `taps`, with one uniform and one count declared once. It
//! is this folder and the registry's lines, and nothing else: the test checks that it reaches
//! every consumer (the registry, `--set`, the book's tables, the pass reflection, the renderer,
//! in-place updates and rebuilds) and counts the files it touched.

use crate::RenderError;
use crate::bindings::{PassLayout, kind};
use crate::contract::technique::{
    FarRule, FrameInfo, Output, Technique, TechniqueContext, TechniqueDesc, TechniqueParams,
};
use crate::passes::{ComputeStep, ScreenPass};
use crate::profiler::GpuProfiler;
use crate::settings::Declared;
use crate::targets::{AO_FORMAT, HDR_FORMAT};
use crate::util;
use wgpu::util::DeviceExt;

crate::declare_settings! {
    /// Settings of `scratch`.
    pub struct Settings {
        occlusion: f32 = "0.25", number(0, 1), uniform, "", "occlusion on every surface";
        taps: u32 = "1", integer(1, 4), count, "", "divides the occlusion (a count, specialised into the kernel)";
    }
}

crate::gpu_struct! {
    /// `ScratchParams` in scratch.wgsl.
    pub struct ScratchParams {
        pub occlusion: f32,
        pub _pad0: f32,
        pub _pad1: f32,
        pub _pad2: f32,
    }
}

pub const SHADER: &str = include_str!("scratch.wgsl");

pub fn source() -> String {
    util::compose(&[
        util::COMMON_WGSL,
        util::ENV_WGSL,
        util::FRAME_BINDINGS_WGSL,
        SHADER,
    ])
}

crate::bind_group! {
    /// Group 1 of `scratch`.
    pub struct ScratchBindings: COMPUTE {
        /// `ScratchParams`.
        params: buffer = kind::UNIFORM,
        /// World normal (rgba16float, xyz unit).
        gb_normal: view = kind::TEXTURE,
        /// `ao` (r32float).
        out_ao: view = kind::write(AO_FORMAT),
        /// `indirect-irradiance` (rgba16float): 0.
        out_indirect_irradiance: view = kind::write(HDR_FORMAT),
    }
}

pub const DESC: TechniqueDesc = TechniqueDesc {
    family: "scratch",
    name: "scratch",
    summary: "the test build's scratch family: a constant occlusion",
    create,
    check: |tp| Settings::from_params(tp).map(|_| ()),
    settings: <Settings as Declared>::TABLE,
    presets: &[],
    denoise: None,
    pass_layouts: || {
        vec![PassLayout {
            name: "technique/scratch",
            source: source(),
            entry_point: "main",
            group1: ScratchBindings::SLOTS,
        }]
    },
    writes: &[Output::Ao, Output::IndirectIrradiance],
    far_rule: FarRule::Own,
    with_volume: &[],
};

impl Settings {
    fn from_params(params: &TechniqueParams) -> Result<Self, String> {
        let mut s = Settings::default();
        crate::settings::apply(&mut s, params, &[])?;
        Ok(s)
    }

    fn params(&self) -> ScratchParams {
        ScratchParams {
            occlusion: self.occlusion,
            _pad0: 0.0,
            _pad1: 0.0,
            _pad2: 0.0,
        }
    }
}

struct Scratch {
    pass: ScreenPass,
    params: wgpu::Buffer,
    settings: Settings,
    size: (u32, u32),
}

fn create(ctx: &TechniqueContext, tp: &TechniqueParams) -> Result<Box<dyn Technique>, RenderError> {
    let settings = Settings::from_params(tp).map_err(RenderError::setting("scratch"))?;
    let (device, i, o) = (ctx.device, ctx.inputs, ctx.outputs);
    let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("scratch params"),
        contents: bytemuck::bytes_of(&settings.params()),
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
    });
    let layout = ScratchBindings::layout(device);
    let group = ScratchBindings {
        params: &params,
        gb_normal: i.normal,
        out_ao: o.ao,
        out_indirect_irradiance: o.require("scratch", Output::IndirectIrradiance)?,
    }
    .bind_group(device, &layout);
    let source = source();
    let kernel = ("scratch", source.as_str(), "main");
    let step = ComputeStep::counted(
        device,
        ctx.frame_group,
        kernel,
        &layout,
        &settings.counts(),
        &[],
    );
    Ok(Box::new(Scratch {
        pass: ScreenPass::single(step, group),
        params,
        settings,
        size: i.size,
    }))
}

impl Technique for Scratch {
    fn name(&self) -> &'static str {
        "scratch"
    }

    fn encode(&self, encoder: &mut wgpu::CommandEncoder, profiler: &mut GpuProfiler, _: FrameInfo) {
        self.pass.encode(encoder, profiler, self.size, 0);
    }

    fn update(&mut self, queue: &wgpu::Queue, tp: &TechniqueParams) -> Result<bool, RenderError> {
        let settings = Settings::from_params(tp).map_err(RenderError::setting("scratch"))?;
        if !settings.same_build(&self.settings) {
            return Ok(false);
        }
        queue.write_buffer(&self.params, 0, bytemuck::bytes_of(&settings.params()));
        self.settings = settings;
        Ok(true)
    }
}
