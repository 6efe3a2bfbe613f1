//! The GPU: instance, adapter, device and queue, for a window or for headless rendering.

use super::RenderError;

/// An open GPU device and what it came from.
#[derive(Debug)]
pub struct GpuContext {
    /// The wgpu instance (backends from `WGPU_BACKEND`, all native ones by default).
    pub instance: wgpu::Instance,
    /// The adapter in use.
    pub adapter: wgpu::Adapter,
    /// The device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
}

impl GpuContext {
    /// A device for rendering offscreen. Backends follow `WGPU_BACKEND` (e.g. `vulkan`, `gl`);
    /// software adapters (Mesa's lavapipe, llvmpipe) are accepted.
    ///
    /// # Errors
    /// [`RenderError::NoAdapter`] when no adapter exists (the message names the package that
    /// provides a software one), [`RenderError::Device`] when the device cannot be opened.
    pub fn headless() -> Result<Self, RenderError> {
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        Self::with_instance(instance, None)
    }

    /// A device able to present to `surface`, created from `instance`.
    ///
    /// # Errors
    /// As [`GpuContext::headless`].
    pub fn with_instance(
        instance: wgpu::Instance,
        surface: Option<&wgpu::Surface<'_>>,
    ) -> Result<Self, RenderError> {
        let options = wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            force_fallback_adapter: false,
            compatible_surface: surface,
            apply_limit_buckets: false,
        };
        let adapter = pollster::block_on(instance.request_adapter(&options))
            .map_err(|e| RenderError::NoAdapter(e.to_string()))?;
        let descriptor = wgpu::DeviceDescriptor {
            label: Some("nendo"),
            required_features: wgpu::Features::empty(),
            required_limits: wgpu::Limits::downlevel_defaults().using_resolution(adapter.limits()),
            ..Default::default()
        };
        let (device, queue) = pollster::block_on(adapter.request_device(&descriptor))
            .map_err(|e| RenderError::Device(e.to_string()))?;
        Ok(Self {
            instance,
            adapter,
            device,
            queue,
        })
    }

    /// One line naming the adapter and backend, e.g. `llvmpipe (LLVM 15.0.6, 256 bits) on Vulkan`.
    #[must_use]
    pub fn describe(&self) -> String {
        let info = self.adapter.get_info();
        format!("{} on {:?}", info.name, info.backend)
    }
}
