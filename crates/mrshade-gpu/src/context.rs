//! Instance, adapter and device. A hardware adapter is preferred; without one, Mesa's
//! lavapipe (a conformant CPU Vulkan driver) runs everything, slowly but correctly.

use anyhow::{Context, Result, bail};

/// What to tell a user who has no adapter at all.
pub const NO_ADAPTER_HELP: &str = "no GPU adapter found: mrshade needs a Vulkan driver. \
On a machine without a GPU install Mesa's software driver lavapipe \
(Debian/Ubuntu: `apt-get install mesa-vulkan-drivers`); on a GPU machine install its Vulkan driver";

/// Features mrshade cannot run without: 64-bit integers and 64-bit atomics in storage
/// buffers, for the compute rasteriser (max) and the caustic splat's fixed-point sums (add)
/// (Vulkan `shaderBufferInt64Atomics`; lavapipe and current desktop GPUs have them).
pub const REQUIRED_FEATURES: wgpu::Features = wgpu::Features::SHADER_INT64
    .union(wgpu::Features::SHADER_INT64_ATOMIC_MIN_MAX)
    .union(wgpu::Features::SHADER_INT64_ATOMIC_ALL_OPS);

/// How to pick the adapter.
#[derive(Clone, Debug, Default)]
pub struct GpuOptions {
    /// Use the first adapter whose name contains this (case-insensitive).
    pub adapter: Option<String>,
}

/// The device every pass records on.
pub struct GpuContext {
    /// The wgpu instance.
    pub instance: wgpu::Instance,
    /// The chosen adapter.
    pub adapter: wgpu::Adapter,
    /// The logical device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    /// Adapter name, backend, type.
    pub info: wgpu::AdapterInfo,
    /// Whether GPU timestamp queries are available (for `bench`).
    pub timestamps: bool,
}

/// Adapter types from most to least preferred.
fn preference(t: wgpu::DeviceType) -> u8 {
    match t {
        wgpu::DeviceType::DiscreteGpu => 0,
        wgpu::DeviceType::IntegratedGpu => 1,
        wgpu::DeviceType::VirtualGpu => 2,
        wgpu::DeviceType::Other => 3,
        wgpu::DeviceType::Cpu => 4,
    }
}

impl GpuContext {
    /// Picks an adapter and opens a device on it.
    pub fn new(options: &GpuOptions) -> Result<Self> {
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
        // Vulkan (and Metal/DX12 elsewhere); `WGPU_BACKEND` overrides.
        desc.backends = wgpu::Backends::from_env().unwrap_or(wgpu::Backends::PRIMARY);
        desc.flags = wgpu::InstanceFlags::from_build_config().with_env();
        let instance = wgpu::Instance::new(desc);
        let mut adapters = pollster::block_on(instance.enumerate_adapters(wgpu::Backends::all()));
        if adapters.is_empty() {
            bail!("{NO_ADAPTER_HELP}");
        }
        if let Some(wanted) = &options.adapter {
            let w = wanted.to_lowercase();
            adapters.retain(|a| a.get_info().name.to_lowercase().contains(&w));
            if adapters.is_empty() {
                bail!("no adapter's name contains '{wanted}' (see `mrshade adapters`)");
            }
        }
        let (capable, lacking): (Vec<_>, Vec<_>) =
            adapters.into_iter().partition(|a| a.features().contains(REQUIRED_FEATURES));
        if capable.is_empty() {
            let names: Vec<String> = lacking.iter().map(|a| a.get_info().name).collect();
            bail!(
                "no adapter supports 64-bit storage-buffer atomics (Vulkan shaderBufferInt64Atomics), which mrshade \
                 needs; adapters found: {}. Mesa's lavapipe (`apt-get install mesa-vulkan-drivers`) has them",
                names.join(", ")
            );
        }
        let mut adapters = capable;
        adapters.sort_by_key(|a| preference(a.get_info().device_type));
        let adapter = adapters.swap_remove(0);
        let info = adapter.get_info();

        let timestamps = adapter.features().contains(wgpu::Features::TIMESTAMP_QUERY);
        let mut required_features = REQUIRED_FEATURES;
        if timestamps {
            required_features |= wgpu::Features::TIMESTAMP_QUERY;
        }
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("mrshade/device"),
            required_features,
            required_limits: adapter.limits(),
            ..Default::default()
        }))
        .with_context(|| format!("cannot open a device on adapter {}", info.name))?;
        Ok(Self { instance, adapter, device, queue, info, timestamps })
    }

    /// "name (backend, type)" for logs and reports.
    pub fn describe(&self) -> String {
        format!("{} ({:?}, {:?})", self.info.name, self.info.backend, self.info.device_type)
    }

    /// Runs `f` and turns any wgpu validation or out-of-memory error it caused into an
    /// `Err` instead of the default panic.
    pub fn checked<T>(&self, what: &str, f: impl FnOnce() -> Result<T>) -> Result<T> {
        let oom = self.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let validation = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let out = f();
        let validation = pollster::block_on(validation.pop());
        let oom = pollster::block_on(oom.pop());
        if let Some(e) = oom {
            bail!("{what}: the GPU ran out of memory: {e}");
        }
        if let Some(e) = validation {
            bail!("{what}: GPU validation error (a bug in mrshade, please report it): {e}");
        }
        out
    }

    /// Blocks until the GPU has finished the submission `index` (and all before it).
    pub fn wait_for(&self, index: wgpu::SubmissionIndex) -> Result<()> {
        self.device
            .poll(wgpu::PollType::Wait { submission_index: Some(index), timeout: None })
            .map(|_| ())
            .map_err(|e| anyhow::anyhow!("waiting for the GPU failed: {e}"))
    }

    /// Blocks until the GPU has finished all submitted work.
    pub fn wait_idle(&self) -> Result<()> {
        self.device
            .poll(wgpu::PollType::Wait { submission_index: None, timeout: None })
            .map(|_| ())
            .map_err(|e| anyhow::anyhow!("waiting for the GPU failed: {e}"))
    }
}

/// Names of every adapter this machine offers, for `mrshade adapters`.
pub fn list_adapters() -> Vec<wgpu::AdapterInfo> {
    let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
    desc.backends = wgpu::Backends::from_env().unwrap_or(wgpu::Backends::PRIMARY);
    let instance = wgpu::Instance::new(desc);
    pollster::block_on(instance.enumerate_adapters(wgpu::Backends::all())).iter().map(|a| a.get_info()).collect()
}
