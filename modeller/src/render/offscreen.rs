//! Drawing without a window: render into a texture, read it back, write a PNG.

use std::io::Write;
use std::path::Path;

use super::renderer::Renderer;
use super::targets::FrameTargets;
use super::{GpuContext, RenderError};

/// The colour format of offscreen frames (8-bit sRGB, what a PNG holds).
pub const OFFSCREEN_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;

/// An 8-bit RGBA image, rows top to bottom.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RgbaImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `4 · width · height` bytes, sRGB encoded.
    pub pixels: Vec<u8>,
}

impl RgbaImage {
    /// Encodes the image as PNG into `out`.
    ///
    /// # Errors
    /// [`RenderError::Png`] when encoding or writing fails.
    pub fn write_png<W: Write>(&self, out: W) -> Result<(), RenderError> {
        let mut encoder = png::Encoder::new(out, self.width, self.height);
        encoder.set_color(png::ColorType::Rgba);
        encoder.set_depth(png::BitDepth::Eight);
        encoder.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
        let mut writer = encoder
            .write_header()
            .map_err(|e| RenderError::Png(e.to_string()))?;
        writer
            .write_image_data(&self.pixels)
            .map_err(|e| RenderError::Png(e.to_string()))?;
        writer.finish().map_err(|e| RenderError::Png(e.to_string()))
    }

    /// Writes the image as a PNG file with the one safe writer ([`nendo_file`]): atomically,
    /// through a symbolic link, keeping the replaced file's permissions.
    ///
    /// # Errors
    /// [`RenderError::Io`] (naming `path`) when the file cannot be written, [`RenderError::Png`]
    /// when encoding fails; either way nothing is written.
    pub fn save_png(&self, path: &Path) -> Result<(), RenderError> {
        let io = |error| RenderError::Io {
            path: path.to_path_buf(),
            error,
        };
        let mut file = nendo_file::AtomicFile::create(path).map_err(|e| io(e.into_io()))?;
        self.write_png(&mut file)?;
        file.commit().map_err(|e| io(e.into_io()))
    }

    /// Reads a PNG (8-bit RGBA or RGB).
    ///
    /// # Errors
    /// [`RenderError::Png`] for anything else or a malformed file.
    pub fn read_png(bytes: &[u8]) -> Result<Self, RenderError> {
        let decoder = png::Decoder::new(std::io::Cursor::new(bytes));
        let mut reader = decoder
            .read_info()
            .map_err(|e| RenderError::Png(e.to_string()))?;
        let size = reader
            .output_buffer_size()
            .ok_or_else(|| RenderError::Png("image too large".into()))?;
        let mut buffer = vec![0u8; size];
        let info = reader
            .next_frame(&mut buffer)
            .map_err(|e| RenderError::Png(e.to_string()))?;
        buffer.truncate(info.buffer_size());
        let pixels = match (info.color_type, info.bit_depth) {
            (png::ColorType::Rgba, png::BitDepth::Eight) => buffer,
            (png::ColorType::Rgb, png::BitDepth::Eight) => buffer
                .chunks_exact(3)
                .flat_map(|c| [c[0], c[1], c[2], 255])
                .collect(),
            other => {
                return Err(RenderError::Png(format!(
                    "unsupported PNG layout {other:?}"
                )));
            }
        };
        Ok(Self {
            width: info.width,
            height: info.height,
            pixels,
        })
    }
}

/// A render target in memory: a colour texture of [`OFFSCREEN_FORMAT`], its multisampled
/// companions, and a buffer to read it back.
#[derive(Debug)]
pub struct Offscreen {
    size: [u32; 2],
    targets: FrameTargets,
    texture: wgpu::Texture,
    view: wgpu::TextureView,
    readback: wgpu::Buffer,
    padded_row: u32,
}

impl Offscreen {
    /// A target of `size` pixels (each side at least 1) with `sample_count` samples per pixel.
    #[must_use]
    pub fn new(device: &wgpu::Device, size: [u32; 2], sample_count: u32) -> Self {
        let size = [size[0].max(1), size[1].max(1)];
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("nendo offscreen"),
            size: wgpu::Extent3d {
                width: size[0],
                height: size[1],
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: OFFSCREEN_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
        let align = wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
        let padded_row = (4 * size[0]).div_ceil(align) * align;
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("nendo readback"),
            size: u64::from(padded_row) * u64::from(size[1]),
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        let targets = FrameTargets::new(device, OFFSCREEN_FORMAT, size, sample_count);
        Self {
            size,
            targets,
            texture,
            view,
            readback,
            padded_row,
        }
    }

    /// Size in pixels.
    #[must_use]
    pub fn size(&self) -> [u32; 2] {
        self.size
    }

    /// Draws one frame with `renderer` (already given its scene and prepared) and reads it back.
    ///
    /// # Errors
    /// [`RenderError::Readback`] when the GPU work or the mapping fails.
    pub fn render(&self, gpu: &GpuContext, renderer: &Renderer) -> Result<RgbaImage, RenderError> {
        let mut encoder = gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("nendo offscreen"),
            });
        {
            let mut pass = self.targets.begin_pass(&mut encoder, &self.view);
            renderer.draw(&mut pass);
        }
        encoder.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo {
                texture: &self.texture,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            wgpu::TexelCopyBufferInfo {
                buffer: &self.readback,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(self.padded_row),
                    rows_per_image: Some(self.size[1]),
                },
            },
            wgpu::Extent3d {
                width: self.size[0],
                height: self.size[1],
                depth_or_array_layers: 1,
            },
        );
        gpu.queue.submit([encoder.finish()]);

        let slice = self.readback.slice(..);
        let (sender, receiver) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |result| {
            let _ = sender.send(result);
        });
        gpu.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| RenderError::Readback(e.to_string()))?;
        receiver
            .recv()
            .map_err(|e| RenderError::Readback(e.to_string()))?
            .map_err(|e| RenderError::Readback(e.to_string()))?;
        let mut pixels = Vec::with_capacity((4 * self.size[0] * self.size[1]) as usize);
        {
            let mapped = slice
                .get_mapped_range()
                .map_err(|e| RenderError::Readback(e.to_string()))?;
            for row in mapped.chunks_exact(self.padded_row as usize) {
                pixels.extend_from_slice(&row[..(4 * self.size[0]) as usize]);
            }
        }
        self.readback.unmap();
        Ok(RgbaImage {
            width: self.size[0],
            height: self.size[1],
            pixels,
        })
    }
}
