//! The pixels' cones of `dvct` (gather.wgsl), once per trace texel (`dvct.trace_block`),
//! their resolve per pixel (resolve.wgsl) into the [`IndirectLight`] that direct lighting
//! adds, and the cones of the pixels that no trace texel around them is like, traced on their
//! own (`dvct.retrace_likeness`); a still view's thin rays for the virtual texels
//! (`dvct.still_rays`); the probe's lights and their maps, whose visibility the cones blend
//! in.

use super::cascade::Cascade;
use super::{GATHER_SHADER, RESOLVE_SHADER};
use crate::methods::probe_maps::ProbeMaps;
use crate::methods::{IndirectLight, MethodInputs, indirect_light};
use crate::scene_gpu::GpuProbe;
use mrshade_gpu::bind;
use mrshade_gpu::shader::{compute_pipeline, compute_pipeline_with};
use mrshade_gpu::timing::{Dispatch, set_pipeline_and_groups};
use wgpu::util::DeviceExt;

/// The per-pixel passes and what they write.
pub(super) struct PixelPasses {
    /// The cones, once per trace texel.
    pub trace: Dispatch,
    /// Their light per pixel, over the internal size.
    pub resolve: Dispatch,
    /// The cones of the pixels the resolve listed.
    pub retrace: Retrace,
    /// What direct lighting adds.
    pub indirect: IndirectLight,
    /// The probe's lights and their maps around the inner volume (`dvct.probe_lights`).
    pub probe_maps: ProbeMaps,
    /// A still view's thin rays for the virtual trace texels (`dvct.still_rays`).
    pub still_rays: StillRays,
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
        let still_rays = StillRays::new(device, trace_size, settings.still_rays);
        let mut entries = IndirectLight::storage_entries().to_vec();
        entries.extend([
            bind::storage_texture(5, indirect_light::FORMAT),
            bind::storage_texture(6, indirect_light::FORMAT),
            bind::storage_rw(8, cs),
            bind::uniform(9, cs),
        ]);
        let traced_layout = bind::layout(device, "dvct/traced_layout", &entries);
        // The trace texels' seven targets, written by the trace and read by the resolve.
        let mut traced_views = traced.resources().to_vec();
        traced_views.extend([TextureView(&glossy.rv.view), TextureView(&glossy.r.view)]);
        // Binding 7 is the retrace's list in the same module (cs_retrace).
        let mut resources: Vec<_> = traced_views.iter().cloned().enumerate().map(|(i, r)| (i as u32, r)).collect();
        resources.extend([(8, still_rays.history.as_entire_binding()), (9, still_rays.params.as_entire_binding())]);
        let traced_group = bind::group_at(device, "dvct/traced_group", &traced_layout, &resources);
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
        // The cones' two entry points (gather.wgsl), each writing through its own group 2.
        let cones_pipeline = |label: &str, entry: &str, out_layout: &wgpu::BindGroupLayout| {
            compute_pipeline_with(
                device,
                label,
                GATHER_SHADER,
                entry,
                &[&gbuffer_layout, volume_layout, out_layout, &trace_probe_layout],
                &[("VIRTUAL_RAYS", settings.virtual_rays as f64)],
            )
        };
        let trace = cones_pipeline("dvct/cones", "cs_main", &traced_layout);
        let trace_groups = vec![gbuffer_group.clone(), volumes, traced_group, trace_probe_group];
        let mut entries = IndirectLight::sampled_entries(0).to_vec();
        entries.extend(IndirectLight::sampled_entries(5).into_iter().take(2));
        let traced_sampled_layout = bind::layout(device, "dvct/traced_sampled_layout", &entries);
        let traced_sampled = bind::group(device, "dvct/traced_sampled_group", &traced_sampled_layout, &traced_views);
        let indirect = IndirectLight::new(device, "dvct/indirect", internal_size);
        let retrace_list = RetraceList::new(device, trace_size, scale, settings.retrace_likeness);
        let mut entries = IndirectLight::storage_entries().to_vec();
        entries.extend([bind::storage_rw(5, cs), bind::uniform(6, cs)]);
        let indirect_layout = bind::layout(device, "dvct/indirect_layout", &entries);
        let resolve = compute_pipeline(
            device,
            "dvct/resolve",
            RESOLVE_SHADER,
            &[&gbuffer_layout, &traced_sampled_layout, &indirect_layout, &probe_layout],
        );
        let mut resources = indirect.resources().to_vec();
        resources.extend([retrace_list.list.as_entire_binding(), retrace_list.params.as_entire_binding()]);
        let resolve_groups = vec![
            gbuffer_group.clone(),
            traced_sampled,
            bind::group(device, "dvct/indirect_group", &indirect_layout, &resources),
            probe_group,
        ];
        // The listed pixels' cones write the method's targets (gather.wgsl cs_retrace).
        let mut entries = IndirectLight::storage_entries().to_vec();
        entries.push(bind::storage(7, cs));
        let retrace_layout = bind::layout(device, "dvct/retrace_layout", &entries);
        // Binding 7: 5 and 6 are the trace's glossy targets in the same module.
        let mut resources: Vec<_> = indirect.resources().into_iter().enumerate().map(|(i, r)| (i as u32, r)).collect();
        resources.push((7, retrace_list.list.as_entire_binding()));
        let retrace_group = bind::group_at(device, "dvct/retrace_group", &retrace_layout, &resources);
        let retrace = Retrace {
            pipeline: cones_pipeline("dvct/retrace", "cs_retrace", &retrace_layout),
            groups: vec![gbuffer_group, trace_groups[1].clone(), retrace_group, trace_groups[3].clone()],
            list: retrace_list,
            active: false,
        };
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
            retrace,
            indirect,
            probe_maps,
            still_rays,
        }
    }
}

/// A still view's thin rays (still_rays.wgsl): while nothing changes, each frame's virtual
/// trace texels gather with `dvct.still_rays` rays shifted anew and keep the running mean of
/// the still's frames; a moving view's frames trace their cones (`dvct.virtual_rays`).
pub(super) struct StillRays {
    /// Per trace texel, the running mean and what it is of (still_rays.wgsl `still_history`).
    history: wgpu::Buffer,
    /// (rays this frame, the frame's number in the still, 0, 0).
    params: wgpu::Buffer,
    rays: u32,
    /// What `params` holds.
    written: [u32; 4],
}

/// Bytes per trace texel of the history: five vec4s (still_rays.wgsl `STILL_HISTORY_VEC4S`).
pub(super) const STILL_HISTORY_BYTES: u64 = 5 * 16;

impl StillRays {
    fn new(device: &wgpu::Device, trace_size: (u32, u32), rays: u32) -> Self {
        let texels = if rays > 0 { trace_size.0 as u64 * trace_size.1 as u64 } else { 1 };
        let history = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("dvct/still_history"),
            size: texels * STILL_HISTORY_BYTES,
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        });
        let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("dvct/still_rays"),
            contents: bytemuck::cast_slice(&[0u32; 4]),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        Self { history, params, rays, written: [0; 4] }
    }

    /// Sets the frame's rays: `still_frames` frames since anything changed (0: this one did).
    pub fn set_frame(&mut self, queue: &wgpu::Queue, still_frames: u32) {
        let rays = if still_frames > 0 { self.rays } else { 0 };
        let values = [rays, if rays > 0 { still_frames } else { 0 }, 0, 0];
        if values != self.written {
            queue.write_buffer(&self.params, 0, bytemuck::cast_slice(&values));
            self.written = values;
        }
    }
}

/// The pixels that no trace texel around them is like (a silhouette, a crease, an object's
/// rim where it meets the desk), listed by the resolve and traced on their own while the view
/// holds still: blended from texels of another facing, a bunny's underside took the light of
/// its front (desk-bunny's region FLIP 0.0618, 0.0568 traced per pixel). A moving view's
/// frames list nothing and keep the blend: at 1080p the pixels listed (mostly surfaces seen at
/// grazing angles, whose texels' depths run apart) cost a moving cornell frame 0.25 ms, past
/// the method's 3 ms (docs/benchmarks.md, 2026-12-07).
pub(super) struct Retrace {
    pipeline: wgpu::ComputePipeline,
    groups: Vec<wgpu::BindGroup>,
    list: RetraceList,
    /// Whether this frame's resolve lists and its pixels are traced (a still view's frame).
    active: bool,
}

impl Retrace {
    /// The volumes its cones read (cones.wgsl's group 1), as the trace's.
    pub fn set_volumes(&mut self, volumes: &wgpu::BindGroup) {
        self.groups[1] = volumes.clone();
    }

    /// Readies the frame (before the pass of [`Self::record`]): a still view's frame empties
    /// the list and has the resolve fill it; a moving view's has it list nothing.
    pub fn begin(&mut self, encoder: &mut wgpu::CommandEncoder, still: bool) {
        let active = self.list.enabled && still;
        if active != self.active {
            let params = if active { &self.list.listing } else { &self.list.not_listing };
            encoder.copy_buffer_to_buffer(params, 0, &self.list.params, 0, RETRACE_PARAMS_BYTES);
            self.active = active;
        }
        if active {
            encoder.copy_buffer_to_buffer(&self.list.init, 0, &self.list.list, 0, RETRACE_HEADER_BYTES);
        }
    }

    /// Traces the listed pixels (after the resolve, in the same pass).
    pub fn record(&self, pass: &mut wgpu::ComputePass) {
        if !self.active {
            return;
        }
        set_pipeline_and_groups(pass, &self.pipeline, &self.groups);
        pass.dispatch_workgroups_indirect(&self.list.list, 0);
    }
}

/// The list of pixels to trace again and what the resolve reads to fill it.
struct RetraceList {
    /// The indirect dispatch's workgroups, the count, then the pixels (resolve.wgsl
    /// RetraceListOut).
    list: wgpu::Buffer,
    /// The list's header as each frame starts: no workgroups, none listed.
    init: wgpu::Buffer,
    /// (capacity, likeness below which a pixel is listed, 0, 0): as the resolve reads it, a
    /// copy of `listing` or `not_listing` (likeness 0).
    params: wgpu::Buffer,
    listing: wgpu::Buffer,
    not_listing: wgpu::Buffer,
    /// Whether any pixel can be listed (a trace texel per pixel lists none, nor likeness 0).
    enabled: bool,
}

/// Bytes of the list's header: the dispatch's three words and the count.
const RETRACE_HEADER_BYTES: u64 = 16;

/// Bytes of the resolve's parameters of the list.
const RETRACE_PARAMS_BYTES: u64 = 16;

impl RetraceList {
    /// The list for a frame of `trace_size` texels of `scale` × `scale` pixels: as many entries
    /// as trace texels (pixels listed beyond them keep the resolve's blend).
    fn new(device: &wgpu::Device, trace_size: (u32, u32), scale: u32, likeness: f32) -> Self {
        let enabled = scale > 1 && likeness > 0.0;
        let capacity = if enabled { trace_size.0 * trace_size.1 } else { 0 };
        let list = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("dvct/retrace_list"),
            size: RETRACE_HEADER_BYTES + 4 * capacity.max(1) as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::INDIRECT | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let init = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("dvct/retrace_init"),
            contents: bytemuck::cast_slice(&[0u32, 1, 1, 0]),
            usage: wgpu::BufferUsages::COPY_SRC,
        });
        let uniform = |label: &str, likeness: f32, usage: wgpu::BufferUsages| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: bytemuck::cast_slice(&[capacity as f32, likeness, 0.0, 0.0]),
                usage,
            })
        };
        let listing = uniform("dvct/retrace_listing", likeness, wgpu::BufferUsages::COPY_SRC);
        let not_listing = uniform("dvct/retrace_not_listing", 0.0, wgpu::BufferUsages::COPY_SRC);
        let params = uniform("dvct/retrace_params", 0.0, wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST);
        Self { list, init, params, listing, not_listing, enabled }
    }
}
