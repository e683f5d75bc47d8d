//! Compute rasteriser shared by every view that needs visibility: the camera's visibility
//! buffer, the shadow maps and the reflective shadow maps. Each view owns a 64-bit target
//! (reversed depth in the high word, triangle id + 1 in the low word) written with
//! `atomicMax`; see raster.wgsl for why this is not the fixed-function rasteriser.

use crate::scene_gpu::Geometry;
use bytemuck::{Pod, Zeroable};
use glam::{Mat4, UVec4, Vec4};
use mrshade_core::flags::Realness;
use mrshade_gpu::timing::Recorder;
use mrshade_gpu::{GpuContext, bind, wgsl};
use wgpu::util::DeviceExt;

/// Which casters a view sees.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Casters {
    /// Real and virtual geometry.
    All,
    /// Only one kind.
    Only(Realness),
    /// Triangles `first..first + count` (one instance's): the nearest surface.
    Range {
        /// First triangle.
        first: u32,
        /// Triangle count.
        count: u32,
    },
    /// Triangles `first..first + count`: the farthest surface, as Wyman's back-face pass
    /// keeps with depth test GREATER (refraction spec §2.12).
    FarthestOf {
        /// First triangle.
        first: u32,
        /// Triangle count.
        count: u32,
    },
}

/// Mirrors `RasterView` in raster.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct ViewUniform {
    clip_from_world: Mat4,
    size: UVec4,
    limits: UVec4,
    params: Vec4,
    clip_plane: Vec4,
}

/// Byte offsets of views that share one buffer are aligned to this (storage-binding offsets).
pub const VIEW_ALIGN: u64 = 256;

/// Bytes of a view of `size` texels in a buffer shared with others, aligned for the next one.
pub fn shared_view_bytes(size: (u32, u32)) -> u64 {
    (size.0 as u64 * size.1 as u64 * 8).next_multiple_of(VIEW_ALIGN)
}

/// Triangles whose bounding box covers more pixels than this are shared by a workgroup.
const SMALL_TRIANGLE_PIXELS: u32 = 256;
/// Workgroups per big triangle (each takes every `BIG_TILE_STRIDE`-th 16×16 tile).
const BIG_TILE_STRIDE: u32 = 64;
/// Big-triangle records per view; beyond that, triangles are drawn by their own thread.
const BIG_CAPACITY: u32 = 16384;
/// Size of one `BigTriangle` in raster.wgsl.
pub(crate) const BIG_RECORD_BYTES: u64 = 80;

/// One rasterised view: its constants and its visibility target.
pub struct RasterView {
    uniform: ViewUniform,
    uniform_buffer: wgpu::Buffer,
    /// `width × height` packed `u64` texels, row-major, from byte `offset`.
    pub target: wgpu::Buffer,
    offset: u64,
    bytes: u64,
    args: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
    args_group: wgpu::BindGroup,
    /// Triangles the view draws (the scene's, or one instance's).
    triangles: u32,
}

impl RasterView {
    /// (width, height) in texels.
    pub fn size(&self) -> (u32, u32) {
        (self.uniform.size.x, self.uniform.size.y)
    }

    /// Draws only what lies on the positive side of the world-space `plane`
    /// (`dot(plane.xyz, p) + plane.w > 0`; `Vec4::W`, the default, keeps everything). Call
    /// before `set_clip_from_world`, which uploads both.
    pub fn set_clip_plane(&mut self, plane: Vec4) {
        self.uniform.clip_plane = plane;
    }

    /// Changes the projection (a moving camera or light); takes effect at the next frame.
    pub fn set_clip_from_world(&mut self, queue: &wgpu::Queue, clip_from_world: Mat4) {
        self.uniform.clip_from_world = clip_from_world;
        queue.write_buffer(&self.uniform_buffer, 0, bytemuck::bytes_of(&self.uniform));
    }
}

/// The pipelines and the geometry they read.
pub struct Rasterizer {
    small: wgpu::ComputePipeline,
    big: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    args_layout: wgpu::BindGroupLayout,
    args_init: wgpu::Buffer,
    triangle_count: u32,
}

impl Rasterizer {
    /// Builds the pipelines for `geometry`.
    pub fn new(ctx: &GpuContext, geometry: &Geometry) -> Self {
        let device = &ctx.device;
        let cs = wgpu::ShaderStages::COMPUTE;
        let rw = |binding| bind::storage_rw(binding, cs);
        let layout = bind::layout(
            device,
            "raster/layout",
            &[
                bind::uniform(0, cs),
                bind::storage(1, cs),
                bind::storage(2, cs),
                bind::storage(3, cs),
                bind::storage(4, cs),
                rw(5),
                rw(6),
            ],
        );
        let args_layout = bind::layout(device, "raster/args_layout", &[rw(0)]);
        let module = mrshade_gpu::shader::create_module(device, "raster/shader", SHADER);
        let pipeline = |entry: &str, layouts: &[Option<&wgpu::BindGroupLayout>]| {
            let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(&format!("raster/{entry}_layout")),
                bind_group_layouts: layouts,
                immediate_size: 0,
            });
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(&format!("raster/{entry}")),
                layout: Some(&pipeline_layout),
                module: &module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                cache: None,
            })
        };
        let args_init = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("raster/args_init"),
            contents: bytemuck::cast_slice(&[0u32, BIG_TILE_STRIDE, 1]),
            usage: wgpu::BufferUsages::COPY_SRC,
        });
        Self {
            small: pipeline("cs_small", &[Some(&layout), Some(&args_layout)]),
            big: pipeline("cs_big", &[Some(&layout)]),
            layout,
            args_layout,
            args_init,
            triangle_count: geometry.triangle_count,
        }
    }

    /// A view of `size` texels seeing `casters` through `clip_from_world`; `near` is the
    /// near-plane distance of a perspective projection (0 for orthographic ones). The view
    /// writes into `target` at the given byte offset (a layer of a shared array), or into a
    /// buffer of its own.
    #[allow(clippy::too_many_arguments, reason = "a view is these seven facts")]
    pub fn view(
        &self,
        ctx: &GpuContext,
        geometry: &Geometry,
        label: &str,
        size: (u32, u32),
        casters: Casters,
        clip_from_world: Mat4,
        near: f32,
        target: Option<(&wgpu::Buffer, u64)>,
    ) -> RasterView {
        let device = &ctx.device;
        // (filter, first triangle, triangle count, keep the farthest)
        let all = self.triangle_count;
        let (filter, first, triangles, farthest) = match casters {
            Casters::All => (0, 0, all, 0.0),
            Casters::Only(Realness::Real) => (1, 0, all, 0.0),
            Casters::Only(Realness::Virtual) => (2, 0, all, 0.0),
            Casters::Range { first, count } => (0, first, count, 0.0),
            Casters::FarthestOf { first, count } => (0, first, count, 1.0),
        };
        let uniform = ViewUniform {
            clip_from_world,
            size: UVec4::new(size.0, size.1, filter, first + triangles),
            limits: UVec4::new(BIG_CAPACITY, SMALL_TRIANGLE_PIXELS, BIG_TILE_STRIDE, first),
            params: Vec4::new(near, farthest, 0.0, 0.0),
            clip_plane: Vec4::W,
        };
        let uniform_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(&format!("{label}/view")),
            contents: bytemuck::bytes_of(&uniform),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        let buffer = |name: &str, size: u64, usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(&format!("{label}/{name}")),
                size,
                usage,
                mapped_at_creation: false,
            })
        };
        let storage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST;
        let bytes = size.0 as u64 * size.1 as u64 * 8;
        let (target, offset) = match target {
            Some((buffer, offset)) => (buffer.clone(), offset),
            None => (buffer("target", bytes, storage | wgpu::BufferUsages::COPY_SRC), 0),
        };
        let big = buffer("big_triangles", BIG_CAPACITY as u64 * BIG_RECORD_BYTES, storage);
        let args = buffer("big_args", 12, storage | wgpu::BufferUsages::INDIRECT);
        let bind_group = bind::group(
            device,
            &format!("{label}/bind_group"),
            &self.layout,
            &[
                uniform_buffer.as_entire_binding(),
                geometry.instances.as_entire_binding(),
                geometry.vertices.as_entire_binding(),
                geometry.indices.as_entire_binding(),
                geometry.triangles.as_entire_binding(),
                wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                    buffer: &target,
                    offset,
                    size: wgpu::BufferSize::new(bytes),
                }),
                big.as_entire_binding(),
            ],
        );
        let args_group =
            bind::group(device, &format!("{label}/args_group"), &self.args_layout, &[args.as_entire_binding()]);
        RasterView { uniform, uniform_buffer, target, offset, bytes, args, bind_group, args_group, triangles }
    }

    /// Clears and rasterises `views`, timed as one pass named `label`.
    pub fn record<'a>(&self, rec: &mut Recorder, label: &str, views: impl IntoIterator<Item = &'a RasterView> + Clone) {
        for v in views.clone() {
            rec.encoder.clear_buffer(&v.target, v.offset, Some(v.bytes));
            rec.encoder.copy_buffer_to_buffer(&self.args_init, 0, &v.args, 0, 12);
        }
        rec.compute(label, |pass| {
            pass.set_pipeline(&self.small);
            for v in views.clone() {
                pass.set_bind_group(0, &v.bind_group, &[]);
                pass.set_bind_group(1, &v.args_group, &[]);
                mrshade_gpu::shader::dispatch_linear(pass, v.triangles.max(1), 64);
            }
            pass.set_pipeline(&self.big);
            for v in views {
                pass.set_bind_group(0, &v.bind_group, &[]);
                pass.dispatch_workgroups_indirect(&v.args, 0);
            }
        });
    }
}

/// The composed WGSL module.
pub const SHADER: &str = wgsl!(
    "../../shaders/lib/gbuffer.wgsl",
    "../../shaders/lib/instance.wgsl",
    "../../shaders/lib/raster_common.wgsl",
    "raster.wgsl",
);
