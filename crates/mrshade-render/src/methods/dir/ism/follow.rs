//! ISM points on skinned and morphing instances follow their surface: after the deformation
//! pass moved the vertices, every anchored point ([`PointAnchor`]) is re-evaluated from its
//! triangle's corners, so imperfect shadow maps and the multiple-bounce VPL candidates see the
//! deformed object (Knecht §2.9 samples the points once, on rigid objects). Runs only in
//! frames whose vertices were deformed.

use crate::methods::dir::points::PointAnchor;
use crate::scene_gpu::Geometry;
use mrshade_gpu::timing::Recorder;
use mrshade_gpu::{GpuContext, bind, wgsl};
use mrshade_scene::Scene;
use wgpu::util::DeviceExt;

/// The pass's WGSL.
pub const FOLLOW_SHADER: &str = wgsl!("follow.wgsl");

/// The follow pass of one point cloud.
pub struct FollowPass {
    pipeline: wgpu::ComputePipeline,
    group: wgpu::BindGroup,
    count: u32,
}

impl FollowPass {
    /// GPU timing label.
    pub const LABEL: &'static str = "ism/follow";

    /// Binds the anchors of `cloud` (`points`, on `scene`'s instances) to the scene's deformed
    /// vertices; `None` when no point lies on a deformable instance.
    pub fn new(
        ctx: &GpuContext,
        label: &str,
        scene: &Scene,
        geometry: &Geometry,
        anchors: &[PointAnchor],
        points: &wgpu::Buffer,
    ) -> Option<Self> {
        if anchors.is_empty() {
            return None;
        }
        let device = &ctx.device;
        // Corners become indices into the scene's vertex buffer.
        let global: Vec<PointAnchor> = anchors
            .iter()
            .map(|a| {
                let base = geometry.base_vertex[scene.instances[a.instance as usize].primitive];
                let mut global = *a;
                global.corners = a.corners.map(|c| c + base);
                global
            })
            .collect();
        let anchors_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(&format!("{label}/anchors")),
            contents: bytemuck::cast_slice(&global),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(&format!("{label}/params")),
            contents: bytemuck::cast_slice(&[global.len() as u32, 0, 0, 0]),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let cs = wgpu::ShaderStages::COMPUTE;
        let layout = bind::layout(
            device,
            &format!("{label}/layout"),
            &[bind::storage(0, cs), bind::storage(1, cs), bind::storage_rw(2, cs), bind::uniform(3, cs)],
        );
        let group = bind::group(
            device,
            &format!("{label}/group"),
            &layout,
            &[
                geometry.vertices.as_entire_binding(),
                anchors_buffer.as_entire_binding(),
                points.as_entire_binding(),
                params.as_entire_binding(),
            ],
        );
        let pipeline = mrshade_gpu::shader::compute_pipeline(device, label, FOLLOW_SHADER, &[&layout]);
        Some(Self { pipeline, group, count: global.len() as u32 })
    }

    /// Moves the anchored points onto the deformed surface.
    pub fn record(&self, rec: &mut Recorder) {
        rec.compute(Self::LABEL, |pass| {
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &self.group, &[]);
            mrshade_gpu::shader::dispatch_linear(pass, self.count, 64);
        });
    }
}
