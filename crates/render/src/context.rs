//! The GPU device: adapter selection and device creation (headless, or for a window's surface).

use crate::RenderError;

/// An adapter, device and queue.
pub struct GpuContext {
    pub instance: wgpu::Instance,
    pub adapter: wgpu::Adapter,
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    /// Whether pass timestamps are available (`wgpu::Features::TIMESTAMP_QUERY`).
    pub timestamps: bool,
    /// Whether shaders may use `pack2x16float`/`unpack2x16float` (`DownlevelFlags::SHADER_F16_IN_F32`;
    /// on Mesa's Vulkan drivers this needs `Features::SHADER_F16`, requested when offered).
    pub pack_half: bool,
    /// Why the device was lost, once it is ([`Self::lost`]).
    lost: LostFlag,
}

/// Set by the device-lost callback; shared with every [`crate::Renderer`] on the device.
pub type LostFlag = std::sync::Arc<std::sync::Mutex<Option<String>>>;

/// Human-readable adapter description: "NAME (Backend, DeviceType)".
pub fn describe(info: &wgpu::AdapterInfo) -> String {
    format!("{} ({:?}, {:?})", info.name, info.backend, info.device_type)
}

impl GpuContext {
    /// Opens a device. With `adapter_filter`, takes the first adapter whose name contains it
    /// (case-insensitive); otherwise prefers discrete, then integrated, then virtual GPUs, and
    /// falls back to a software adapter (lavapipe, llvmpipe). `WGPU_BACKEND` restricts the
    /// backends searched. Validation layers are off unless `WGPU_VALIDATION=1`.
    pub fn new(adapter_filter: Option<&str>) -> Result<Self, RenderError> {
        Self::with_instance(Self::instance(None), adapter_filter, None)
    }

    /// Whether [`Self::new`] would find an adapter it can run on, without opening a device: what
    /// a command checks before it loads or bakes anything.
    pub fn check_adapter(adapter_filter: Option<&str>) -> Result<(), RenderError> {
        choose_adapter(&Self::instance(None), adapter_filter, None).map(|_| ())
    }

    /// The instance [`Self::new`] uses; with a display handle when windows will be shown on it.
    pub fn instance(display: Option<Box<dyn wgpu::wgt::WgpuHasDisplayHandle>>) -> wgpu::Instance {
        let mut desc = match display {
            Some(d) => wgpu::InstanceDescriptor::new_with_display_handle(d),
            None => wgpu::InstanceDescriptor::new_without_display_handle(),
        };
        desc.backends = desc_backends();
        desc.flags = wgpu::InstanceFlags::empty().with_env();
        wgpu::Instance::new(desc)
    }

    /// [`Self::new`] on a given instance; with `surface`, only adapters that can present to it
    /// are considered.
    pub fn with_instance(
        instance: wgpu::Instance,
        adapter_filter: Option<&str>,
        surface: Option<&wgpu::Surface>,
    ) -> Result<Self, RenderError> {
        let adapter = choose_adapter(&instance, adapter_filter, surface)?;
        let info = adapter.get_info();
        let timestamps = adapter.features().contains(wgpu::Features::TIMESTAMP_QUERY);
        if !timestamps {
            log::warn!(
                "{}: no timestamp queries; per-pass timings are unavailable",
                describe(&info)
            );
        }
        let mut features = wgpu::Features::empty();
        if timestamps {
            features |= wgpu::Features::TIMESTAMP_QUERY;
        }
        if adapter.features().contains(wgpu::Features::SHADER_F16) {
            features |= wgpu::Features::SHADER_F16;
        }
        let pack_half = adapter
            .get_downlevel_capabilities()
            .flags
            .contains(wgpu::DownlevelFlags::SHADER_F16_IN_F32);
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("nearfield"),
            required_features: features,
            required_limits: adapter.limits(),
            ..Default::default()
        }))
        .map_err(|e| RenderError::Device {
            adapter: describe(&info),
            msg: e.to_string(),
        })?;
        let lost: LostFlag = Default::default();
        let on_lost = lost.clone();
        device.set_device_lost_callback(move |reason, msg| {
            let why = if msg.is_empty() {
                format!("{reason:?}")
            } else {
                format!("{reason:?}: {msg}")
            };
            *on_lost.lock().unwrap_or_else(|e| e.into_inner()) = Some(why);
        });
        // Errors nobody captured are bugs (a panic, as wgpu's default), except once the device
        // is lost: then every call fails, and the commands report the loss instead.
        let after_loss = lost.clone();
        device.on_uncaptured_error(std::sync::Arc::new(move |e: wgpu::Error| {
            let lost = after_loss
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .is_some();
            // A lost device makes objects invalid without an error of its own; using them
            // reports an invalid resource, sometimes before the loss callback has run.
            let cascade = format!("{e:?}").contains("InvalidResource");
            if lost || cascade || matches!(e, wgpu::Error::OutOfMemory { .. }) {
                log::debug!("after the device was lost: {e}");
            } else {
                panic!("wgpu error: {e}");
            }
        }));
        crate::pipeline_cache::register(&device);
        Ok(GpuContext {
            instance,
            adapter,
            device,
            queue,
            timestamps,
            pack_half,
            lost,
        })
    }

    /// Why the device was lost, if it was (a driver reset, a GPU removed, `destroy`). After a
    /// loss every frame renders nothing and every read gives zeros: check this before writing
    /// what was read.
    pub fn lost(&self) -> Option<String> {
        self.lost.lock().unwrap_or_else(|e| e.into_inner()).clone()
    }

    /// The flag [`Self::lost`] reads, for objects that outlive a borrow of the context.
    pub fn lost_flag(&self) -> LostFlag {
        self.lost.clone()
    }

    pub fn adapter_info(&self) -> wgpu::AdapterInfo {
        self.adapter.get_info()
    }

    /// Waits until all submitted work has finished.
    pub fn wait(&self) {
        let _ = self.device.poll(wgpu::PollType::wait_indefinitely());
    }
}

impl Drop for GpuContext {
    /// The device's cached pipelines go with it.
    fn drop(&mut self) {
        crate::pipeline_cache::forget(&self.device);
    }
}

/// The adapter [`GpuContext::with_instance`] opens: see [`GpuContext::new`] for the order; an
/// adapter without WebGPU's full capabilities (GL) is refused with what it lacks.
fn choose_adapter(
    instance: &wgpu::Instance,
    adapter_filter: Option<&str>,
    surface: Option<&wgpu::Surface>,
) -> Result<wgpu::Adapter, RenderError> {
    let adapters = pollster::block_on(instance.enumerate_adapters(desc_backends()));
    let rank = |a: &wgpu::Adapter| match a.get_info().device_type {
        wgpu::DeviceType::DiscreteGpu => 0,
        wgpu::DeviceType::IntegratedGpu => 1,
        wgpu::DeviceType::VirtualGpu => 2,
        wgpu::DeviceType::Other => 3,
        wgpu::DeviceType::Cpu => 4,
    };
    // Vulkan first among equals: it is the backend CI and the timings use.
    let backend_rank = |a: &wgpu::Adapter| match a.get_info().backend {
        wgpu::Backend::Vulkan => 0,
        wgpu::Backend::Metal | wgpu::Backend::Dx12 => 1,
        _ => 2,
    };
    let mut candidates: Vec<wgpu::Adapter> = adapters
        .into_iter()
        .filter(|a| match adapter_filter {
            Some(f) => a.get_info().name.to_lowercase().contains(&f.to_lowercase()),
            None => true,
        })
        .filter(|a| surface.is_none_or(|s| a.is_surface_supported(s)))
        .collect();
    candidates.sort_by_key(|a| (rank(a), backend_rank(a)));
    // The passes need WebGPU's full capabilities (render targets of every format they
    // write, depth and array views as declared): GL and other downlevel adapters lack some,
    // so they are refused with what they lack, before anything is made on them.
    let compliant = |a: &wgpu::Adapter| a.get_downlevel_capabilities().is_webgpu_compliant();
    if let Some(best) = candidates.first()
        && !candidates.iter().any(compliant)
    {
        let caps = best.get_downlevel_capabilities();
        let missing = wgpu::DownlevelFlags::compliant() - caps.flags;
        let mut names: Vec<&str> = missing.iter_names().map(|(n, _)| n).collect();
        if names.is_empty() {
            names.push("the full shader model and limits");
        }
        return Err(RenderError::Downlevel {
            adapter: describe(&best.get_info()),
            missing: names.join(", "),
        });
    }
    candidates
        .into_iter()
        .find(compliant)
        .ok_or_else(|| RenderError::NoAdapter {
            filter: adapter_filter
                .map(|f| format!(" whose name contains '{f}'"))
                .unwrap_or_default(),
        })
}

fn desc_backends() -> wgpu::Backends {
    wgpu::Backends::from_env().unwrap_or(wgpu::Backends::all())
}
