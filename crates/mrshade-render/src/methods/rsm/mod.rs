//! Reflective shadow maps (Knecht §2.8; Franke §2.0.2 and §2.12.2 for `dlpv`): each light layer (the same projections as the
//! shadow maps, at `dir.rsm_resolution`) is rasterised, resolved into surface, material and
//! received power per texel, and reduced into an importance pyramid for VPL placement.
//! Real lights keep a real-only and a virtual-only RSM; so do virtual ones here (their
//! union is the single RSM of the thesis, and the split costs nothing extra).

use crate::limits::Fit;
use crate::raster::{RasterViews, Rasterizer, ViewSpec};
use crate::scene_gpu::{GpuMaterials, GpuScene, Moved, ShadowLayer};
use anyhow::{Result, bail};
use bytemuck::{Pod, Zeroable};
use glam::{UVec4, Vec4};
use mrshade_gpu::timing::Recorder;
use mrshade_gpu::{GpuContext, bind, wgsl};
use wgpu::util::DeviceExt;

/// Bytes of one `RsmTexel`.
pub const TEXEL_BYTES: u64 = 80;
/// Bytes of one texel's height toward its light (`RsmPass::heights`).
const HEIGHT_BYTES: u64 = 4;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct RsmParams {
    size: UVec4,
    scale: Vec4,
}

/// Halves `resolution` (the setting `name`) down to 32 until `layers` maps' texels fit one
/// buffer binding of the device.
pub(crate) fn fit_resolution(fit: &mut Fit, name: &str, layers: u64, resolution: &mut u32) -> Result<()> {
    let max_binding = fit.max_binding;
    let fits = |res: u64| layers * res * res * TEXEL_BYTES <= max_binding;
    if !fit.shrink(name, resolution, &fits, 32) {
        bail!("{layers} RSM layers ({name}) need more than one GPU buffer of this device holds even at 32×32");
    }
    Ok(())
}

/// GPU bytes of `layers` maps of side `resolution`: depth, texels, raster targets, views.
pub(crate) fn bytes(layers: u64, resolution: u32) -> u64 {
    let res = resolution as u64;
    layers * (res * res * (8 + TEXEL_BYTES + HEIGHT_BYTES + 11) + crate::limits::VIEW_BYTES)
}

/// The RSM of every light layer, with importance pyramids.
pub struct RsmPass {
    views: RasterViews,
    resolve: wgpu::ComputePipeline,
    resolve_groups: [wgpu::BindGroup; 2],
    base: wgpu::ComputePipeline,
    reduce: wgpu::ComputePipeline,
    level_groups: Vec<wgpu::BindGroup>,
    /// `layers × resolution²` RSM texels.
    pub texels: wgpu::Buffer,
    /// Per texel, how far toward its light the surface lies (f32; shaders/lib/lights.wgsl
    /// `rsm_height`): a depth map of 4 bytes a texel for shadow tests, which would otherwise
    /// read 80-byte texels for their positions.
    pub heights: wgpu::Buffer,
    /// Per layer, `pyramid_stride` (importance, coverage) pairs: every level, finest first.
    pub pyramid: wgpu::Buffer,
    /// Side of every layer.
    pub resolution: u32,
    /// Number of layers (same as the shadow layers).
    pub layers: u32,
    /// `world_from_clip` per layer, for unprojecting texels.
    world_from_clip: wgpu::Buffer,
    /// Pairs per layer in `pyramid`.
    pub pyramid_stride: u32,
}

impl RsmPass {
    /// GPU timing label of the rasterisation.
    pub const RASTER_LABEL: &'static str = "rsm-raster";
    /// GPU timing label of resolve and pyramid.
    pub const LABEL: &'static str = "rsm";

    /// Builds the RSMs of `layers` at `resolution`, whose lights are in `lights` (the scene's
    /// own, or others such as `dlpv`'s lights of the probe).
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        ctx: &GpuContext,
        rasterizer: &Rasterizer,
        scene: &GpuScene,
        lights: &wgpu::Buffer,
        layers: &[ShadowLayer],
        resolution: u32,
        shadow_resolution: u32,
        caustic_vpls: bool,
    ) -> Self {
        let device = &ctx.device;
        let res = resolution;
        let count = layers.len().max(1) as u64;
        let texel_count = res as u64 * res as u64;
        let buffer = |label: &str, size: u64| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            })
        };
        let visibility = buffer("rsm/visibility", count * texel_count * 8);
        let views = rasterizer.views(ctx, &scene.geometry, "rsm", Some(&visibility), &ViewSpec::of_layers(layers, res));
        let levels = res.ilog2() + 1;
        let pyramid_stride: u32 = (0..levels).map(|l| (res >> l) * (res >> l)).sum();
        let texels = buffer("rsm/texels", count * texel_count * TEXEL_BYTES);
        let heights = buffer("rsm/heights", count * texel_count * HEIGHT_BYTES);
        let pyramid = buffer("rsm/pyramid", count * pyramid_stride as u64 * 8);

        let storage = |label: &str, contents: &[u8]| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage: wgpu::BufferUsages::STORAGE,
            })
        };
        let mut world_from_clip: Vec<glam::Mat4> = layers.iter().map(|l| l.clip_from_world.inverse()).collect();
        let mut layer_light: Vec<u32> = layers.iter().map(|l| l.light).collect();
        world_from_clip.resize(world_from_clip.len().max(1), glam::Mat4::IDENTITY);
        layer_light.resize(layer_light.len().max(1), 0);
        let params = RsmParams {
            size: UVec4::new(res, layers.len() as u32, caustic_vpls as u32, 0),
            scale: Vec4::new(shadow_resolution as f32 / res as f32, 0.0, 0.0, 0.0),
        };
        let uniform = |label: &str, bytes: &[u8]| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: bytes,
                usage: wgpu::BufferUsages::UNIFORM,
            })
        };
        let cs = wgpu::ShaderStages::COMPUTE;
        let rw = bind::storage_rw(10, cs);
        let mut entries: Vec<wgpu::BindGroupLayoutEntry> = vec![bind::uniform(0, cs)];
        entries.extend((1..10).map(|b| bind::storage(b, cs)));
        entries.push(rw);
        entries.push(bind::storage_rw(11, cs));
        let resolve_layout = bind::layout(device, "rsm/resolve_layout", &entries);
        let texture_layout = bind::layout(device, "rsm/texture_layout", &GpuMaterials::texture_entries(0, cs));
        let g = &scene.geometry;
        let m = &scene.materials;
        let params_buffer = uniform("rsm/params", bytemuck::bytes_of(&params));
        let world_from_clip = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("rsm/world_from_clip"),
            contents: bytemuck::cast_slice(&world_from_clip),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        });
        let layer_light = storage("rsm/layer_light", bytemuck::cast_slice(&layer_light));
        let resolve_groups = [
            bind::group(
                device,
                "rsm/resolve_group",
                &resolve_layout,
                &[
                    params_buffer.as_entire_binding(),
                    g.instances.as_entire_binding(),
                    g.vertices.as_entire_binding(),
                    g.indices.as_entire_binding(),
                    g.triangles.as_entire_binding(),
                    m.buffer.as_entire_binding(),
                    lights.as_entire_binding(),
                    world_from_clip.as_entire_binding(),
                    layer_light.as_entire_binding(),
                    visibility.as_entire_binding(),
                    texels.as_entire_binding(),
                    heights.as_entire_binding(),
                ],
            ),
            bind::group(device, "rsm/texture_group", &texture_layout, &m.texture_resources()),
        ];
        let resolve = mrshade_gpu::shader::compute_pipeline(
            device,
            "rsm/resolve",
            RESOLVE_SHADER,
            &[&resolve_layout, &texture_layout],
        );

        let pyramid_layout = bind::layout(
            device,
            "rsm/pyramid_layout",
            &[bind::uniform(0, cs), bind::storage(1, cs), bind::storage_rw(2, cs)],
        );
        let level_groups = (0..levels)
            .map(|level| {
                let p = UVec4::new(res, layers.len() as u32, level, pyramid_stride);
                let u = uniform(&format!("rsm/pyramid_level{level}"), bytemuck::bytes_of(&p));
                bind::group(
                    device,
                    &format!("rsm/pyramid_group{level}"),
                    &pyramid_layout,
                    &[u.as_entire_binding(), texels.as_entire_binding(), pyramid.as_entire_binding()],
                )
            })
            .collect();
        let base = mrshade_gpu::shader::compute_pipeline_entry(
            device,
            "rsm/pyramid_base",
            PYRAMID_SHADER,
            "cs_base",
            &[&pyramid_layout],
        );
        let reduce = mrshade_gpu::shader::compute_pipeline_entry(
            device,
            "rsm/pyramid_reduce",
            PYRAMID_SHADER,
            "cs_reduce",
            &[&pyramid_layout],
        );
        Self {
            world_from_clip,
            views,
            resolve,
            resolve_groups,
            base,
            reduce,
            level_groups,
            texels,
            heights,
            pyramid,
            resolution: res,
            layers: layers.len() as u32,
            pyramid_stride,
        }
    }

    /// Moves the layers' projections to `layers` (moving lights); the next frame draws them.
    pub fn set_layers(&mut self, queue: &wgpu::Queue, layers: &[ShadowLayer]) {
        self.views.set_layers(queue, layers);
        let world_from_clip: Vec<glam::Mat4> = layers.iter().map(|l| l.clip_from_world.inverse()).collect();
        if !world_from_clip.is_empty() {
            queue.write_buffer(&self.world_from_clip, 0, bytemuck::cast_slice(&world_from_clip));
        }
    }

    /// Rasterises the layers of the casters that `moved` (`Moved::ALL` after a light moved),
    /// resolves and reduces every layer.
    pub fn record(&self, rec: &mut Recorder, rasterizer: &Rasterizer, moved: Moved) {
        Self::record_sets(rec, rasterizer, &[(self, moved)], true);
    }

    /// Rasterises the layers of each set's casters that moved (the others keep their texels:
    /// `Rasterizer::record_moved`), resolves every layer (the same texels again where nothing
    /// moved), and reduces it into the flux pyramid if `pyramid` (the VPL sampler's;
    /// injecting every texel needs none: ten tiny dispatches per set of maps). The sets share
    /// one raster pass and one resolve pass: their dispatches do not wait for each other.
    pub fn record_sets(rec: &mut Recorder, rasterizer: &Rasterizer, sets: &[(&RsmPass, Moved)], pyramid: bool) {
        let sets: Vec<(&RsmPass, Moved)> =
            sets.iter().copied().filter(|(s, m)| !s.views.is_empty() && m.any()).collect();
        if sets.is_empty() {
            return;
        }
        rasterizer.record_moved(rec, Self::RASTER_LABEL, sets.iter().map(|(s, moved)| (&s.views, *moved)));
        rec.compute(Self::LABEL, |pass| {
            for (set, _) in &sets {
                set.record_resolve(pass, pyramid);
            }
        });
    }

    fn record_resolve(&self, pass: &mut wgpu::ComputePass<'_>, pyramid: bool) {
        let groups = self.resolution.div_ceil(8);
        pass.set_pipeline(&self.resolve);
        pass.set_bind_group(0, &self.resolve_groups[0], &[]);
        pass.set_bind_group(1, &self.resolve_groups[1], &[]);
        pass.dispatch_workgroups(groups, groups, self.layers);
        if !pyramid {
            return;
        }
        pass.set_pipeline(&self.base);
        pass.set_bind_group(0, &self.level_groups[0], &[]);
        pass.dispatch_workgroups(groups, groups, self.layers);
        pass.set_pipeline(&self.reduce);
        for (level, group) in self.level_groups.iter().enumerate().skip(1) {
            let side = (self.resolution >> level).div_ceil(8);
            pass.set_bind_group(0, group, &[]);
            pass.dispatch_workgroups(side, side, self.layers);
        }
    }
}

/// The resolve module.
pub const RESOLVE_SHADER: &str = wgsl!(
    "../../../shaders/lib/frame.wgsl",
    "../../../shaders/lib/gbuffer.wgsl",
    "../../../shaders/lib/instance.wgsl",
    "../../../shaders/lib/lights.wgsl",
    "../../../shaders/lib/triangles.wgsl",
    "../../../shaders/lib/material_textures.wgsl",
    "../../../shaders/lib/rsm_texel.wgsl",
    "resolve.wgsl",
);

/// The pyramid module.
pub const PYRAMID_SHADER: &str = wgsl!("../../../shaders/lib/rsm_texel.wgsl", "pyramid.wgsl");
