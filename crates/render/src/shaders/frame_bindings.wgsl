// frame_bindings.wgsl — nearfield's own glue for group 0 (crate::bindings::FrameBindings, the
// order of its fields): the only shared file that declares bindings. The libraries (common.wgsl,
// env.wgsl, far.wgsl, and each technique's own) take these resources as parameters; an entry
// file of nearfield passes them on from here. Another engine declares its own bindings instead
// and passes those (docs/src/architecture.md, "Lifting a pass into another engine").

// The narrow view every near-field kernel reads (common.wgsl's `View`).
@group(0) @binding(0) var<uniform> view: View;
// The environment (env.wgsl): radiance with box-filtered mips, GGX-prefiltered radiance, the
// sampler (repeat u, clamp v, linear), its uniform, the pre-convolved diffuse map.
@group(0) @binding(1) var env_radiance: texture_2d<f32>;
@group(0) @binding(2) var env_specular: texture_2d<f32>;
@group(0) @binding(3) var env_sampler: sampler;
@group(0) @binding(4) var<uniform> env: EnvUniforms;
@group(0) @binding(5) var env_irradiance_map: texture_2d<f32>;
// The far field (far.wgsl): probes, visibility moments, irradiance atlas.
@group(0) @binding(6) var far_probes: texture_2d<f32>;
@group(0) @binding(7) var far_visibility: texture_2d<f32>;
@group(0) @binding(8) var far_irradiance_atlas: texture_2d<f32>;
// The rest of nearfield's frame (common.wgsl's `Frame`): exposure, tone mapping, light count,
// the AOV shown. A read-only storage buffer: a third uniform buffer in group 0 crashes lavapipe
// (Mesa 22.3) in every technique.
@group(0) @binding(9) var<storage, read> frame: Frame;
