//! Reuse of compiled GPU objects across rebuilds: shader modules by source, bind group layouts
//! by entries, compute pipelines by (module, entry point, layouts, override constants).
//!
//! A technique is rebuilt whenever a count changes (the viewer's sliders, `compare` over several
//! settings of one technique, a resize); its shaders rarely do. Compiling a pipeline is the
//! expensive part on every driver (on lavapipe, LLVM runs per pipeline), so identical requests
//! return the object made the first time. Keys are exact: the WGSL source text (hashed, then
//! compared), the layout entries, the constants' bits. Each device holds at most [`CAPACITY`]
//! pipelines (least recently used dropped first), and [`forget`] drops a device's entries.
//! Only devices of a [`crate::GpuContext`] are cached (it [`register`]s them). wgpu compares
//! devices by their id within their instance: an engine that makes its own device while a
//! `GpuContext` of another instance is alive in the same process should drop the context
//! first, or its device may be taken for the context's.

use std::collections::HashMap;
use std::hash::{Hash, Hasher};
use std::sync::{LazyLock, Mutex};

/// Pipelines kept per device.
pub const CAPACITY: usize = 256;

#[derive(Clone, PartialEq, Eq, Hash)]
struct PipelineKey {
    module: wgpu::ShaderModule,
    entry: String,
    groups: [Option<wgpu::BindGroupLayout>; 2],
    constants: Vec<(String, u64)>,
}

/// What makes a raster pipeline (`util::RasterPipeline`), the label aside.
#[derive(Clone, PartialEq, Eq, Hash)]
pub struct RasterKey {
    pub module: wgpu::ShaderModule,
    pub vertex: String,
    pub fragment: String,
    pub groups: [Option<wgpu::BindGroupLayout>; 2],
    pub color_formats: Vec<wgpu::TextureFormat>,
    pub cull: Option<wgpu::Face>,
    /// Depth bias: constant, slope scale and clamp (bits).
    pub depth_bias: (i32, u32, u32),
}

#[derive(Default)]
struct DeviceCache {
    raster: HashMap<RasterKey, (wgpu::RenderPipeline, u64)>,
    modules: HashMap<u64, Vec<(String, wgpu::ShaderModule)>>,
    layouts: HashMap<Vec<wgpu::BindGroupLayoutEntry>, wgpu::BindGroupLayout>,
    pipelines: HashMap<PipelineKey, (wgpu::ComputePipeline, u64)>,
    clock: u64,
    hits: u64,
    misses: u64,
}

/// Per device: how many live [`crate::GpuContext`]s have a device that compares equal to it,
/// and its cache. wgpu compares devices by their id within an instance, so devices of two
/// instances alive at once may compare equal: such a device is not cached at all (nor is a
/// device no context registered, such as an engine's own).
#[derive(Default)]
struct Entry {
    contexts: usize,
    cache: DeviceCache,
}

static CACHE: LazyLock<Mutex<HashMap<wgpu::Device, Entry>>> =
    LazyLock::new(|| Mutex::new(HashMap::new()));

/// Runs `f` on `device`'s cache, or not at all (None) when the device is not cached.
fn with<R>(device: &wgpu::Device, f: impl FnOnce(&mut DeviceCache) -> R) -> Option<R> {
    let mut all = CACHE.lock().unwrap_or_else(|e| e.into_inner());
    match all.get_mut(device) {
        Some(e) if e.contexts == 1 => Some(f(&mut e.cache)),
        _ => None,
    }
}

/// Registers a device made by a [`crate::GpuContext`] (which calls [`forget`] when dropped).
pub fn register(device: &wgpu::Device) {
    let mut all = CACHE.lock().unwrap_or_else(|e| e.into_inner());
    let e = all.entry(device.clone()).or_default();
    e.contexts += 1;
    if e.contexts > 1 {
        // Another instance's device with the same id: what is cached may be its objects.
        e.cache = DeviceCache::default();
    }
}

/// The runtime checks nearfield's kernels are compiled with: all of wgpu's, except the loop
/// bounds (see [`shader_module`]).
pub fn kernel_runtime_checks() -> wgpu::ShaderRuntimeChecks {
    let mut checks = wgpu::ShaderRuntimeChecks::checked();
    checks.force_loop_bounding = false;
    checks
}

/// The shader module of `source` (one of this crate's kernels), compiled once per device.
pub(crate) fn shader_module(
    device: &wgpu::Device,
    label: &str,
    source: &str,
) -> wgpu::ShaderModule {
    let mut h = std::collections::hash_map::DefaultHasher::new();
    source.hash(&mut h);
    let key = h.finish();
    if let Some(m) = with(device, |c| {
        c.modules
            .get(&key)
            .and_then(|v| v.iter().find(|(s, _)| s == source).map(|(_, m)| m.clone()))
    })
    .flatten()
    {
        return m;
    }
    let desc = wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    };
    // wgpu's checks stay on but one: the loop bound it adds to every loop (a counter the
    // driver must carry) keeps NVIDIA's Vulkan compiler from unrolling the loops over a
    // kernel's local arrays (SH coefficients, a filter's sums), which then live in local
    // memory: on an H200 at 1920×1080 hbil's search took 9.9 ms with it and 0.87 ms without,
    // s3ho's SH filter 17.6 against 0.39 (book: architecture.md, "Loop bounds").
    let checks = kernel_runtime_checks();
    // SAFETY: `force_loop_bounding` off requires that no loop of the module runs forever. Every
    // loop of nearfield's kernels has a trip bound: `for` loops count an integer up to a
    // bound, and the one `loop` (vbgi/bitmask.wgsl's mask_weight) is a `for` over at most 16
    // runs of bits; tests/portable.rs checks every WGSL file for that form. `source` is one of this
    // crate's kernels (the function is not public), never a user's.
    let module = unsafe { device.create_shader_module_trusted(desc, checks) };
    with(device, |c| {
        c.modules
            .entry(key)
            .or_default()
            .push((source.to_string(), module.clone()))
    });
    module
}

/// The bind group layout of `entries`, made once per device.
pub fn bind_group_layout(
    device: &wgpu::Device,
    label: &str,
    entries: &[wgpu::BindGroupLayoutEntry],
) -> wgpu::BindGroupLayout {
    if let Some(l) = with(device, |c| c.layouts.get(entries).cloned()).flatten() {
        return l;
    }
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some(label),
        entries,
    });
    with(device, |c| {
        c.layouts.insert(entries.to_vec(), layout.clone())
    });
    layout
}

/// The compute pipeline of `module`'s `entry_point` over `groups`, specialised by `constants`:
/// compiled once per device while it stays among the [`CAPACITY`] most recently used.
pub fn compute_pipeline(
    device: &wgpu::Device,
    label: &str,
    module: &wgpu::ShaderModule,
    entry_point: &str,
    groups: [Option<&wgpu::BindGroupLayout>; 2],
    constants: &[(&str, f64)],
) -> wgpu::ComputePipeline {
    let key = PipelineKey {
        module: module.clone(),
        entry: entry_point.to_string(),
        groups: groups.map(|g| g.cloned()),
        constants: constants
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_bits()))
            .collect(),
    };
    cached(
        device,
        |c| &mut c.pipelines,
        key,
        || {
            let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(label),
                bind_group_layouts: &groups,
                immediate_size: 0,
            });
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(label),
                layout: Some(&pipeline_layout),
                module,
                entry_point: Some(entry_point),
                compilation_options: wgpu::PipelineCompilationOptions {
                    constants,
                    ..Default::default()
                },
                cache: None,
            })
        },
    )
}

/// The raster pipeline of `key`, made by `make` the first time (raster pipelines are compiled
/// per draw state by some drivers, and memory of pipelines rebuilt over and over is not always
/// returned: lavapipe keeps some per pipeline it has drawn with).
pub fn raster_pipeline(
    device: &wgpu::Device,
    key: RasterKey,
    make: impl FnOnce() -> wgpu::RenderPipeline,
) -> wgpu::RenderPipeline {
    cached(device, |c| &mut c.raster, key, make)
}

/// The value of `key` in the map `map` picks from `device`'s cache, made by `make` on a miss
/// (the least recently used entry dropped when the map holds [`CAPACITY`]); made every time for
/// a device that is not cached.
fn cached<K: Clone + Eq + Hash, V: Clone>(
    device: &wgpu::Device,
    map: impl Fn(&mut DeviceCache) -> &mut HashMap<K, (V, u64)>,
    key: K,
    make: impl FnOnce() -> V,
) -> V {
    let hit = with(device, |c| {
        c.clock += 1;
        let now = c.clock;
        let found = map(c).get_mut(&key).map(|(v, used)| {
            *used = now;
            v.clone()
        });
        if found.is_some() {
            c.hits += 1;
        } else {
            c.misses += 1;
        }
        found
    });
    if let Some(v) = hit.flatten() {
        return v;
    }
    let value = make();
    with(device, |c| {
        let now = c.clock;
        let m = map(c);
        if m.len() >= CAPACITY
            && let Some(oldest) = m
                .iter()
                .min_by_key(|(_, (_, used))| *used)
                .map(|(k, _)| k.clone())
        {
            m.remove(&oldest);
        }
        m.insert(key, (value.clone(), now));
    });
    value
}

/// (hits, misses, pipelines held) of `device`'s pipeline cache.
pub fn stats(device: &wgpu::Device) -> (u64, u64, usize) {
    with(device, |c| {
        (c.hits, c.misses, c.pipelines.len() + c.raster.len())
    })
    .unwrap_or_default()
}

/// Ends a registration of `device`: its cache goes with the last one.
pub fn forget(device: &wgpu::Device) {
    let mut all = CACHE.lock().unwrap_or_else(|e| e.into_inner());
    if let Some(e) = all.get_mut(device) {
        e.contexts = e.contexts.saturating_sub(1);
        e.cache = DeviceCache::default();
        if e.contexts == 0 {
            all.remove(device);
        }
    }
}

/// A compute pipeline outside the frame (environment prefiltering, the viewer's display): group
/// 0 is empty, group 1 is `layout`.
pub fn standalone_pipeline(
    device: &wgpu::Device,
    label: &str,
    module: &wgpu::ShaderModule,
    entry_point: &str,
    layout: &wgpu::BindGroupLayout,
) -> wgpu::ComputePipeline {
    compute_pipeline(
        device,
        label,
        module,
        entry_point,
        [None, Some(layout)],
        &[],
    )
}
