//! Direct-light differential shading (Knecht §2.7, Eq. 5.1–5.5), the `direct` method:
//! punctual lights with real-only/virtual-only shadow maps, unshadowed image-based light from
//! the probe, emission. Writes `L_rv` and `L_r` from the same evaluation in one dispatch.
//! Inputs: G-buffer, lights, shadow maps, probe. Outputs: `Differential { rv, r }`.

use crate::methods::IndirectLight;
use crate::passes::gbuffer::GBuffer;
use crate::passes::probe_sh::ProbeShPass;
use crate::passes::shadow::ShadowPass;
use crate::scene_gpu::{GpuProbe, GpuScene};
use bytemuck::{Pod, Zeroable};
use glam::{UVec4, Vec4};
use mrshade_core::Differential;
use mrshade_core::settings::{IblSettings, PrtSpecular, ShadowSettings, VirtualShading};
use mrshade_core::sog::SogTable;
use mrshade_gpu::timing::{Recorder, set_pipeline_and_groups};
use mrshade_gpu::{GpuContext, Target, bind, wgsl};
use wgpu::util::DeviceExt;

/// Mirrors `ShadowParams` in shaders/lib/shadow.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct ShadowParams {
    /// Resolution, PCF radius, 1 if the `dir` method's indirect buffers are added, unused.
    pub size: UVec4,
    /// Normal offset (texels), relative depth bias, unused, unused.
    pub bias: Vec4,
}

impl ShadowParams {
    /// The uniform of `settings`; `with_indirect` adds the `dir` method's indirect buffers.
    pub fn new(settings: &ShadowSettings, with_indirect: bool) -> Self {
        Self {
            size: UVec4::new(settings.resolution, settings.pcf_radius, with_indirect as u32, 0),
            bias: Vec4::new(settings.normal_offset, settings.depth_bias, 0.0, 0.0),
        }
    }
}

/// Format of the radiance buffers `L_rv`, `L_r` (linear HDR).
pub const RADIANCE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// The Sum-of-Gaussians table's cells per axis (`n·v` × roughness), and the GGX samples that
/// fit each (spec §2.5 leaves both open; 16² cells interpolated bilinearly, as the DFG table).
const SOG_SIZE: u32 = 16;
const SOG_SAMPLES: u32 = 1024;

/// Allocates the pair of radiance buffers at `size`.
pub fn radiance_targets(device: &wgpu::Device, size: (u32, u32)) -> Differential<Target> {
    let usage =
        wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_SRC;
    Differential {
        rv: Target::new_2d(device, "radiance/l_rv", size, RADIANCE_FORMAT, usage),
        r: Target::new_2d(device, "radiance/l_r", size, RADIANCE_FORMAT, usage),
    }
}

/// The direct shading pass with its bind groups.
pub struct DirectPass {
    pipeline: wgpu::ComputePipeline,
    groups: [wgpu::BindGroup; 4],
    size: (u32, u32),
}

impl DirectPass {
    /// GPU timing label.
    pub const LABEL: &'static str = "direct";

    /// Binds the G-buffer, scene, shadow maps and probe, writing into `radiance`.
    #[allow(clippy::too_many_arguments, reason = "the pass's inputs, each a different resource")]
    pub fn new(
        ctx: &GpuContext,
        frame: &wgpu::Buffer,
        settings: &ShadowSettings,
        gbuffer: &GBuffer,
        scene: &GpuScene,
        shadows: &ShadowPass,
        indirect: Option<&IndirectLight>,
        radiance: &Differential<Target>,
        ibl: (&IblSettings, &ProbeShPass, Option<&Target>),
    ) -> Self {
        let device = &ctx.device;
        let cs = wgpu::ShaderStages::COMPUTE;
        let unfilterable = wgpu::TextureSampleType::Float { filterable: false };
        let d2 = wgpu::TextureViewDimension::D2;
        let params = ShadowParams::new(settings, indirect.is_some());
        // Without indirect light the bindings still need textures; these are never read.
        let placeholder;
        let indirect = match indirect {
            Some(i) => i,
            None => {
                placeholder = IndirectLight::new(device, "direct/no_indirect", (1, 1));
                &placeholder
            }
        };
        let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("direct/shadow_params"),
            contents: bytemuck::bytes_of(&params),
            usage: wgpu::BufferUsages::UNIFORM,
        });

        let gbuffer_layout = bind::layout(
            device,
            "direct/gbuffer_layout",
            &[
                bind::uniform(0, cs),
                bind::uniform(1, cs),
                bind::texture(2, cs, unfilterable, d2),
                bind::texture(3, cs, unfilterable, d2),
                bind::texture(4, cs, unfilterable, d2),
                bind::texture(5, cs, unfilterable, d2),
                bind::texture(6, cs, unfilterable, d2),
                bind::texture(7, cs, wgpu::TextureSampleType::Uint, d2),
                bind::texture(8, cs, unfilterable, d2),
                bind::texture(9, cs, unfilterable, d2),
                bind::texture(10, cs, unfilterable, d2),
                bind::texture(11, cs, unfilterable, d2),
                bind::texture(12, cs, unfilterable, d2),
            ],
        );
        let lights_layout = bind::layout(
            device,
            "direct/lights_layout",
            &[bind::storage(0, cs), bind::storage(1, cs), bind::storage(2, cs), bind::storage(3, cs)],
        );
        let mut entries = GpuProbe::layout_entries(cs).to_vec();
        entries.extend([
            bind::storage(4, cs),
            bind::texture(5, cs, wgpu::TextureSampleType::Float { filterable: true }, d2),
            bind::uniform(6, cs),
            bind::texture(7, cs, unfilterable, d2),
            bind::storage(8, cs),
        ]);
        let probe_layout = bind::layout(device, "direct/probe_layout", &entries);
        let (ibl_settings, probe_sh, prt) = ibl;
        let shading = match ibl_settings.virtual_shading {
            VirtualShading::Prefiltered => 0,
            VirtualShading::Sh => 1,
            VirtualShading::Fis => 2,
            VirtualShading::Prt => 3,
        };
        // Without PRT the binding still needs a texture; it is never read.
        let no_prt;
        let prt = match prt {
            Some(t) => t,
            None => {
                let usage = wgpu::TextureUsages::TEXTURE_BINDING;
                no_prt = Target::new_2d(device, "direct/no_prt", (1, 1), wgpu::TextureFormat::Rgba16Float, usage);
                &no_prt
            }
        };
        // The GGX lobe's Sum-of-Gaussians fit for `prt` (spec §2.5); one dummy entry otherwise.
        let sog = ibl_settings.virtual_shading == VirtualShading::Prt && ibl_settings.prt_specular == PrtSpecular::Sog;
        let sog_table = if sog { SogTable::fit(SOG_SIZE, SOG_SAMPLES).to_vec4() } else { vec![[0.0; 4]] };
        let sog_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("direct/sog_table"),
            contents: bytemuck::cast_slice(&sog_table),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let ibl_uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("direct/ibl"),
            contents: bytemuck::bytes_of(&UVec4::new(shading, ibl_settings.samples, sog as u32, SOG_SIZE)),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let output_layout = bind::layout(
            device,
            "direct/output_layout",
            &[bind::storage_texture(0, RADIANCE_FORMAT), bind::storage_texture(1, RADIANCE_FORMAT)],
        );
        use wgpu::BindingResource::TextureView;
        let probe = &scene.probe;
        let groups = [
            bind::group(
                device,
                "direct/gbuffer_group",
                &gbuffer_layout,
                &[
                    frame.as_entire_binding(),
                    params.as_entire_binding(),
                    TextureView(&gbuffer.depth_motion.view),
                    TextureView(&gbuffer.albedo_metallic.view),
                    TextureView(&gbuffer.normal_roughness.view),
                    TextureView(&gbuffer.specular.view),
                    TextureView(&gbuffer.emission_occlusion.view),
                    TextureView(&gbuffer.flags.view),
                    TextureView(&indirect.light.rv.view),
                    TextureView(&indirect.light.r.view),
                    TextureView(&indirect.env.rv.view),
                    TextureView(&indirect.env.r.view),
                    TextureView(&indirect.env_weight.view),
                ],
            ),
            bind::group(
                device,
                "direct/lights_group",
                &lights_layout,
                &[
                    scene.materials.buffer.as_entire_binding(),
                    scene.lights.as_entire_binding(),
                    scene.shadow_matrices.as_entire_binding(),
                    shadows.maps.as_entire_binding(),
                ],
            ),
            bind::group(device, "direct/probe_group", &probe_layout, &{
                let mut r = probe.resources().to_vec();
                r.extend([
                    probe_sh.coefficients.as_entire_binding(),
                    TextureView(&probe.pyramid.view),
                    ibl_uniform.as_entire_binding(),
                    TextureView(&prt.view),
                    sog_buffer.as_entire_binding(),
                ]);
                r
            }),
            bind::group(
                device,
                "direct/output_group",
                &output_layout,
                &[TextureView(&radiance.rv.view), TextureView(&radiance.r.view)],
            ),
        ];
        let pipeline = mrshade_gpu::shader::compute_pipeline(
            device,
            "direct",
            SHADER,
            &[&gbuffer_layout, &lights_layout, &probe_layout, &output_layout],
        );
        Self { pipeline, groups, size: radiance.rv.size() }
    }

    /// Shades every pixel.
    pub fn record(&self, rec: &mut Recorder) {
        rec.compute(Self::LABEL, |pass| {
            set_pipeline_and_groups(pass, &self.pipeline, &self.groups);
            pass.dispatch_workgroups(self.size.0.div_ceil(8), self.size.1.div_ceil(8), 1);
        });
    }
}

/// The composed WGSL module (shared library + this pass).
pub const SHADER: &str = wgsl!(
    "../../../shaders/lib/frame.wgsl",
    "../../../shaders/lib/gbuffer.wgsl",
    "../../../shaders/lib/brdf.wgsl",
    "../../../shaders/lib/gbuffer_pixel.wgsl",
    "../../../shaders/lib/dfg.wgsl",
    "../../../shaders/lib/env.wgsl",
    "../../../shaders/lib/env_visibility.wgsl",
    "../../../shaders/lib/lights.wgsl",
    "../../../shaders/lib/cube.wgsl",
    "../../../shaders/lib/shadow.wgsl",
    "../../../shaders/lib/punctual.wgsl",
    "../../../shaders/lib/sampling.wgsl",
    "../../../shaders/lib/sh.wgsl",
    "direct.wgsl",
    "ibl.wgsl",
);
