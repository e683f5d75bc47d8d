//! Interleaved indirect shading (Knecht §2.7, §2.10): every pixel evaluates its subset of the
//! VPLs with their ISM visibilities into `Differential { rv, r }`, plus the environment-VPL
//! visibility sums that shadow the probe's light. Inputs: G-buffer, VPLs, ISMs. Outputs:
//! [`IndirectLight`].

use crate::methods::IndirectLight;
use crate::methods::dir::ism::IsmResources;
use crate::passes::gbuffer::GBuffer;
use bytemuck::{Pod, Zeroable};
use glam::{UVec4, Vec4};
use mrshade_core::Differential;
use mrshade_core::settings::DirSettings;
use mrshade_gpu::timing::{Recorder, set_pipeline_and_groups};
use mrshade_gpu::{GpuContext, Target, bind, wgsl};
use wgpu::util::DeviceExt;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct IndirectParams {
    info: UVec4,
    values: Vec4,
    near: UVec4,
}

/// The interleaved shading pass.
pub struct IndirectPass {
    pipeline: wgpu::ComputePipeline,
    /// `[parity]`: group 0, group 1 (VPL buffer of that parity), groups 2 and 3.
    groups: [[wgpu::BindGroup; 4]; 2],
    size: (u32, u32),
}

impl IndirectPass {
    /// GPU timing label.
    pub const LABEL: &'static str = "indirect";

    /// Binds the G-buffer, VPLs and ISMs (VPLs lit closer than `d_min` metres light as if
    /// from `d_min`; multiple-bounce VPLs from `near_radius`, within which the previous
    /// frame's `previous_indirect` light is gathered from the screen); writes `out`. With
    /// `probe_caustics` the probe's light through transmissive casters is the specular
    /// stage's (photons), not the shadow's.
    #[allow(clippy::too_many_arguments, reason = "shading reads all of these")]
    pub fn new(
        ctx: &GpuContext,
        frame: &wgpu::Buffer,
        gbuffer: &GBuffer,
        materials: &wgpu::Buffer,
        vpls: &[wgpu::Buffer; 2],
        ism: &IsmResources,
        settings: &DirSettings,
        probe_caustics: bool,
        d_min: f32,
        near_radius: f32,
        previous_radiance: &Differential<Target>,
        previous_indirect: &Differential<Target>,
        out: &IndirectLight,
    ) -> Self {
        let device = &ctx.device;
        let cs = wgpu::ShaderStages::COMPUTE;
        let params = IndirectParams {
            info: UVec4::new(
                settings.interleave,
                ism.params.tile.z,
                settings.near_field_samples,
                probe_caustics as u32,
            ),
            values: Vec4::new(d_min, near_radius, 0.0, 0.0),
            near: UVec4::new(settings.near_field_bounce_samples, 0, 0, 0),
        };
        let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("indirect/params"),
            contents: bytemuck::bytes_of(&params),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let unfilterable = wgpu::TextureSampleType::Float { filterable: false };
        let d2 = wgpu::TextureViewDimension::D2;
        let (scene_layout, scene_group) =
            crate::methods::pixel_inputs(device, "indirect/scene", frame, &params, gbuffer, materials);
        let vpl_layout = bind::layout(
            device,
            "indirect/vpl_layout",
            &[bind::storage(0, cs), bind::uniform(1, cs), bind::storage(2, cs), bind::storage(3, cs)],
        );
        let out_layout = bind::layout(device, "indirect/out_layout", &IndirectLight::storage_entries());
        let previous_layout = bind::layout(
            device,
            "indirect/previous_layout",
            &(0..4).map(|i| bind::texture(i, cs, unfilterable, d2)).collect::<Vec<_>>(),
        );
        let previous_group = bind::group(
            device,
            "indirect/previous_group",
            &previous_layout,
            &[
                TextureView(&previous_radiance.rv.view),
                TextureView(&previous_radiance.r.view),
                TextureView(&previous_indirect.rv.view),
                TextureView(&previous_indirect.r.view),
            ],
        );
        use wgpu::BindingResource::TextureView;
        let groups = [0usize, 1].map(|parity| {
            [
                scene_group.clone(),
                bind::group(
                    device,
                    "indirect/vpl_group",
                    &vpl_layout,
                    &[
                        vpls[parity].as_entire_binding(),
                        ism.params_buffer.as_entire_binding(),
                        ism.atlas_real.as_entire_binding(),
                        ism.atlas_virtual.as_entire_binding(),
                    ],
                ),
                bind::group(device, "indirect/out_group", &out_layout, &out.resources()),
                previous_group.clone(),
            ]
        });
        let pipeline = mrshade_gpu::shader::compute_pipeline(
            device,
            "indirect",
            SHADER,
            &[&scene_layout, &vpl_layout, &out_layout, &previous_layout],
        );
        Self { pipeline, groups, size: out.size() }
    }

    /// Shades every pixel with its VPL subset of buffer `parity`.
    pub fn record(&self, rec: &mut Recorder, parity: usize) {
        rec.compute(Self::LABEL, |pass| {
            set_pipeline_and_groups(pass, &self.pipeline, &self.groups[parity]);
            pass.dispatch_workgroups(self.size.0.div_ceil(8), self.size.1.div_ceil(8), 1);
        });
    }
}

/// The composed WGSL module.
pub const SHADER: &str = wgsl!(
    "../../../../shaders/lib/frame.wgsl",
    "../../../../shaders/lib/gbuffer.wgsl",
    "../../../../shaders/lib/brdf.wgsl",
    "../../../../shaders/lib/gbuffer_pixel.wgsl",
    "../../../../shaders/lib/indirect_out.wgsl",
    "../../../../shaders/lib/sampling.wgsl",
    "../../../../shaders/lib/vpl.wgsl",
    "../../../../shaders/lib/ism.wgsl",
    "../../../../shaders/lib/vpl_light.wgsl",
    "indirect.wgsl",
    "nearfield.wgsl",
);
