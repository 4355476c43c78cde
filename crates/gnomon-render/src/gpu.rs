use crate::{InvalidInput, RenderError};

/// A GPU device and its queue: opened by gnomon ([`Gpu::new`], headless) or handed over by
/// the program that owns them ([`Gpu::from_device`]).
#[derive(Debug, Clone)]
pub struct Gpu {
    /// The device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    /// What the adapter is (name, backend, device type).
    pub adapter_info: wgpu::AdapterInfo,
}

/// The optional features gnomon uses where the adapter has them: a 32-bit float depth with
/// stencil for the shadow volumes (else Depth24PlusStencil8) and GPU timestamps (else wall
/// clock).
pub const OPTIONAL_FEATURES: wgpu::Features =
    wgpu::Features::DEPTH32FLOAT_STENCIL8.union(wgpu::Features::TIMESTAMP_QUERY);

impl Gpu {
    /// Opens the first adapter wgpu finds (backends and adapter selectable with the usual
    /// `WGPU_*` environment variables, e.g. `WGPU_BACKEND=gl`), with the adapter's largest
    /// texture size and the [`OPTIONAL_FEATURES`] it has.
    ///
    /// Open one per process and clone it (a `Gpu` is a handle): with NVIDIA's Linux Vulkan
    /// driver (580, measured on an H200), dropping a device while another thread's device
    /// lives on crashed the process (the driver's threads ran into code it had unloaded;
    /// gfx-rs/wgpu#8365). gnomon's own tests share one device for that reason.
    pub fn new() -> Result<Self, RenderError> {
        pollster::block_on(Self::new_async())
    }

    async fn new_async() -> Result<Self, RenderError> {
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let adapter = instance
            .request_adapter(&wgpu::RequestAdapterOptions::default())
            .await
            .map_err(|e| RenderError::NoAdapter(e.to_string()))?;
        let adapter_info = adapter.get_info();
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("gnomon"),
                required_features: adapter.features() & OPTIONAL_FEATURES,
                required_limits: wgpu::Limits::default().using_resolution(adapter.limits()),
                ..Default::default()
            })
            .await
            .map_err(|e| RenderError::Device(e.to_string()))?;
        Ok(Self {
            device,
            queue,
            adapter_info,
        })
    }

    /// A device and queue the caller opened (an engine, a window's program). Request
    /// [`OPTIONAL_FEATURES`] where the adapter has them for the best depth and timing.
    pub fn from_device(
        device: wgpu::Device,
        queue: wgpu::Queue,
        adapter_info: wgpu::AdapterInfo,
    ) -> Self {
        Self {
            device,
            queue,
            adapter_info,
        }
    }

    /// A one-line description of the adapter.
    pub fn describe(&self) -> String {
        let i = &self.adapter_info;
        format!("{} ({:?}, {:?})", i.name, i.backend, i.device_type)
    }

    /// The largest image or shadow map side this device takes.
    pub fn max_texture_size(&self) -> u32 {
        self.device.limits().max_texture_dimension_2d
    }

    /// Refuses a `what` (image, target) of `width` x `height` that this device cannot make.
    pub(crate) fn check_size(
        &self,
        what: &'static str,
        width: u32,
        height: u32,
    ) -> Result<(), RenderError> {
        let max = self.max_texture_size();
        if width == 0 || height == 0 || width > max || height > max {
            return Err(InvalidInput::ImageSize {
                what,
                width,
                height,
                max,
            }
            .into());
        }
        Ok(())
    }

    /// Waits until the GPU has finished all submitted work.
    pub(crate) fn wait(&self) -> Result<(), RenderError> {
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map(|_| ())
            .map_err(|e| RenderError::Gpu(e.to_string()))
    }
}

/// Validation and internal (GL shader compilation) error scopes around GPU work.
pub(crate) struct ErrorScopes {
    validation: wgpu::ErrorScopeGuard,
    internal: wgpu::ErrorScopeGuard,
}

impl ErrorScopes {
    pub fn push(gpu: &Gpu) -> Self {
        Self {
            validation: gpu.device.push_error_scope(wgpu::ErrorFilter::Validation),
            internal: gpu.device.push_error_scope(wgpu::ErrorFilter::Internal),
        }
    }

    pub fn pop(self) -> Result<(), RenderError> {
        let internal = pollster::block_on(self.internal.pop());
        let validation = pollster::block_on(self.validation.pop());
        match internal.or(validation) {
            Some(error) => Err(RenderError::Gpu(error.to_string())),
            None => Ok(()),
        }
    }
}
