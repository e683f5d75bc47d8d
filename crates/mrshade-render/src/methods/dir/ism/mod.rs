//! Imperfect shadow maps (Knecht §2.9): two atlases of one small depth map per VPL, one
//! splatted from points on real surfaces, one from points on virtual surfaces (VPLs can lie
//! on either, so every VPL needs `V_r` and `V_v`). Inputs: the VPLs, the point clouds.
//! Output: the atlases.

mod follow;

use crate::methods::dir::{GpuPoint, PointCloud};
use crate::scene_gpu::Geometry;
use bytemuck::{Pod, Zeroable};
pub use follow::FOLLOW_SHADER;
use follow::FollowPass;
use glam::{UVec4, Vec4};
use mrshade_core::flags::Realness;
use mrshade_core::settings::DirSettings;
use mrshade_gpu::timing::{Dispatch, Recorder};
use mrshade_gpu::{GpuContext, bind, wgsl};
use mrshade_scene::Scene;
use wgpu::util::DeviceExt;

/// Mirrors `IsmParams` in shaders/lib/ism.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct IsmParams {
    /// Tile resolution, tiles per atlas row, VPL count, points per VPL.
    pub tile: UVec4,
    /// Bounding sphere of the real points: centre, radius.
    pub scene: Vec4,
    /// Bounding sphere of the virtual objects (follows them when they move).
    pub scene_virtual: Vec4,
    /// Splat half-size of real and virtual points (m), relative depth bias, receiver offset
    /// in splat half-sizes.
    pub splat: Vec4,
}

/// The point clouds and the two atlases.
pub struct IsmResources {
    /// The constants of every ISM shader.
    pub params: IsmParams,
    /// `params` on the GPU.
    pub params_buffer: wgpu::Buffer,
    /// Points on real surfaces.
    pub points_real: wgpu::Buffer,
    /// Points on virtual surfaces.
    pub points_virtual: wgpu::Buffer,
    /// Number of real points.
    pub real_count: u32,
    /// Number of virtual points.
    pub virtual_count: u32,
    /// Surface areas sampled by the two clouds (m²).
    pub areas: (f32, f32),
    /// Bounding sphere of the virtual points at load time.
    points_sphere: Vec4,
    /// Sphere of the box around the virtual objects at the first frame.
    first_virtual_box: Option<Vec4>,
    /// ISM atlas of the real points.
    pub atlas_real: wgpu::Buffer,
    /// ISM atlas of the virtual points.
    pub atlas_virtual: wgpu::Buffer,
    /// Moves the points on skinned and morphing instances (real cloud, virtual cloud).
    follow: [Option<FollowPass>; 2],
}

impl IsmResources {
    /// Builds the point clouds of `scene` and allocates the atlases.
    pub fn new(
        ctx: &GpuContext,
        scene: &Scene,
        geometry: &Geometry,
        settings: &DirSettings,
        center: glam::Vec3,
        radius: f32,
    ) -> Self {
        let device = &ctx.device;
        let count = (settings.vpl_count * settings.points_per_vpl) as usize;
        let per_vpl = settings.points_per_vpl as usize;
        let real = PointCloud::new(scene, Realness::Real, count, per_vpl);
        let virt = PointCloud::new(scene, Realness::Virtual, count, per_vpl);
        let tiles_per_row = (settings.vpl_count as f32).sqrt().ceil() as u32;
        let side = tiles_per_row * settings.ism_resolution;
        // A point stands for area / points_per_vpl of its cloud within one VPL's map.
        let half_size = |area: f32| (area / settings.points_per_vpl as f32).sqrt() * 0.5 * settings.splat_scale;
        let params = IsmParams {
            tile: UVec4::new(settings.ism_resolution, tiles_per_row, settings.vpl_count, settings.points_per_vpl),
            scene: bounding_sphere(&real.points, scene).unwrap_or(center.extend(radius)),
            scene_virtual: bounding_sphere(&virt.points, scene).unwrap_or(center.extend(radius)),
            splat: Vec4::new(half_size(real.area), half_size(virt.area), settings.ism_bias, settings.ism_normal_offset),
        };
        let points = |label: &str, cloud: &PointCloud| {
            let mut pts = cloud.points.clone();
            if pts.is_empty() {
                pts.push(GpuPoint::zeroed());
            }
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: bytemuck::cast_slice(&pts),
                // Written by `FollowPass`; read back by tests.
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            })
        };
        let (points_real, points_virtual) = (points("ism/points_real", &real), points("ism/points_virtual", &virt));
        let follow = [
            FollowPass::new(ctx, "ism/follow_real", scene, geometry, &real.anchors, &points_real),
            FollowPass::new(ctx, "ism/follow_virtual", scene, geometry, &virt.anchors, &points_virtual),
        ];
        let atlas = |label: &str| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: side as u64 * side as u64 * 4,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            })
        };
        Self {
            params,
            params_buffer: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("ism/params"),
                contents: bytemuck::bytes_of(&params),
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            }),
            points_real,
            points_virtual,
            real_count: real.points.len() as u32,
            virtual_count: virt.points.len() as u32,
            areas: (real.area, virt.area),
            points_sphere: params.scene_virtual,
            first_virtual_box: None,
            atlas_real: atlas("ism/atlas_real"),
            atlas_virtual: atlas("ism/atlas_virtual"),
            follow,
        }
    }

    /// Moves the points on deformed instances onto their surface (in frames whose vertices
    /// the deformation pass moved).
    pub fn record_follow(&self, rec: &mut Recorder) {
        for pass in self.follow.iter().flatten() {
            pass.record(rec);
        }
    }

    /// Moves the virtual atlas's directional maps with the virtual objects: `virtual_box` is
    /// the box around them now (`None`: there are none). The sphere of their points at load
    /// time is shifted and scaled as that box moved and grew, so that a moved object keeps its
    /// probe shadows (and a still scene keeps the tighter sphere of its points).
    pub fn prepare(&mut self, queue: &wgpu::Queue, virtual_box: Option<(glam::Vec3, glam::Vec3)>) {
        let Some((lo, hi)) = virtual_box else { return };
        let now = sphere_of_box(lo, hi);
        let first = *self.first_virtual_box.get_or_insert(now);
        let sphere = (self.points_sphere.truncate() + now.truncate() - first.truncate())
            .extend(self.points_sphere.w * now.w / first.w);
        if sphere != self.params.scene_virtual {
            self.params.scene_virtual = sphere;
            queue.write_buffer(&self.params_buffer, 0, bytemuck::bytes_of(&self.params));
        }
    }

    /// Side of each square atlas in texels.
    pub fn atlas_side(&self) -> u32 {
        self.params.tile.x * self.params.tile.y
    }
}

/// Big-triangle records per atlas for the directional maps.
const BIG_CAPACITY: u64 = 65536;
/// Workgroups per big triangle.
const BIG_TILE_STRIDE: u32 = 16;

/// Splats both clouds (surface VPLs) and rasterises the triangles (directional VPLs).
pub struct IsmPass {
    pipeline: wgpu::ComputePipeline,
    /// One group per cloud and per VPL-buffer parity: `[parity][cloud]`.
    groups: [[wgpu::BindGroup; 2]; 2],
    counts: [u32; 2],
    raster_small: wgpu::ComputePipeline,
    raster_big: wgpu::ComputePipeline,
    /// `[parity][atlas]`.
    raster_groups: [[wgpu::BindGroup; 2]; 2],
    /// `[atlas]`: indirect arguments of `raster_big` (and the group that counts into them).
    raster_args: [(wgpu::Buffer, wgpu::BindGroup); 2],
    /// Empties the atlases and resets `raster_args` (clear.wgsl), before `record`.
    pub clear: Dispatch,
    triangle_count: u32,
    vpl_count: u32,
}

impl IsmPass {
    /// GPU timing label.
    pub const LABEL: &'static str = "ism";

    /// Builds the splat pipeline over `vpls` (the two VPL buffers of the ping-pong).
    pub fn new(ctx: &GpuContext, resources: &IsmResources, geometry: &Geometry, vpls: &[wgpu::Buffer; 2]) -> Self {
        let device = &ctx.device;
        let cs = wgpu::ShaderStages::COMPUTE;
        let layout = bind::layout(
            device,
            "ism/layout",
            &[
                bind::uniform(0, cs),
                bind::uniform(1, cs),
                bind::storage(2, cs),
                bind::storage(3, cs),
                bind::storage(4, cs),
                bind::storage_rw(5, cs),
            ],
        );
        let clouds = [
            (&resources.points_real, resources.real_count, &resources.atlas_real, 0u32),
            (&resources.points_virtual, resources.virtual_count, &resources.atlas_virtual, 1),
        ];
        let group = |parity: usize, cloud: usize| {
            let (points, count, atlas, is_virtual) = clouds[cloud];
            let info = UVec4::new(count, is_virtual, 0, 0);
            let splat = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("ism/splat_params"),
                contents: bytemuck::bytes_of(&info),
                usage: wgpu::BufferUsages::UNIFORM,
            });
            bind::group(
                device,
                &format!("ism/group{parity}{cloud}"),
                &layout,
                &[
                    resources.params_buffer.as_entire_binding(),
                    splat.as_entire_binding(),
                    geometry.instances.as_entire_binding(),
                    points.as_entire_binding(),
                    vpls[parity].as_entire_binding(),
                    atlas.as_entire_binding(),
                ],
            )
        };
        let raster_layout = bind::layout(
            device,
            "ism/raster_layout",
            &[
                bind::uniform(0, cs),
                bind::uniform(1, cs),
                bind::storage(2, cs),
                bind::storage(3, cs),
                bind::storage(4, cs),
                bind::storage(5, cs),
                bind::storage(6, cs),
                bind::storage_rw(7, cs),
                bind::storage_rw(8, cs),
            ],
        );
        let args_layout = bind::layout(device, "ism/raster_args_layout", &[bind::storage_rw(0, cs)]);
        let atlases = [&resources.atlas_real, &resources.atlas_virtual];
        let raster_args = [0, 1].map(|a| {
            let args = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("ism/raster_args"),
                size: 12,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::INDIRECT | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let group =
                bind::group(device, &format!("ism/raster_args_group{a}"), &args_layout, &[args.as_entire_binding()]);
            (args, group)
        });
        let big = [0, 1].map(|a| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(&format!("ism/raster_big{a}")),
                size: BIG_CAPACITY * crate::raster::BIG_RECORD_BYTES,
                usage: wgpu::BufferUsages::STORAGE,
                mapped_at_creation: false,
            })
        });
        let raster_group = |parity: usize, atlas: usize| {
            let info = UVec4::new(geometry.triangle_count, atlas as u32, BIG_CAPACITY as u32, BIG_TILE_STRIDE);
            let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("ism/raster_params"),
                contents: bytemuck::bytes_of(&info),
                usage: wgpu::BufferUsages::UNIFORM,
            });
            bind::group(
                device,
                &format!("ism/raster_group{parity}{atlas}"),
                &raster_layout,
                &[
                    resources.params_buffer.as_entire_binding(),
                    params.as_entire_binding(),
                    geometry.instances.as_entire_binding(),
                    geometry.vertices.as_entire_binding(),
                    geometry.indices.as_entire_binding(),
                    geometry.triangles.as_entire_binding(),
                    vpls[parity].as_entire_binding(),
                    atlases[atlas].as_entire_binding(),
                    big[atlas].as_entire_binding(),
                ],
            )
        };
        let raster = |entry: &str, layouts: &[&wgpu::BindGroupLayout]| {
            mrshade_gpu::shader::compute_pipeline_entry(
                device,
                &format!("ism/raster_{entry}"),
                RASTER_SHADER,
                entry,
                layouts,
            )
        };
        let args_init = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("ism/raster_args_init"),
            contents: bytemuck::cast_slice(&[0u32, BIG_TILE_STRIDE, 1]),
            usage: wgpu::BufferUsages::STORAGE,
        });
        // Both atlases and both arguments written, the arguments' initial values read.
        let mut clear_entries: Vec<_> = (0..4).map(|i| bind::storage_rw(i, cs)).collect();
        clear_entries.push(bind::storage(4, cs));
        let clear_layout = bind::layout(device, "ism/clear", &clear_entries);
        let clear_group = bind::group(
            device,
            "ism/clear",
            &clear_layout,
            &[&resources.atlas_real, &resources.atlas_virtual, &raster_args[0].0, &raster_args[1].0, &args_init]
                .map(|b| b.as_entire_binding()),
        );
        let clear = Dispatch {
            pipeline: mrshade_gpu::shader::compute_pipeline(device, "ism/clear", CLEAR_SHADER, &[&clear_layout]),
            groups: vec![clear_group],
            workgroups: [CLEAR_GROUPS, 1, 1],
        };
        Self {
            pipeline: mrshade_gpu::shader::compute_pipeline(device, "ism/splat", SHADER, &[&layout]),
            groups: [[group(0, 0), group(0, 1)], [group(1, 0), group(1, 1)]],
            counts: [resources.real_count, resources.virtual_count],
            raster_small: raster("cs_small", &[&raster_layout, &args_layout]),
            raster_big: raster("cs_big", &[&raster_layout]),
            raster_groups: [[raster_group(0, 0), raster_group(0, 1)], [raster_group(1, 0), raster_group(1, 1)]],
            raster_args,
            clear,
            triangle_count: geometry.triangle_count,
            vpl_count: resources.params.tile.z,
        }
    }

    /// Splats the points of the surface VPLs and rasterises the maps of the directional VPLs
    /// in buffer `parity` (into atlases that `clear` emptied).
    pub fn record(&self, rec: &mut Recorder, parity: usize) {
        // Hosts the specular rays (`Recorder::compute_hosting`): beside its last dispatch,
        // the point splat, they cost least of the method's passes (H200, 1080p: 0.14 ms
        // saved; beside `indirect` 0.03).
        rec.compute_hosting(Self::LABEL, |pass| {
            if self.triangle_count > 0 {
                pass.set_pipeline(&self.raster_small);
                for atlas in 0..2 {
                    pass.set_bind_group(0, &self.raster_groups[parity][atlas], &[]);
                    pass.set_bind_group(1, &self.raster_args[atlas].1, &[]);
                    pass.dispatch_workgroups(self.triangle_count.div_ceil(64), self.vpl_count, 1);
                }
                pass.set_pipeline(&self.raster_big);
                for atlas in 0..2 {
                    pass.set_bind_group(0, &self.raster_groups[parity][atlas], &[]);
                    pass.dispatch_workgroups_indirect(&self.raster_args[atlas].0, 0);
                }
            }
            pass.set_pipeline(&self.pipeline);
            for (cloud, &count) in self.counts.iter().enumerate() {
                if count == 0 {
                    continue;
                }
                pass.set_bind_group(0, &self.groups[parity][cloud], &[]);
                mrshade_gpu::shader::dispatch_linear(pass, count, 64);
            }
        });
    }
}

/// Workgroups of the atlases' clear (`CLEAR_GROUPS` in clear.wgsl).
pub const CLEAR_GROUPS: u32 = 1024;
/// The atlases' clear module.
pub const CLEAR_SHADER: &str = wgsl!("clear.wgsl");

/// The directional-map rasteriser module.
pub const RASTER_SHADER: &str = wgsl!(
    "../../../../shaders/lib/frame.wgsl",
    "../../../../shaders/lib/gbuffer.wgsl",
    "../../../../shaders/lib/brdf.wgsl",
    "../../../../shaders/lib/instance.wgsl",
    "../../../../shaders/lib/sampling.wgsl",
    "../../../../shaders/lib/vpl.wgsl",
    "../../../../shaders/lib/ism.wgsl",
    "../../../../shaders/lib/raster_common.wgsl",
    "raster.wgsl",
);

/// The splat module.
pub const SHADER: &str = wgsl!(
    "../../../../shaders/lib/frame.wgsl",
    "../../../../shaders/lib/gbuffer.wgsl",
    "../../../../shaders/lib/brdf.wgsl",
    "../../../../shaders/lib/instance.wgsl",
    "../../../../shaders/lib/sampling.wgsl",
    "../../../../shaders/lib/vpl.wgsl",
    "../../../../shaders/lib/ism.wgsl",
    "splat.wgsl",
);

/// Centre and radius of the box around `points` (world space), padded by 1 %.
fn bounding_sphere(points: &[GpuPoint], scene: &Scene) -> Option<Vec4> {
    let mut lo = glam::Vec3::splat(f32::INFINITY);
    let mut hi = glam::Vec3::splat(f32::NEG_INFINITY);
    for p in points {
        let w = scene.instances[p.instance as usize].world_from_object.transform_point3(p.position.into());
        lo = lo.min(w);
        hi = hi.max(w);
    }
    (lo.x <= hi.x).then(|| sphere_of_box(lo, hi))
}

/// The sphere through the corners of box `(lo, hi)`, padded by 1 %.
fn sphere_of_box(lo: glam::Vec3, hi: glam::Vec3) -> Vec4 {
    ((lo + hi) * 0.5).extend(((hi - lo).length() * 0.5).max(1e-3) * 1.01)
}
