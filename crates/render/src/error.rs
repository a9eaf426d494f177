//! Errors of the renderer library.

#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    #[error(
        "no GPU adapter found{filter}. Install a Vulkan driver: on Debian/Ubuntu `apt-get install mesa-vulkan-drivers libvulkan1` gives the software rasterizer lavapipe"
    )]
    NoAdapter { filter: String },
    #[error(
        "the only GPU adapter, {adapter}, lacks what nearfield's passes need ({missing}): it runs on Vulkan, Metal or DX12. Install a Vulkan driver: on Debian/Ubuntu `apt-get install mesa-vulkan-drivers libvulkan1` gives the software rasterizer lavapipe"
    )]
    Downlevel { adapter: String, missing: String },
    #[error("cannot create the GPU device on {adapter}: {msg}")]
    Device { adapter: String, msg: String },
    #[error("image size {width}×{height} is not supported: {why}")]
    Size {
        width: u32,
        height: u32,
        why: String,
    },
    #[error("{}", nearfield_scene::one_line(.0))]
    Scene(String),
    #[error(
        "unknown technique '{}' (known: {known})",
        nearfield_scene::one_line(name)
    )]
    UnknownTechnique { name: String, known: String },
    #[error(
        "technique '{}': {}",
        nearfield_scene::one_line(technique),
        nearfield_scene::one_line(msg)
    )]
    Setting { technique: String, msg: String },
    #[error("GPU error: {0}")]
    Gpu(String),
    #[error("the GPU device was lost ({0}); outputs not yet written were not written")]
    Lost(String),
    /// More memory than the adapter has (exit status 2: a smaller size fits).
    #[error("{0}")]
    Memory(String),
}

impl RenderError {
    /// A refused setting of `technique`, for `map_err` over a settings parser's message.
    pub fn setting(technique: &str) -> impl Fn(String) -> RenderError + '_ {
        move |msg| RenderError::Setting {
            technique: technique.into(),
            msg,
        }
    }
}
