//! Compute rasteriser shared by every view that needs visibility: the camera's visibility
//! buffer, the shadow maps, the reflective shadow maps and the specular stage's impostors.
//! Each view writes a 64-bit target (reversed depth in the high word, triangle id + 1 in the
//! low word) with `atomicMax`; views that belong together ([`RasterViews`]: a light's faces,
//! a set of maps) are drawn by one dispatch pair. See raster.wgsl for why this is not the
//! fixed-function rasteriser.

use crate::scene_gpu::{Geometry, Moved, ShadowLayer};
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
    layer: UVec4,
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
/// Big-triangle records per view (a set of views shares `views × BIG_CAPACITY`, at most four
/// views' worth); beyond that, triangles are drawn by their own thread.
const BIG_CAPACITY: u32 = 16384;
/// Size of one `BigTriangle` in raster.wgsl.
pub(crate) const BIG_RECORD_BYTES: u64 = 80;

/// One view of a [`RasterViews`] set: what it sees, how, and where its texels go.
#[derive(Clone, Copy, Debug)]
pub struct ViewSpec {
    /// (width, height) in texels.
    pub size: (u32, u32),
    /// Which triangles it draws.
    pub casters: Casters,
    /// The projection (a moving camera or light changes it with `set_clip_from_world`).
    pub clip_from_world: Mat4,
    /// Near-plane distance of a perspective projection (0 for orthographic ones).
    pub near: f32,
    /// Byte offset of its layer in the set's target (a multiple of 8).
    pub offset: u64,
}

impl ViewSpec {
    /// One square view of `resolution` texels per shadow layer (its casters and projection),
    /// layer `i` at byte `i × resolution² × 8` of a shared target.
    pub fn of_layers(layers: &[ShadowLayer], resolution: u32) -> Vec<ViewSpec> {
        let layer_bytes = resolution as u64 * resolution as u64 * 8;
        layers
            .iter()
            .enumerate()
            .map(|(i, layer)| ViewSpec {
                size: (resolution, resolution),
                casters: Casters::Only(layer.casters),
                clip_from_world: layer.clip_from_world,
                near: layer.near,
                offset: i as u64 * layer_bytes,
            })
            .collect()
    }
}

/// Views drawn together (the faces of a light's shadow map, the layers of reflective shadow
/// maps): one clear, one thread per triangle and view, one shared list of big triangles. Each
/// view writes `width × height` packed `u64` texels, row-major, from its byte offset in
/// `target`.
pub struct RasterViews {
    uniforms: Vec<ViewUniform>,
    /// What each view sees and bytes `start..end` of `target` it covers.
    views: Vec<(Casters, (u64, u64))>,
    entries: wgpu::Buffer,
    /// The layers of every view.
    pub target: wgpu::Buffer,
    args: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
    args_group: wgpu::BindGroup,
    /// Most triangles any view draws.
    triangles: u32,
}

impl RasterViews {
    /// Number of views.
    pub fn len(&self) -> usize {
        self.uniforms.len()
    }

    /// Whether the set has no views.
    pub fn is_empty(&self) -> bool {
        self.uniforms.is_empty()
    }

    /// (width, height) in texels of view `i`.
    pub fn size(&self, i: usize) -> (u32, u32) {
        (self.uniforms[i].size.x, self.uniforms[i].size.y)
    }

    /// Draws only what lies on the positive side of the world-space `plane`
    /// (`dot(plane.xyz, p) + plane.w > 0`; `Vec4::W`, the default, keeps everything). Call
    /// before `set_clip_from_world`, which uploads both.
    pub fn set_clip_plane(&mut self, i: usize, plane: Vec4) {
        self.uniforms[i].clip_plane = plane;
    }

    /// Moves the views made by [`ViewSpec::of_layers`] to their layers' projections (moving
    /// lights), in one upload; takes effect at the next frame.
    pub fn set_layers(&mut self, queue: &wgpu::Queue, layers: &[ShadowLayer]) {
        for (uniform, layer) in self.uniforms.iter_mut().zip(layers) {
            uniform.clip_from_world = layer.clip_from_world;
        }
        if !self.uniforms.is_empty() {
            queue.write_buffer(&self.entries, 0, bytemuck::cast_slice(&self.uniforms));
        }
    }

    /// Changes view `i`'s projection (a moving camera or light); takes effect at the next
    /// frame.
    pub fn set_clip_from_world(&mut self, queue: &wgpu::Queue, i: usize, clip_from_world: Mat4) {
        self.uniforms[i].clip_from_world = clip_from_world;
        let at = (i * std::mem::size_of::<ViewUniform>()) as u64;
        queue.write_buffer(&self.entries, at, bytemuck::bytes_of(&self.uniforms[i]));
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
                bind::storage(0, cs),
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
        // cs_big's dispatch (x: the big triangles, counted by cs_small) and the kind of view
        // cs_small leaves as it is, one set of four words per `Skip`.
        let args_init: Vec<u32> = [Skip::None, Skip::RealOnly, Skip::VirtualOnly]
            .iter()
            .flat_map(|&s| [0, BIG_TILE_STRIDE, 1, s as u32])
            .collect();
        let args_init = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("raster/args_init"),
            contents: bytemuck::cast_slice(&args_init),
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

    /// One view of `size` texels seeing `casters` through `clip_from_world` (`near`: see
    /// [`ViewSpec`]) into a target of its own.
    #[allow(clippy::too_many_arguments, reason = "a view is these facts")]
    pub fn view(
        &self,
        ctx: &GpuContext,
        geometry: &Geometry,
        label: &str,
        size: (u32, u32),
        casters: Casters,
        clip_from_world: Mat4,
        near: f32,
    ) -> RasterViews {
        let spec = ViewSpec { size, casters, clip_from_world, near, offset: 0 };
        self.views(ctx, geometry, label, None, &[spec])
    }

    /// Views drawn together into `target` at their offsets, or into a buffer of their own
    /// that holds them all.
    pub fn views(
        &self,
        ctx: &GpuContext,
        geometry: &Geometry,
        label: &str,
        target: Option<&wgpu::Buffer>,
        specs: &[ViewSpec],
    ) -> RasterViews {
        let device = &ctx.device;
        let all = self.triangle_count;
        let capacity = BIG_CAPACITY * (specs.len() as u32).clamp(1, 4);
        let mut spans = Vec::new();
        let uniforms: Vec<ViewUniform> = specs
            .iter()
            .map(|spec| {
                // (filter, first triangle, triangle count, keep the farthest)
                let (filter, first, triangles, farthest) = match spec.casters {
                    Casters::All => (0, 0, all, 0.0),
                    Casters::Only(Realness::Real) => (1, 0, all, 0.0),
                    Casters::Only(Realness::Virtual) => (2, 0, all, 0.0),
                    Casters::Range { first, count } => (0, first, count, 0.0),
                    Casters::FarthestOf { first, count } => (0, first, count, 1.0),
                };
                let bytes = spec.size.0 as u64 * spec.size.1 as u64 * 8;
                spans.push((spec.casters, (spec.offset, spec.offset + bytes)));
                ViewUniform {
                    clip_from_world: spec.clip_from_world,
                    size: UVec4::new(spec.size.0, spec.size.1, filter, first + triangles),
                    limits: UVec4::new(capacity, SMALL_TRIANGLE_PIXELS, BIG_TILE_STRIDE, first),
                    params: Vec4::new(spec.near, farthest, 0.0, 0.0),
                    clip_plane: Vec4::W,
                    layer: UVec4::new((spec.offset / 8) as u32, 0, 0, 0),
                }
            })
            .collect();
        let span_end = spans.iter().map(|(_, (_, end))| *end).max().unwrap_or(0);
        let triangles = uniforms.iter().map(|u| u.size.w - u.limits.w).max().unwrap_or(0);
        let mut entries_contents = uniforms.clone();
        entries_contents.resize(uniforms.len().max(1), ViewUniform::zeroed());
        let entries = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(&format!("{label}/views")),
            contents: bytemuck::cast_slice(&entries_contents),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
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
        let target = match target {
            Some(buffer) => buffer.clone(),
            None => buffer("target", span_end.max(8), storage | wgpu::BufferUsages::COPY_SRC),
        };
        let big = buffer("big_triangles", capacity as u64 * BIG_RECORD_BYTES, storage);
        let args = buffer("big_args", ARGS_BYTES, storage | wgpu::BufferUsages::INDIRECT);
        let bind_group = bind::group(
            device,
            &format!("{label}/bind_group"),
            &self.layout,
            &[
                entries.as_entire_binding(),
                geometry.instances.as_entire_binding(),
                geometry.vertices.as_entire_binding(),
                geometry.indices.as_entire_binding(),
                geometry.triangles.as_entire_binding(),
                target.as_entire_binding(),
                big.as_entire_binding(),
            ],
        );
        let args_group =
            bind::group(device, &format!("{label}/args_group"), &self.args_layout, &[args.as_entire_binding()]);
        RasterViews { uniforms, views: spans, entries, target, args, bind_group, args_group, triangles }
    }

    /// Clears and rasterises every view of `sets`, timed as one pass named `label`.
    pub fn record<'a>(&self, rec: &mut Recorder, label: &str, sets: impl IntoIterator<Item = &'a RasterViews>) {
        self.record_moved(rec, label, sets.into_iter().map(|s| (s, Moved::ALL)));
    }

    /// Clears and rasterises, in one pass named `label`, the views of each set that see
    /// casters of a kind that moved for it: a view of real casters alone keeps its texels
    /// when only virtual instances moved (a virtual object that turns in front of a static
    /// room redraws only half of each light's shadow layers). Views of every caster, or of an
    /// instance's triangles, are redrawn when anything moved.
    pub fn record_moved<'a>(
        &self,
        rec: &mut Recorder,
        label: &str,
        sets: impl IntoIterator<Item = (&'a RasterViews, Moved)>,
    ) {
        let sets: Vec<&RasterViews> = sets
            .into_iter()
            .filter(|(s, moved)| !s.is_empty() && moved.any())
            .map(|(s, moved)| {
                let skip = match (moved.of(Realness::Real), moved.of(Realness::Virtual)) {
                    (true, false) => Skip::VirtualOnly,
                    (false, true) => Skip::RealOnly,
                    _ => Skip::None,
                };
                for (start, end) in spans_to_clear(&s.views, skip) {
                    rec.encoder.clear_buffer(&s.target, start, Some(end - start));
                }
                rec.encoder.copy_buffer_to_buffer(&self.args_init, skip as u64 * ARGS_BYTES, &s.args, 0, ARGS_BYTES);
                s
            })
            .collect();
        if sets.is_empty() {
            return;
        }
        rec.compute(label, |pass| {
            pass.set_pipeline(&self.small);
            for s in &sets {
                pass.set_bind_group(0, &s.bind_group, &[]);
                pass.set_bind_group(1, &s.args_group, &[]);
                let groups = s.triangles.max(1).div_ceil(64);
                let max = mrshade_gpu::shader::MAX_WORKGROUPS_PER_DIMENSION;
                pass.dispatch_workgroups(groups.min(max), groups.div_ceil(max), s.len() as u32);
            }
            pass.set_pipeline(&self.big);
            for s in &sets {
                pass.set_bind_group(0, &s.bind_group, &[]);
                pass.dispatch_workgroups_indirect(&s.args, 0);
            }
        });
    }
}

/// Bytes of a set's `big_args` (raster.wgsl): cs_big's dispatch and the kind of view to skip.
const ARGS_BYTES: u64 = 16;

/// The views a draw leaves as they are (the filter values of raster.wgsl `RasterView.size.z`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Skip {
    None = 0,
    RealOnly = 1,
    VirtualOnly = 2,
}

impl Skip {
    /// Whether a view of `casters` keeps its texels.
    fn keeps(self, casters: Casters) -> bool {
        matches!(
            (self, casters),
            (Skip::RealOnly, Casters::Only(Realness::Real)) | (Skip::VirtualOnly, Casters::Only(Realness::Virtual))
        )
    }
}

/// The byte ranges of a set's target to clear before the views that `skip` does not keep
/// are drawn (`views`: what each sees and the bytes it covers): runs of neighbouring views in
/// one range (one fill instead of one per view: the probe's maps are 64 views).
fn spans_to_clear(views: &[(Casters, (u64, u64))], skip: Skip) -> Vec<(u64, u64)> {
    let mut views: Vec<(bool, (u64, u64))> = views.iter().map(|&(casters, span)| (skip.keeps(casters), span)).collect();
    views.sort_by_key(|&(_, (start, _))| start);
    let mut spans: Vec<(u64, u64)> = Vec::new();
    // Whether the last view was cleared: this one then extends its range.
    let mut run_open = false;
    for (kept, (start, end)) in views {
        if kept {
            run_open = false;
            continue;
        }
        match spans.last_mut() {
            Some(last) if run_open => last.1 = last.1.max(end),
            _ => spans.push((start, end)),
        }
        run_open = true;
    }
    spans
}

/// The composed WGSL module.
pub const SHADER: &str = wgsl!(
    "../../shaders/lib/gbuffer.wgsl",
    "../../shaders/lib/instance.wgsl",
    "../../shaders/lib/raster_common.wgsl",
    "raster.wgsl",
);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_views_drawn_again_are_cleared_in_runs_and_the_kept_ones_not() {
        let real = Casters::Only(Realness::Real);
        let inserted = Casters::Only(Realness::Virtual);
        // A point light's layers: real faces, then virtual ones; a gap after the last.
        let views: Vec<(Casters, (u64, u64))> = [real, real, inserted, inserted]
            .iter()
            .enumerate()
            .map(|(i, &c)| (c, (i as u64 * 8, i as u64 * 8 + 8)))
            .collect();
        assert_eq!(spans_to_clear(&views, Skip::None), vec![(0, 32)]);
        assert_eq!(spans_to_clear(&views, Skip::RealOnly), vec![(16, 32)]);
        assert_eq!(spans_to_clear(&views, Skip::VirtualOnly), vec![(0, 16)]);
        // Pairs of layers, light by light (the probe's maps): every other view kept.
        let pairs: Vec<(Casters, (u64, u64))> = [real, inserted, real, inserted]
            .iter()
            .enumerate()
            .map(|(i, &c)| (c, (i as u64 * 8, i as u64 * 8 + 8)))
            .collect();
        assert_eq!(spans_to_clear(&pairs, Skip::RealOnly), vec![(8, 16), (24, 32)]);
        // Views of every caster are never kept.
        assert_eq!(spans_to_clear(&[(Casters::All, (0, 8))], Skip::RealOnly), vec![(0, 8)]);
    }
}
