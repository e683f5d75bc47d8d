//! The pixels' cones of `dvct` (gather.wgsl), once per trace texel (`dvct.trace_block`),
//! and their resolve per pixel (resolve.wgsl) into the [`IndirectLight`] that direct
//! lighting adds; the probe's lights and their maps, whose visibility the cones blend in.

use super::cascade::Cascade;
use super::{GATHER_SHADER, RESOLVE_SHADER};
use crate::methods::probe_maps::ProbeMaps;
use crate::methods::{IndirectLight, MethodInputs, indirect_light};
use crate::scene_gpu::GpuProbe;
use mrshade_gpu::bind;
use mrshade_gpu::shader::{compute_pipeline, compute_pipeline_with};
use mrshade_gpu::timing::Dispatch;

/// The per-pixel passes and what they write.
pub(super) struct PixelPasses {
    /// The cones, once per trace texel.
    pub trace: Dispatch,
    /// Their light per pixel, over the internal size.
    pub resolve: Dispatch,
    /// What direct lighting adds.
    pub indirect: IndirectLight,
    /// The probe's lights and their maps around the inner volume (`dvct.probe_lights`).
    pub probe_maps: ProbeMaps,
}

impl PixelPasses {
    /// The passes of the session of `inputs` around the `inner` cascade, reading the volumes
    /// through `volumes` (of `volume_layout`, cones.wgsl's group 1).
    pub fn new(
        inputs: &MethodInputs,
        inner: &Cascade,
        volume_layout: &wgpu::BindGroupLayout,
        volumes: wgpu::BindGroup,
    ) -> Self {
        let MethodInputs { ctx, session, scene, rasterizer, frame_uniforms, gbuffer, internal_size, .. } = *inputs;
        let device = &ctx.device;
        let settings = &session.settings.dvct;
        let scene_box = session.scene.bounds();
        let cs = wgpu::ShaderStages::COMPUTE;
        use wgpu::BindingResource::TextureView;
        let (gbuffer_layout, gbuffer_group) = crate::methods::pixel_inputs(
            device,
            "dvct/gbuffer",
            frame_uniforms,
            &inner.params_buffer,
            gbuffer,
            &scene.materials.buffer,
        );
        let scale = settings.trace_block;
        let trace_size = (internal_size.0.div_ceil(scale), internal_size.1.div_ceil(scale));
        let traced = IndirectLight::new(device, "dvct/traced", trace_size);
        let glossy = IndirectLight::new(device, "dvct/traced_glossy", trace_size).light;
        let mut entries = IndirectLight::storage_entries().to_vec();
        entries.extend([
            bind::storage_texture(5, indirect_light::FORMAT),
            bind::storage_texture(6, indirect_light::FORMAT),
        ]);
        let traced_layout = bind::layout(device, "dvct/traced_layout", &entries);
        // The trace texels' seven targets, written by the trace and read by the resolve.
        let mut traced_views = traced.resources().to_vec();
        traced_views.extend([TextureView(&glossy.rv.view), TextureView(&glossy.r.view)]);
        let traced_group = bind::group(device, "dvct/traced_group", &traced_layout, &traced_views);
        let probe_layout = bind::layout(device, "dvct/probe_layout", &GpuProbe::layout_entries(cs));
        let probe_group = bind::group(device, "dvct/probe_group", &probe_layout, &scene.probe.resources());
        // The probe's lights and their maps around the inner volume (the cones' probe
        // visibility where they cover a pixel).
        let probe_lights = match (&session.environment, settings.probe_lights) {
            (Some(env), n) if n > 0 => crate::ibl::probe_lights_with_spread(env, n),
            _ => Vec::new(),
        };
        let probe_maps = ProbeMaps::new(
            ctx,
            rasterizer,
            scene,
            "dvct",
            probe_lights,
            settings.probe_map_resolution,
            inner.cube(),
            scene_box,
            &session.settings.shadows,
            false,
        );
        let mut entries = GpuProbe::layout_entries(cs).to_vec();
        entries.extend(ProbeMaps::layout_entries(4));
        let trace_probe_layout = bind::layout(device, "dvct/trace_probe_layout", &entries);
        let mut resources = scene.probe.resources().to_vec();
        resources.extend(probe_maps.resources());
        let trace_probe_group = bind::group(device, "dvct/trace_probe_group", &trace_probe_layout, &resources);
        let trace = compute_pipeline_with(
            device,
            "dvct/cones",
            GATHER_SHADER,
            "cs_main",
            &[&gbuffer_layout, volume_layout, &traced_layout, &trace_probe_layout],
            &[("VIRTUAL_RAYS", settings.virtual_rays as f64)],
        );
        let trace_groups = vec![gbuffer_group.clone(), volumes, traced_group, trace_probe_group];
        let mut entries = IndirectLight::sampled_entries(0).to_vec();
        entries.extend(IndirectLight::sampled_entries(5).into_iter().take(2));
        let traced_sampled_layout = bind::layout(device, "dvct/traced_sampled_layout", &entries);
        let traced_sampled = bind::group(device, "dvct/traced_sampled_group", &traced_sampled_layout, &traced_views);
        let indirect = IndirectLight::new(device, "dvct/indirect", internal_size);
        let indirect_layout = bind::layout(device, "dvct/indirect_layout", &IndirectLight::storage_entries());
        let resolve = compute_pipeline(
            device,
            "dvct/resolve",
            RESOLVE_SHADER,
            &[&gbuffer_layout, &traced_sampled_layout, &indirect_layout, &probe_layout],
        );
        let resolve_groups = vec![
            gbuffer_group,
            traced_sampled,
            bind::group(device, "dvct/indirect_group", &indirect_layout, &indirect.resources()),
            probe_group,
        ];
        Self {
            trace: Dispatch {
                pipeline: trace,
                groups: trace_groups,
                workgroups: [trace_size.0.div_ceil(8), trace_size.1.div_ceil(8), 1],
            },
            resolve: Dispatch {
                pipeline: resolve,
                groups: resolve_groups,
                workgroups: [internal_size.0.div_ceil(8), internal_size.1.div_ceil(8), 1],
            },
            indirect,
            probe_maps,
        }
    }
}
