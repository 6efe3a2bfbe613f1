//! A GPU buffer that grows to fit what is written into it.

/// A vertex, index or instance buffer rewritten whole when its content changes, and recreated
/// (one and a half times larger) only when the content outgrows it.
#[derive(Debug)]
pub(crate) struct GrowBuffer {
    label: &'static str,
    usage: wgpu::BufferUsages,
    buffer: Option<wgpu::Buffer>,
    /// Bytes of valid content.
    len: u64,
}

impl GrowBuffer {
    pub(crate) fn new(label: &'static str, usage: wgpu::BufferUsages) -> Self {
        Self {
            label,
            usage: usage | wgpu::BufferUsages::COPY_DST,
            buffer: None,
            len: 0,
        }
    }

    /// Bytes of valid content.
    pub(crate) fn len(&self) -> u64 {
        self.len
    }

    /// Replaces the content with `bytes`.
    pub(crate) fn write(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, bytes: &[u8]) {
        self.len = bytes.len() as u64;
        if bytes.is_empty() {
            return;
        }
        // Copies must be 4-byte multiples.
        let needed = (self.len + 3) & !3;
        if self.buffer.as_ref().is_none_or(|b| b.size() < needed) {
            let size = (needed + needed / 2).max(256);
            self.buffer = Some(device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(self.label),
                size,
                usage: self.usage,
                mapped_at_creation: false,
            }));
        }
        if let Some(buffer) = &self.buffer {
            if bytes.len().is_multiple_of(4) {
                queue.write_buffer(buffer, 0, bytes);
            } else {
                let mut padded = bytes.to_vec();
                padded.resize(needed as usize, 0);
                queue.write_buffer(buffer, 0, &padded);
            }
        }
    }

    /// Rewrites `bytes` at `offset` (bytes, a multiple of 4) within the content, leaving the
    /// rest as it is; false (nothing written) when that is not within the content.
    pub(crate) fn write_at(&self, queue: &wgpu::Queue, offset: u64, bytes: &[u8]) -> bool {
        let end = offset + bytes.len() as u64;
        let Some(buffer) = &self.buffer else {
            return false;
        };
        if end > self.len || !offset.is_multiple_of(4) || !bytes.len().is_multiple_of(4) {
            return false;
        }
        if !bytes.is_empty() {
            queue.write_buffer(buffer, offset, bytes);
        }
        true
    }

    /// Size of the allocation (0 before the first write): it changes exactly when a write
    /// recreated the buffer (what bind groups holding it must notice).
    pub(crate) fn capacity(&self) -> u64 {
        self.buffer.as_ref().map_or(0, wgpu::Buffer::size)
    }

    /// The whole allocation as a binding (storage buffers), if there is one.
    pub(crate) fn whole(&self) -> Option<wgpu::BindingResource<'_>> {
        self.buffer.as_ref().map(wgpu::Buffer::as_entire_binding)
    }

    /// The buffer's content as a slice, if there is any.
    pub(crate) fn slice(&self) -> Option<wgpu::BufferSlice<'_>> {
        let buffer = self.buffer.as_ref()?;
        (self.len > 0).then(|| buffer.slice(..self.len))
    }
}
