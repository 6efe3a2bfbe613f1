//! The analysis pass: draws the surface in a [`SurfaceMode`] other than clay (zebra,
//! curvature, isophotes) with `modeller/shaders/analysis.wgsl`, from the patches' control
//! points in a storage buffer and each vertex's patch and `(u, v)`; the formulas are in
//! [`super::display_mode`]. The [`Renderer`](super::Renderer) draws it in place of the clay
//! when a mode is set ([`Renderer::set_analysis`](super::Renderer::set_analysis)).

use super::buffer::GrowBuffer;
use super::display_mode::{
    AnalysisUniform, AnalysisVertex, SurfaceAnalysis, SurfaceMode, analysis_vertices,
    patch_points_f32,
};
use super::gpu_data::SurfaceVertex;
use super::targets::DEPTH_FORMAT;
use crate::mesh::{PatchPoints, TriMesh};

/// `modeller/shaders/globals.wgsl` followed by `modeller/shaders/analysis.wgsl`.
pub const ANALYSIS_WGSL: &str = concat!(
    include_str!("../../shaders/globals.wgsl"),
    include_str!("../../shaders/analysis.wgsl")
);

/// The pipeline and buffers of the analysis display.
#[derive(Debug)]
pub(super) struct AnalysisPass {
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
    uniform: wgpu::Buffer,
    points: GrowBuffer,
    bind_group: Option<wgpu::BindGroup>,
    vertices: GrowBuffer,
    vertex_count: u32,
    mode: SurfaceMode,
}

impl AnalysisPass {
    /// The pass for targets of `format` and `sample_count`, with the renderer's globals at
    /// group 0.
    pub(super) fn new(
        device: &wgpu::Device,
        globals_layout: &wgpu::BindGroupLayout,
        format: wgpu::TextureFormat,
        sample_count: u32,
    ) -> Self {
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("nendo analysis"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: wgpu::BufferSize::new(
                            std::mem::size_of::<AnalysisUniform>() as u64,
                        ),
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Storage { read_only: true },
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                },
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("nendo analysis"),
            bind_group_layouts: &[Some(globals_layout), Some(&layout)],
            immediate_size: 0,
        });
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("analysis"),
            source: wgpu::ShaderSource::Wgsl(ANALYSIS_WGSL.into()),
        });
        let buffers = [
            Some(wgpu::VertexBufferLayout {
                array_stride: std::mem::size_of::<SurfaceVertex>() as u64,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &SurfaceVertex::ATTRIBUTES,
            }),
            Some(wgpu::VertexBufferLayout {
                array_stride: std::mem::size_of::<AnalysisVertex>() as u64,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &AnalysisVertex::ATTRIBUTES,
            }),
        ];
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("analysis"),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: &buffers,
            },
            primitive: wgpu::PrimitiveState {
                topology: wgpu::PrimitiveTopology::TriangleList,
                cull_mode: None,
                ..Default::default()
            },
            depth_stencil: Some(wgpu::DepthStencilState {
                format: DEPTH_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Less),
                stencil: wgpu::StencilState::default(),
                bias: wgpu::DepthBiasState::default(),
            }),
            multisample: wgpu::MultisampleState {
                count: sample_count,
                ..Default::default()
            },
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs_main"),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format,
                    blend: None,
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: None,
        });
        let uniform = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("nendo analysis uniform"),
            size: std::mem::size_of::<AnalysisUniform>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Self {
            pipeline,
            layout,
            uniform,
            points: GrowBuffer::new("nendo analysis control points", wgpu::BufferUsages::STORAGE),
            bind_group: None,
            vertices: GrowBuffer::new("nendo analysis vertices", wgpu::BufferUsages::VERTEX),
            vertex_count: 0,
            mode: SurfaceMode::Clay,
        }
    }

    /// Uploads the patches' control points and, per vertex of `mesh` (the tessellation of
    /// `patches` last given to the renderer), its patch and `(u, v)`.
    pub(super) fn set_patches(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        patches: &[PatchPoints],
        mesh: &TriMesh,
    ) {
        let points = patch_points_f32(patches);
        let before = self.points.capacity();
        self.points
            .write(device, queue, bytemuck::cast_slice(&points));
        if self.bind_group.is_none() || self.points.capacity() != before {
            self.bind_group = self.points.whole().map(|points| {
                device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("nendo analysis"),
                    layout: &self.layout,
                    entries: &[
                        wgpu::BindGroupEntry {
                            binding: 0,
                            resource: self.uniform.as_entire_binding(),
                        },
                        wgpu::BindGroupEntry {
                            binding: 1,
                            resource: points,
                        },
                    ],
                })
            });
        }
        let vertices = analysis_vertices(mesh);
        self.vertices
            .write(device, queue, bytemuck::cast_slice(&vertices));
        self.vertex_count = vertices.len() as u32;
    }

    /// Sets the mode and its settings for a camera `world_from_view`.
    pub(super) fn prepare(
        &mut self,
        queue: &wgpu::Queue,
        settings: &SurfaceAnalysis,
        world_from_view: glam::Mat4,
    ) {
        self.mode = settings.mode;
        let uniform = settings.uniform(world_from_view);
        queue.write_buffer(&self.uniform, 0, bytemuck::bytes_of(&uniform));
    }

    /// Draws the surface if a mode other than clay is set and the uploaded analysis vertices
    /// match the surface's `surface_vertex_count`; false (nothing drawn) otherwise, and the
    /// caller draws the clay.
    pub(super) fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        surface: wgpu::BufferSlice<'_>,
        surface_vertex_count: u64,
        indices: wgpu::BufferSlice<'_>,
        index_count: u32,
    ) -> bool {
        if self.mode == SurfaceMode::Clay || u64::from(self.vertex_count) != surface_vertex_count {
            return false;
        }
        let (Some(bind_group), Some(vertices)) = (&self.bind_group, self.vertices.slice()) else {
            return false;
        };
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(1, bind_group, &[]);
        pass.set_vertex_buffer(0, surface);
        pass.set_vertex_buffer(1, vertices);
        pass.set_index_buffer(indices, wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..index_count, 0, 0..1);
        true
    }
}
