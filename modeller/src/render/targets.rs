//! The textures a frame is drawn into: multisampled colour and depth.

/// Depth buffer format of every pass.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// Multisampled colour (resolved into the caller's texture) and depth for one frame size.
#[derive(Debug)]
pub struct FrameTargets {
    /// Size in pixels `[width, height]`.
    pub size: [u32; 2],
    /// Samples per pixel.
    pub sample_count: u32,
    msaa: Option<wgpu::TextureView>,
    depth: wgpu::TextureView,
}

impl FrameTargets {
    /// Targets of `size` pixels for colour `format`; `sample_count` 1 draws straight into the
    /// caller's texture.
    #[must_use]
    pub fn new(
        device: &wgpu::Device,
        format: wgpu::TextureFormat,
        size: [u32; 2],
        sample_count: u32,
    ) -> Self {
        let extent = wgpu::Extent3d {
            width: size[0].max(1),
            height: size[1].max(1),
            depth_or_array_layers: 1,
        };
        let texture = |label, format, samples| {
            device
                .create_texture(&wgpu::TextureDescriptor {
                    label: Some(label),
                    size: extent,
                    mip_level_count: 1,
                    sample_count: samples,
                    dimension: wgpu::TextureDimension::D2,
                    format,
                    usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
                    view_formats: &[],
                })
                .create_view(&wgpu::TextureViewDescriptor::default())
        };
        let msaa = (sample_count > 1).then(|| texture("nendo msaa colour", format, sample_count));
        let depth = texture("nendo depth", DEPTH_FORMAT, sample_count);
        Self {
            size,
            sample_count,
            msaa,
            depth,
        }
    }

    /// A render pass drawing into `output` (through the multisampled texture when there is
    /// one), colour and depth cleared first.
    pub fn begin_pass<'e>(
        &self,
        encoder: &'e mut wgpu::CommandEncoder,
        output: &wgpu::TextureView,
    ) -> wgpu::RenderPass<'e> {
        let (view, resolve_target) = match &self.msaa {
            Some(msaa) => (msaa, Some(output)),
            None => (output, None),
        };
        encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("nendo scene"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &self.depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Discard,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        })
    }
}
