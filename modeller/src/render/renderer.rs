//! The scene renderer: background, clay surface, spheres and lines, in one render pass.

use glam::{Mat4, Vec3};

use super::analysis::AnalysisPass;
use super::buffer::GrowBuffer;
use super::gpu_data::{Globals, LineVertex, SphereInstance, SphereVertex, SurfaceVertex};
use super::scene::{LineBatch, Style, View};
use super::targets::DEPTH_FORMAT;
use crate::mesh::TriMesh;

/// The `Globals` uniform block and its binding, defined once (`modeller/shaders/globals.wgsl`)
/// and prepended to every shader that reads it. Its layout is [`Globals`]'s.
pub const GLOBALS_WGSL: &str = include_str!("../../shaders/globals.wgsl");

/// `modeller/shaders/globals.wgsl` followed by `modeller/shaders/$file`, as one WGSL source.
macro_rules! with_globals {
    ($file:literal) => {
        concat!(
            include_str!("../../shaders/globals.wgsl"),
            include_str!(concat!("../../shaders/", $file))
        )
    };
}

const BACKGROUND_WGSL: &str = include_str!("../../shaders/background.wgsl");
const CLAY_WGSL: &str = with_globals!("clay.wgsl");
const LINES_WGSL: &str = with_globals!("lines.wgsl");
const SPHERES_WGSL: &str = with_globals!("spheres.wgsl");

/// Every shader program of the renderer, `(file name, source as compiled)`, for validation and
/// tools: the file's text, preceded by [`GLOBALS_WGSL`] for the programs that read the
/// per-frame uniform (all but the background).
pub const SHADERS: [(&str, &str); 5] = [
    ("analysis.wgsl", super::analysis::ANALYSIS_WGSL),
    ("background.wgsl", BACKGROUND_WGSL),
    ("clay.wgsl", CLAY_WGSL),
    ("lines.wgsl", LINES_WGSL),
    ("spheres.wgsl", SPHERES_WGSL),
];

/// The GPU vertices of `mesh` in `range` (with the seam heat of [`Renderer::set_surface`]):
/// what an upload copies, built on the CPU.
#[must_use]
pub fn surface_vertices(
    mesh: &TriMesh,
    seam: &[[f32; 2]],
    range: std::ops::Range<u32>,
) -> Vec<SurfaceVertex> {
    let range = range.start as usize..(range.end as usize).min(mesh.positions.len());
    range
        .map(|i| SurfaceVertex {
            position: mesh.positions[i].to_array(),
            normal: mesh
                .normals
                .get(i)
                .map_or([0.0, 0.0, 1.0], |n| n.to_array()),
            seam: seam.get(i).copied().unwrap_or([0.0, 0.0]),
        })
        .collect()
}

/// Draws a scene: a tessellated surface (clay, seam heat map, tool footprint), coloured line
/// segments and spheres. Knows nothing of the application: it is given meshes, lines, spheres
/// and a view, and draws them into a render pass the caller opens (see
/// [`super::FrameTargets::begin_pass`]).
#[derive(Debug)]
pub struct Renderer {
    globals: wgpu::Buffer,
    globals_bind_group: wgpu::BindGroup,
    background: wgpu::RenderPipeline,
    clay: wgpu::RenderPipeline,
    lines: wgpu::RenderPipeline,
    lines_on_top: wgpu::RenderPipeline,
    spheres_opaque: wgpu::RenderPipeline,
    spheres_translucent: wgpu::RenderPipeline,
    surface_vertices: GrowBuffer,
    surface_indices: GrowBuffer,
    surface_index_count: u32,
    line_vertices: GrowBuffer,
    line_vertex_count: u32,
    on_top_vertices: GrowBuffer,
    on_top_vertex_count: u32,
    sphere_mesh_vertices: wgpu::Buffer,
    sphere_mesh_indices: wgpu::Buffer,
    sphere_mesh_index_count: u32,
    sphere_instances: GrowBuffer,
    opaque_spheres: u32,
    translucent_spheres: u32,
    analysis: AnalysisPass,
}

impl Renderer {
    /// A renderer drawing into colour targets of `format` with `sample_count` samples per
    /// pixel (and a [`DEPTH_FORMAT`] depth buffer of the same count).
    #[must_use]
    pub fn new(device: &wgpu::Device, format: wgpu::TextureFormat, sample_count: u32) -> Self {
        let globals = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("nendo globals"),
            size: std::mem::size_of::<Globals>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let globals_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("nendo globals"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: wgpu::BufferSize::new(std::mem::size_of::<Globals>() as u64),
                },
                count: None,
            }],
        });
        let globals_bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("nendo globals"),
            layout: &globals_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: globals.as_entire_binding(),
            }],
        });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("nendo scene"),
            bind_group_layouts: &[Some(&globals_layout)],
            immediate_size: 0,
        });
        let factory = PipelineFactory {
            device,
            layout: &layout,
            format,
            sample_count,
        };

        let background = factory.build(&PipelineSpec {
            label: "background",
            source: BACKGROUND_WGSL,
            buffers: &[],
            topology: wgpu::PrimitiveTopology::TriangleList,
            depth_write: false,
            depth_compare: wgpu::CompareFunction::Always,
            blend: None,
        });
        let clay = factory.build(&PipelineSpec {
            label: "clay",
            source: CLAY_WGSL,
            buffers: &[wgpu::VertexBufferLayout {
                array_stride: std::mem::size_of::<SurfaceVertex>() as u64,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &SurfaceVertex::ATTRIBUTES,
            }],
            topology: wgpu::PrimitiveTopology::TriangleList,
            depth_write: true,
            depth_compare: wgpu::CompareFunction::Less,
            blend: None,
        });
        let line_buffers = [wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<LineVertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &LineVertex::ATTRIBUTES,
        }];
        let lines = factory.build(&PipelineSpec {
            label: "lines",
            source: LINES_WGSL,
            buffers: &line_buffers,
            topology: wgpu::PrimitiveTopology::LineList,
            depth_write: true,
            depth_compare: wgpu::CompareFunction::LessEqual,
            blend: Some(wgpu::BlendState::ALPHA_BLENDING),
        });
        let lines_on_top = factory.build(&PipelineSpec {
            label: "lines (on top)",
            source: LINES_WGSL,
            buffers: &line_buffers,
            topology: wgpu::PrimitiveTopology::LineList,
            depth_write: false,
            depth_compare: wgpu::CompareFunction::Always,
            blend: Some(wgpu::BlendState::ALPHA_BLENDING),
        });
        let sphere_buffers = [
            wgpu::VertexBufferLayout {
                array_stride: std::mem::size_of::<SphereVertex>() as u64,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &SphereVertex::ATTRIBUTES,
            },
            wgpu::VertexBufferLayout {
                array_stride: std::mem::size_of::<SphereInstance>() as u64,
                step_mode: wgpu::VertexStepMode::Instance,
                attributes: &SphereInstance::ATTRIBUTES,
            },
        ];
        let spheres_opaque = factory.build(&PipelineSpec {
            label: "spheres (opaque)",
            source: SPHERES_WGSL,
            buffers: &sphere_buffers,
            topology: wgpu::PrimitiveTopology::TriangleList,
            depth_write: true,
            depth_compare: wgpu::CompareFunction::Less,
            blend: None,
        });
        let spheres_translucent = factory.build(&PipelineSpec {
            label: "spheres (translucent)",
            source: SPHERES_WGSL,
            buffers: &sphere_buffers,
            topology: wgpu::PrimitiveTopology::TriangleList,
            depth_write: false,
            depth_compare: wgpu::CompareFunction::Less,
            blend: Some(wgpu::BlendState::ALPHA_BLENDING),
        });

        let analysis = AnalysisPass::new(device, &globals_layout, format, sample_count);
        let (unit_vertices, unit_indices) = unit_sphere(12, 24);
        let sphere_mesh_vertices = buffer_init(
            device,
            "nendo unit sphere vertices",
            bytemuck::cast_slice(&unit_vertices),
            wgpu::BufferUsages::VERTEX,
        );
        let sphere_mesh_indices = buffer_init(
            device,
            "nendo unit sphere indices",
            bytemuck::cast_slice(&unit_indices),
            wgpu::BufferUsages::INDEX,
        );

        Self {
            globals,
            globals_bind_group,
            background,
            clay,
            lines,
            lines_on_top,
            spheres_opaque,
            spheres_translucent,
            surface_vertices: GrowBuffer::new("nendo surface vertices", wgpu::BufferUsages::VERTEX),
            surface_indices: GrowBuffer::new("nendo surface indices", wgpu::BufferUsages::INDEX),
            surface_index_count: 0,
            line_vertices: GrowBuffer::new("nendo line vertices", wgpu::BufferUsages::VERTEX),
            line_vertex_count: 0,
            on_top_vertices: GrowBuffer::new(
                "nendo on-top line vertices",
                wgpu::BufferUsages::VERTEX,
            ),
            on_top_vertex_count: 0,
            sphere_mesh_vertices,
            sphere_mesh_indices,
            sphere_mesh_index_count: unit_indices.len() as u32,
            sphere_instances: GrowBuffer::new("nendo sphere instances", wgpu::BufferUsages::VERTEX),
            opaque_spheres: 0,
            translucent_spheres: 0,
            analysis,
        }
    }

    /// Uploads the surface: a tessellation and, per vertex, the seam heat `[angle°, weight]` of
    /// [`crate::mesh::seam_bands`] (missing entries count as no seam).
    pub fn set_surface(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        mesh: &TriMesh,
        seam: &[[f32; 2]],
    ) {
        let vertices = surface_vertices(mesh, seam, 0..mesh.positions.len() as u32);
        self.surface_vertices
            .write(device, queue, bytemuck::cast_slice(&vertices));
        self.surface_indices
            .write(device, queue, bytemuck::cast_slice(&mesh.indices));
        self.surface_index_count = mesh.indices.len() as u32;
    }

    /// Uploads again only the given vertex ranges of the surface (a live stroke: the
    /// vertex ranges the caller knows changed since the last upload), for a mesh
    /// whose indices and vertex count are those last given to [`Renderer::set_surface`].
    /// Falls back to [`Renderer::set_surface`] when the vertex count differs or a range lies
    /// outside the mesh.
    pub fn update_surface_vertices(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        mesh: &TriMesh,
        seam: &[[f32; 2]],
        ranges: &[std::ops::Range<u32>],
    ) {
        let count = mesh.positions.len() as u32;
        let stride = std::mem::size_of::<SurfaceVertex>() as u64;
        let fits = self.surface_index_count == mesh.indices.len() as u32
            && self.surface_vertices.len() == u64::from(count) * stride
            && ranges.iter().all(|r| r.start <= r.end && r.end <= count);
        if !fits {
            self.set_surface(device, queue, mesh, seam);
            return;
        }
        for r in ranges {
            let vertices = surface_vertices(mesh, seam, r.clone());
            let offset = u64::from(r.start) * stride;
            if !self
                .surface_vertices
                .write_at(queue, offset, bytemuck::cast_slice(&vertices))
            {
                self.set_surface(device, queue, mesh, seam);
                return;
            }
        }
    }

    /// Uploads what the analysis display modes read ([`super::analysis`]): the control points
    /// of `patches` and the patch and `(u, v)` of every vertex of `mesh`, their tessellation
    /// as given to [`Renderer::set_surface`]. Needed again whenever the patches change while
    /// a mode other than clay is shown.
    pub fn set_analysis_patches(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        patches: &[crate::mesh::PatchPoints],
        mesh: &TriMesh,
    ) {
        self.analysis.set_patches(device, queue, patches, mesh);
    }

    /// Chooses how the surface is drawn: clay, or an analysis mode with its settings for the
    /// camera of `view`.
    pub fn set_analysis(
        &mut self,
        queue: &wgpu::Queue,
        settings: &super::SurfaceAnalysis,
        view: &View,
    ) {
        self.analysis.prepare(queue, settings, view.world_from_view);
    }

    /// Uploads the line segments (those on top are drawn last, over everything).
    pub fn set_lines(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, lines: &LineBatch) {
        self.line_vertices
            .write(device, queue, bytemuck::cast_slice(lines.vertices()));
        self.line_vertex_count = lines.vertices().len() as u32;
        self.on_top_vertices
            .write(device, queue, bytemuck::cast_slice(lines.on_top_vertices()));
        self.on_top_vertex_count = lines.on_top_vertices().len() as u32;
    }

    /// Uploads the spheres (opaque ones are drawn before the lines, translucent ones last).
    pub fn set_spheres(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        spheres: &[SphereInstance],
    ) {
        let (mut opaque, translucent): (Vec<SphereInstance>, Vec<SphereInstance>) =
            spheres.iter().partition(|s| s.colour[3] >= 1.0);
        self.opaque_spheres = opaque.len() as u32;
        self.translucent_spheres = translucent.len() as u32;
        opaque.extend(translucent);
        self.sphere_instances
            .write(device, queue, bytemuck::cast_slice(&opaque));
    }

    /// Writes the per-frame uniform: the view, the style, and the viewport size in pixels.
    pub fn prepare(&self, queue: &wgpu::Queue, view: &View, style: &Style, viewport_px: [f32; 2]) {
        let view_to_light = Vec3::new(-0.62, 0.6, 0.5).normalize();
        let key_light = view
            .world_from_view
            .transform_vector3(view_to_light)
            .normalize_or(Vec3::Z);
        let tool = style.tool.unwrap_or_default();
        let eye = view.eye_homogeneous();
        let globals = Globals {
            clip_from_world: view.clip_from_world.to_cols_array_2d(),
            eye: eye.truncate().to_array(),
            heat_max_deg: style.heat_max_deg,
            key_light: key_light.to_array(),
            heat_on: if style.heat_map { 1.0 } else { 0.0 },
            clay: style.clay,
            tool_center: tool.center.to_array(),
            tool_radius: tool.radius,
            tool_axis: tool.axis.normalize_or(Vec3::Z).to_array(),
            tool_on: if style.tool.is_some() { 1.0 } else { 0.0 },
            viewport: viewport_px,
            line_depth_bias: style.line_depth_bias,
            eye_w: eye.w,
            view_right: view
                .world_from_view
                .x_axis
                .truncate()
                .normalize_or(Vec3::X)
                .to_array(),
            matcap: style.matcap.map_or(0.0, |m| m.code() as f32),
            view_up: view
                .world_from_view
                .y_axis
                .truncate()
                .normalize_or(Vec3::Y)
                .to_array(),
            pad: 0.0,
        };
        queue.write_buffer(&self.globals, 0, bytemuck::bytes_of(&globals));
    }

    /// Records the draws into `pass` (opened on targets of this renderer's format and sample
    /// count); the viewport is the caller's to set.
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>) {
        pass.set_bind_group(0, &self.globals_bind_group, &[]);
        pass.set_pipeline(&self.background);
        pass.draw(0..3, 0..1);

        if let (Some(vertices), Some(indices)) =
            (self.surface_vertices.slice(), self.surface_indices.slice())
        {
            let vertex_count =
                self.surface_vertices.len() / std::mem::size_of::<SurfaceVertex>() as u64;
            if !self.analysis.draw(
                pass,
                vertices,
                vertex_count,
                indices,
                self.surface_index_count,
            ) {
                pass.set_pipeline(&self.clay);
                pass.set_vertex_buffer(0, vertices);
                pass.set_index_buffer(indices, wgpu::IndexFormat::Uint32);
                pass.draw_indexed(0..self.surface_index_count, 0, 0..1);
            }
        }
        let instances = self.sphere_instances.slice();
        if let Some(instances) = instances.filter(|_| self.opaque_spheres > 0) {
            pass.set_pipeline(&self.spheres_opaque);
            pass.set_vertex_buffer(0, self.sphere_mesh_vertices.slice(..));
            pass.set_vertex_buffer(1, instances);
            pass.set_index_buffer(
                self.sphere_mesh_indices.slice(..),
                wgpu::IndexFormat::Uint32,
            );
            pass.draw_indexed(0..self.sphere_mesh_index_count, 0, 0..self.opaque_spheres);
        }
        if let Some(vertices) = self.line_vertices.slice() {
            pass.set_pipeline(&self.lines);
            pass.set_vertex_buffer(0, vertices);
            pass.draw(0..self.line_vertex_count, 0..1);
        }
        if let Some(instances) = instances.filter(|_| self.translucent_spheres > 0) {
            let range = self.opaque_spheres..self.opaque_spheres + self.translucent_spheres;
            pass.set_pipeline(&self.spheres_translucent);
            pass.set_vertex_buffer(0, self.sphere_mesh_vertices.slice(..));
            pass.set_vertex_buffer(1, instances);
            pass.set_index_buffer(
                self.sphere_mesh_indices.slice(..),
                wgpu::IndexFormat::Uint32,
            );
            pass.draw_indexed(0..self.sphere_mesh_index_count, 0, range);
        }
        if let Some(vertices) = self.on_top_vertices.slice() {
            pass.set_pipeline(&self.lines_on_top);
            pass.set_vertex_buffer(0, vertices);
            pass.draw(0..self.on_top_vertex_count, 0..1);
        }
    }
}

/// What differs between the pipelines.
struct PipelineSpec<'a> {
    label: &'static str,
    source: &'static str,
    buffers: &'a [wgpu::VertexBufferLayout<'a>],
    topology: wgpu::PrimitiveTopology,
    depth_write: bool,
    depth_compare: wgpu::CompareFunction,
    blend: Option<wgpu::BlendState>,
}

/// What the pipelines share.
struct PipelineFactory<'a> {
    device: &'a wgpu::Device,
    layout: &'a wgpu::PipelineLayout,
    format: wgpu::TextureFormat,
    sample_count: u32,
}

impl PipelineFactory<'_> {
    fn build(&self, spec: &PipelineSpec<'_>) -> wgpu::RenderPipeline {
        let module = self
            .device
            .create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(spec.label),
                source: wgpu::ShaderSource::Wgsl(spec.source.into()),
            });
        let buffers: Vec<Option<wgpu::VertexBufferLayout<'_>>> =
            spec.buffers.iter().cloned().map(Some).collect();
        self.device
            .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(spec.label),
                layout: Some(self.layout),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some("vs_main"),
                    compilation_options: Default::default(),
                    buffers: &buffers,
                },
                primitive: wgpu::PrimitiveState {
                    topology: spec.topology,
                    cull_mode: None,
                    ..Default::default()
                },
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: DEPTH_FORMAT,
                    depth_write_enabled: Some(spec.depth_write),
                    depth_compare: Some(spec.depth_compare),
                    stencil: wgpu::StencilState::default(),
                    bias: wgpu::DepthBiasState::default(),
                }),
                multisample: wgpu::MultisampleState {
                    count: self.sample_count,
                    ..Default::default()
                },
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some("fs_main"),
                    compilation_options: Default::default(),
                    targets: &[Some(wgpu::ColorTargetState {
                        format: self.format,
                        blend: spec.blend,
                        write_mask: wgpu::ColorWrites::ALL,
                    })],
                }),
                multiview_mask: None,
                cache: None,
            })
    }
}

fn buffer_init(
    device: &wgpu::Device,
    label: &str,
    bytes: &[u8],
    usage: wgpu::BufferUsages,
) -> wgpu::Buffer {
    use wgpu::util::DeviceExt;
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: bytes,
        usage,
    })
}

/// A UV sphere of unit radius: `stacks` bands from pole to pole, `slices` around.
fn unit_sphere(stacks: u32, slices: u32) -> (Vec<SphereVertex>, Vec<u32>) {
    let mut vertices = Vec::new();
    for i in 0..=stacks {
        let theta = std::f32::consts::PI * i as f32 / stacks as f32;
        for j in 0..=slices {
            let phi = std::f32::consts::TAU * j as f32 / slices as f32;
            vertices.push(SphereVertex {
                unit: [
                    theta.sin() * phi.cos(),
                    theta.sin() * phi.sin(),
                    theta.cos(),
                ],
            });
        }
    }
    let mut indices = Vec::new();
    let row = slices + 1;
    for i in 0..stacks {
        for j in 0..slices {
            let (a, b) = (i * row + j, (i + 1) * row + j);
            indices.extend([a, b, b + 1, a, b + 1, a + 1]);
        }
    }
    (vertices, indices)
}

/// `clip_from_world` for tests and tools that have no camera of their own: a perspective view
/// from `eye` towards `target`, `+Z` up.
#[must_use]
pub fn look_at_view(eye: Vec3, target: Vec3, fov_y: f32, aspect: f32) -> View {
    let view_from_world = glam::camera::rh::view::look_at_mat4(eye, target, Vec3::Z);
    let distance = (target - eye).length().max(1e-3);
    let proj = glam::camera::rh::proj::directx::perspective(
        fov_y,
        aspect,
        distance * 0.01,
        distance * 100.0,
    );
    View {
        clip_from_world: proj * view_from_world,
        world_from_view: view_from_world.inverse(),
    }
}

impl View {
    /// The camera position.
    #[must_use]
    pub fn eye(&self) -> Vec3 {
        self.world_from_view.w_axis.truncate()
    }

    /// True for an orthographic projection: clip `w` does not depend on the point (the
    /// projection's last row is `(0, 0, 0, 1)`).
    #[must_use]
    pub fn is_orthographic(&self) -> bool {
        self.clip_from_world.row(3).truncate().abs().max_element() < 1e-6
    }

    /// The eye in homogeneous coordinates: `(eye, 1)` for a perspective view, `(e, 0)` for an
    /// orthographic one, `e` the unit direction towards the camera (view space's +z).
    #[must_use]
    pub fn eye_homogeneous(&self) -> glam::Vec4 {
        if self.is_orthographic() {
            let e = self.world_from_view.z_axis.truncate().normalize_or(Vec3::Z);
            e.extend(0.0)
        } else {
            self.eye().extend(1.0)
        }
    }

    /// The view matrices of an identity camera (for defaults).
    #[must_use]
    pub fn identity() -> Self {
        View {
            clip_from_world: Mat4::IDENTITY,
            world_from_view: Mat4::IDENTITY,
        }
    }
}
