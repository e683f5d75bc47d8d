//! Delta light propagation volumes, the `dlpv` method (Franke §2.12, [Fra13a]), its passes in
//! the order of the spec's pseudo-code (§2.12.8): per light a real-only and a virtual-only
//! reflective shadow map (their nearer hit per texel is R_ρ, the real one R_μ) → split
//! injection into signed SH volumes → propagation → per-pixel merge into the
//! [`IndirectLight`] that direct lighting adds. Maps, injection and propagation are redone
//! only when geometry or a light moved; the merge runs every frame.
//!
//! Where it departs from the thesis, and why: punctual lights' direct change (their shadows)
//! comes from the frame's real-only and virtual-only shadow maps, exact as with every other
//! method; the probe, which the thesis leaves to other techniques, is split into directional
//! lights by median cut (`dlpv.probe_lights`) whose maps inject its bounce light and, as the
//! direct change, the shadow of its broadest lights; the other lights' shadow on real surfaces
//! is read from their maps in the merge (`dlpv.sharp_probe_shadows_deg`; hard, or soft by each
//! light's angular radius with `dlpv.soft_probe_shadows`): the volume blurs a contact shadow
//! over its cells and ends it at its own edge.
//! Texels seen alike by R_ρ and R_μ cancel exactly at injection. V_ρ, the virtual objects' light
//! from the real scene, is by default not propagated but gathered (`dlpv.virtual_light`,
//! vpl_gather.rs): the maps' texels summed into VPLs and the real surfaces the camera sees into
//! VPLs of the photo's light (`dlpv.photo_bounce`), each cell of the virtual content's box the
//! sum of their light — the propagation's light walks about √steps cells and pools near its
//! source, and sources outside the volume never enter it. So, by default, are the real
//! surfaces' bounce light V_μ and the indirect change of V_Δ (`dlpv.bounce_light`): the same
//! VPLs, signed for the change (+ a virtual surface's light, − that of the real surface it
//! hides), summed at every cell a pixel reads; propagated, a floor lit itself through its own
//! cells and a block's lit top never reached the wall behind it. Only the probe's broad lights'
//! direct change is then injected (and not propagated, `dlpv.direct_steps`). The gathered
//! VPLs see no surface on their way (the propagation's geometry volume is gone with it) but
//! the virtual ones, with `dlpv.virtual_bounce` (while the content and the lights rest; in
//! the frames they move in too with `dlpv.virtual_bounce_moving`, 0.17–0.33 ms more): the
//! virtual surfaces mark their cells with their planes, each marked cell sends the light its
//! surface takes from V_ρ on (one virtual surface lights another, and the real ones around),
//! and in V_ρ's cells a path that crosses a marked plane carries nothing (vpl_aggregate.wgsl
//! `cell_vpls`; visibility.rs: per part of 2³ cells a map of how far the planes lie in every
//! direction); with `dlpv.bounce_visibility` (0.5–0.9 ms more) in every cell.

mod lights;
mod params;
mod propagation;
mod shaders;
mod visibility;
mod vpl_gather;

use super::around::place;
use super::probe_maps::{ProbeMaps, bounding_radius, layer_pairs};
use super::rsm::{self, RsmPass};
use super::{FrameChange, IndirectLight, LightTransport, MethodInputs};
use crate::limits::Fit;
use crate::raster::Rasterizer;
use crate::scene_gpu::{GpuProbe, Moved};
use anyhow::Result;
use glam::{UVec4, Vec3};
use lights::{InjectSet, power_bound};
use mrshade_core::settings::{DlpvSettings, RenderSettings, ShadowSettings};
use mrshade_gpu::bind;
use mrshade_gpu::shader::{compute_pipeline, compute_pipeline_entry};
use mrshade_gpu::timing::{Dispatch, Recorder};
use params::*;
pub use params::{DlpvParams, SCRATCH_CELL_BYTES};
pub use propagation::{propagate_layout, sum_updates};
pub use shaders::*;
pub use visibility::{MAP_SIDE, MAP_UNITS, NO_CROSSING, VisibilityMapsView};
use vpl_gather::{MapSet, VplGather, VplPhoto};
use wgpu::util::DeviceExt;

/// The method's passes and volumes.
pub struct DlpvMethod {
    params: DlpvParams,
    /// Per dispatch of seeding (0) and propagation (1, 2, …): its uniform (the step).
    step_params: Vec<wgpu::Buffer>,
    extent: f32,
    scene_box: Option<(Vec3, Vec3)>,
    shadows: ShadowSettings,
    /// The scene's lights' maps (their layers are the frame's shadow layers).
    scene_maps: Option<RsmPass>,
    /// The directional lights the probe is split into, their maps around the volume.
    probe: ProbeMaps,
    /// The injection's dispatches: the scene's lights, then the probe's.
    sets: Vec<InjectSet>,
    /// Per source, channel and cell: the injected SH coefficients in fixed point (`i32`,
    /// `DlpvParams::scale` units).
    pub injected: wgpu::Buffer,
    inject: wgpu::ComputePipeline,
    seed: wgpu::ComputePipeline,
    propagate: wgpu::ComputePipeline,
    /// Seeding, then one dispatch per propagation step: their groups.
    dispatches: Vec<wgpu::BindGroup>,
    /// The sums every dispatch chain starts from (cleared before seeding).
    first_sums: wgpu::Buffer,
    /// The accumulated V_ρ, V_Δ and V_μ, one after the other (three RGB × four SH
    /// coefficients per cell each).
    pub volumes: wgpu::Buffer,
    /// V_ρ's band 2 where it is gathered from VPLs (volume.wgsl `rho_band2`).
    pub rho_band2: wgpu::Buffer,
    /// V_ρ summed over VPLs (`dlpv.virtual_light = "gathered"`).
    vpl_gather: Option<VplGather>,
    /// The per-pixel pass, over the internal size.
    gather: Dispatch,
    /// What direct lighting adds.
    pub indirect: IndirectLight,
    /// The kinds of caster the maps no longer show (none: the volumes are as they were).
    stale: Moved,
    /// The camera or the photo changed: V_ρ takes the photo's light again.
    stale_photo: bool,
    /// Gather once more next frame (with `dlpv.virtual_bounce`, after the maps were drawn).
    gather_again: bool,
    /// Whether the volumes were made for `dlpv.virtual_bounce` and its frames choose it
    /// (`dlpv.virtual_bounce_moving` off): on while the content and the lights rest.
    bounce_at_rest: bool,
    /// Gathers still to come with the virtual surfaces' bounce since it came on (two: their
    /// VPLs read the last gather's V_ρ).
    bounce_gathers: u8,
}

/// Builds the method (the registry's `build`).
pub(crate) fn build(inputs: &MethodInputs) -> Box<dyn LightTransport> {
    Box::new(DlpvMethod::new(inputs))
}

/// Halves the maps until every set's texels fit one buffer binding; the visibility maps of
/// `dlpv.virtual_bounce` (sized by the volume, not to be halved) must fit one as they are.
pub(crate) fn fit(settings: &mut RenderSettings, fit: &mut Fit) -> Result<()> {
    let dlpv = &mut settings.dlpv;
    rsm::fit_resolution(fit, "dlpv.rsm_resolution", fit.shadow_layers, &mut dlpv.rsm_resolution)?;
    rsm::fit_resolution(
        fit,
        "dlpv.probe_rsm_resolution",
        2 * dlpv.probe_lights as u64,
        &mut dlpv.probe_rsm_resolution,
    )?;
    let maps = visibility_bytes(dlpv);
    if maps > fit.max_binding {
        anyhow::bail!(
            "dlpv.virtual_bounce at dlpv.resolution = {} and dlpv.extent = {} needs {} MiB of visibility maps in one \
             buffer, more than this device binds ({} MiB): lower dlpv.resolution or raise dlpv.extent",
            dlpv.resolution,
            dlpv.extent,
            maps >> 20,
            fit.max_binding >> 20
        );
    }
    Ok(())
}

/// Bytes of the visibility maps `settings` makes (none without `dlpv.virtual_bounce`).
fn visibility_bytes(settings: &DlpvSettings) -> u64 {
    if gathered_volumes(settings) & vpl_gather::GATHERED_BOUNCE != 0 && settings.virtual_bounce {
        visibility::bytes(settings.resolution, settings.extent)
    } else {
        0
    }
}

/// GPU bytes of the method, item by item.
pub(crate) fn estimate(settings: &RenderSettings, internal_pixels: u64, layers: u64) -> Vec<(&'static str, u64)> {
    let d = &settings.dlpv;
    let cells = (d.resolution as u64).pow(3);
    vec![
        ("dlpv screen targets (output size × supersample²)", internal_pixels * 5 * 8),
        ("dlpv RSMs (light layers × dlpv.rsm_resolution²)", rsm::bytes(layers, d.rsm_resolution)),
        (
            "dlpv probe-light RSMs (2 × dlpv.probe_lights × dlpv.probe_rsm_resolution²)",
            rsm::bytes(2 * d.probe_lights as u64, d.probe_rsm_resolution),
        ),
        (
            "dlpv probe maps' nearest highest surfaces (with soft probe shadows: 2 × 4 bytes a texel)",
            if d.soft_probe_shadows || d.soft_virtual_probe_shadows {
                2 * 4 * 2 * d.probe_lights as u64 * (d.probe_rsm_resolution as u64).pow(2)
            } else {
                0
            },
        ),
        (
            "dlpv volumes (dlpv.resolution³)",
            cells
                * (SOURCES as u64 * (CELL_BYTES + 2 * SCRATCH_CELL_BYTES)
                    + 2 * VOLUMES * CELL_BYTES
                    + BAND2_CELL_BYTES),
        ),
        (
            "dlpv gathered volumes (VPLs of the maps and the photo, partial sums)",
            match gathered_volumes(d) {
                0 => 0,
                gathered => vpl_gather::bytes(
                    &[
                        (layers, (d.rsm_resolution as u64).pow(2)),
                        (d.probe_lights as u64, (d.probe_rsm_resolution as u64).pow(2)),
                    ],
                    d.gather_block as u64,
                    cells,
                    gathered,
                ),
            },
        ),
        ("dlpv visibility maps of V_ρ's parts (with dlpv.virtual_bounce)", visibility_bytes(d)),
    ]
}

impl DlpvMethod {
    /// GPU timing label of the maps' rasterisation (the RSM pass's).
    pub const RSM_LABEL: &'static str = RsmPass::LABEL;
    /// GPU timing label of the injection.
    pub const INJECT_LABEL: &'static str = "dlpv-inject";
    /// GPU timing label of seeding and propagation.
    pub const PROPAGATE_LABEL: &'static str = "dlpv-propagate";
    /// GPU timing label of the per-pixel merge.
    pub const LABEL: &'static str = "dlpv-merge";

    /// Builds every pass for the session of `inputs`.
    pub fn new(inputs: &MethodInputs) -> Self {
        let MethodInputs { ctx, session, scene, rasterizer, frame_uniforms, gbuffer, internal_size, .. } = *inputs;
        let device = &ctx.device;
        let settings = &session.settings.dlpv;
        let res = settings.resolution;
        let cells = res * res * res;
        let cs = wgpu::ShaderStages::COMPUTE;
        let scene_box = session.scene.bounds();
        let (origin, side) = place(scene.geometry.virtual_box(), scene_box, settings.extent);
        let cube = (origin, origin + Vec3::splat(side));

        // The light sets: the scene's lights, and the probe's split into directional ones.
        let probe_lights = match &session.environment {
            Some(env) => crate::ibl::probe_lights_with_spread(env, settings.probe_lights),
            None => Vec::new(),
        };
        let shadows = &session.settings.shadows;
        let scene_radius = bounding_radius(scene_box);
        let gathered = params::gathered_volumes(settings);
        let probe_only: Vec<_> = probe_lights.iter().map(|(light, _)| light.clone()).collect();
        let bound =
            power_bound(&session.scene.lights, scene_radius) + power_bound(&probe_only, bounding_radius(Some(cube)));
        let params = DlpvParams::new(settings, origin, side, bound);
        let injected = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("dlpv/injected"),
            size: SOURCES as u64 * cells as u64 * CELL_BYTES,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let uniform = |label: &str, p: &DlpvParams| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: bytemuck::bytes_of(p),
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            })
        };
        let max_steps = params.steps.max_element();
        let step_params: Vec<wgpu::Buffer> =
            (0..=max_steps).map(|step| uniform(&format!("dlpv/params_step{step}"), &params.at_step(step))).collect();

        let inject_layout = bind::layout(
            device,
            "dlpv/inject_layout",
            &[
                bind::uniform(0, cs),
                bind::storage(1, cs),
                bind::storage(2, cs),
                bind::storage(3, cs),
                bind::storage_rw(4, cs),
                bind::uniform(5, cs),
            ],
        );
        let inject = compute_pipeline(device, "dlpv/inject", INJECT_SHADER, &[&inject_layout]);
        // One dispatch per set: its maps' texels, pairs and lights, and (resolution, pairs, 1
        // if the set's direct change is injected: the probe's broad lights' shadow; punctual
        // lights' comes from the shadow maps, the probe's sharp lights' from their maps).
        let inject_set =
            |label: &str, [lights, texels, pairs_buffer]: [&wgpu::Buffer; 3], pairs, resolution, direct| {
                let size = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(&format!("dlpv/{label}_rsm_size")),
                    contents: bytemuck::bytes_of(&UVec4::new(resolution, pairs, direct as u32, 0)),
                    usage: wgpu::BufferUsages::UNIFORM,
                });
                let group = bind::group(
                    device,
                    &format!("dlpv/{label}_inject_group"),
                    &inject_layout,
                    &[
                        step_params[0].as_entire_binding(),
                        texels.as_entire_binding(),
                        pairs_buffer.as_entire_binding(),
                        lights.as_entire_binding(),
                        injected.as_entire_binding(),
                        size.as_entire_binding(),
                    ],
                );
                InjectSet { group, pairs, resolution }
            };
        let mut sets = Vec::new();
        let mut map_sets = Vec::new();
        let scene_maps = (!scene.shadow_layers.is_empty()).then(|| {
            let layers = &scene.shadow_layers;
            let resolution = settings.rsm_resolution;
            let rsm =
                RsmPass::new(ctx, rasterizer, scene, &scene.lights, layers, resolution, shadows.resolution, false);
            let pairs = layer_pairs(layers);
            let pairs_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("dlpv/scene_lights_pairs"),
                contents: bytemuck::cast_slice(&pairs),
                usage: wgpu::BufferUsages::STORAGE,
            });
            let buffers = [&scene.lights, &rsm.texels, &pairs_buffer];
            sets.push(inject_set("scene_lights", buffers, pairs.len() as u32, resolution, false));
            (rsm, pairs_buffer, pairs.len() as u32)
        });
        let probe = ProbeMaps::new(
            ctx,
            rasterizer,
            scene,
            "dlpv",
            probe_lights,
            settings.probe_rsm_resolution,
            cube,
            scene_box,
            shadows,
            settings.soft_probe_shadows || settings.soft_virtual_probe_shadows,
        );
        if let Some((rsm, pairs_buffer, pairs)) = &scene_maps {
            let buffers = [&scene.lights, &rsm.texels, pairs_buffer];
            map_sets.push(MapSet { buffers, pairs: *pairs, resolution: settings.rsm_resolution });
        }
        if let Some((buffers, pairs, resolution)) = probe.maps() {
            sets.push(inject_set("probe_lights", buffers, pairs, resolution, true));
            map_sets.push(MapSet { buffers, pairs, resolution });
        }

        // Seeding and propagation: every source's volume in scratch A and B, the sums of the
        // three accumulated volumes in two buffers.
        let buffer = |label: &str, size: u64| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            })
        };
        let volume_bytes = cells as u64 * CELL_BYTES;
        let scratch = ["a", "b"]
            .map(|n| buffer(&format!("dlpv/scratch_{n}"), SOURCES as u64 * cells as u64 * SCRATCH_CELL_BYTES));
        // Every dispatch reads one sum buffer and writes the other. Adding into one read-write
        // buffer from dispatch to dispatch raced on the H200 (lavapipe runs dispatches in
        // order and hid it), and so would two dispatches writing the same scratch buffer.
        let sums = ["0", "1"].map(|n| buffer(&format!("dlpv/sums_{n}"), VOLUMES * volume_bytes));
        let propagate_layout = propagate_layout(device);
        let seed = compute_pipeline_entry(device, "dlpv/seed", PROPAGATE_SHADER, "seed", &[&propagate_layout]);
        let propagate =
            compute_pipeline_entry(device, "dlpv/propagate", PROPAGATE_SHADER, "propagate", &[&propagate_layout]);
        // Dispatch k reads scratch k mod 2 and writes the other (a seed reads no scratch: the
        // other one stands in for its unused `source`). Sums: the seed and every dispatch
        // that adds to them (`sum_updates`) read the buffer the one before wrote.
        let updates = sum_updates(max_steps);
        let dispatches: Vec<wgpu::BindGroup> = (0..=max_steps as usize)
            .map(|k| {
                let (read, write) = (k % 2, 1 - k % 2);
                let sums_read = updates[k] % 2;
                bind::group(
                    device,
                    &format!("dlpv/step{k}_group"),
                    &propagate_layout,
                    &[
                        step_params[k].as_entire_binding(),
                        injected.as_entire_binding(),
                        scratch[read].as_entire_binding(),
                        scratch[write].as_entire_binding(),
                        sums[sums_read].as_entire_binding(),
                        sums[1 - sums_read].as_entire_binding(),
                    ],
                )
            })
            .collect();
        let volumes = sums[updates[max_steps as usize + 1] % 2].clone();
        let rho_band2 = buffer("dlpv/rho_band2", cells as u64 * BAND2_CELL_BYTES);
        let vpl_gather = (gathered != 0).then(|| {
            let photo = VplPhoto { frame_uniforms, gbuffer, photo: inputs.photo, internal_size };
            VplGather::new(
                device,
                &step_params[0],
                &volumes,
                &rho_band2,
                &injected,
                gathered,
                &map_sets,
                photo,
                settings.gather_block,
                scene.geometry.virtual_box(),
                &params,
                settings.extent,
            )
        });
        drop(map_sets);
        let first_sums = sums[0].clone();

        // The per-pixel merge.
        let (gbuffer_layout, gbuffer_group) = super::pixel_inputs(
            device,
            "dlpv/gbuffer",
            frame_uniforms,
            &step_params[0],
            gbuffer,
            &scene.materials.buffer,
        );
        // 0: the three volumes; 1–4: the probe's lights' lookups, their maps' heights, counts
        // and highest surfaces near each texel (the pixels' shadows of the probe); 5: V_ρ's
        // band 2.
        let mut entries = vec![bind::storage(0, cs)];
        entries.extend(ProbeMaps::layout_entries(1));
        entries.push(bind::storage(5, cs));
        let volume_layout = bind::layout(device, "dlpv/volume_layout", &entries);
        let mut resources = vec![volumes.as_entire_binding()];
        resources.extend(probe.resources());
        resources.push(rho_band2.as_entire_binding());
        let volume_group = bind::group(device, "dlpv/volume_group", &volume_layout, &resources);
        let indirect = IndirectLight::new(device, "dlpv/indirect", internal_size);
        let indirect_layout = bind::layout(device, "dlpv/indirect_layout", &IndirectLight::storage_entries());
        let probe_layout = bind::layout(device, "dlpv/probe_layout", &GpuProbe::layout_entries(cs));
        let gather = compute_pipeline(
            device,
            "dlpv/merge",
            GATHER_SHADER,
            &[&gbuffer_layout, &volume_layout, &indirect_layout, &probe_layout],
        );
        let gather_groups = vec![
            gbuffer_group,
            volume_group,
            bind::group(device, "dlpv/indirect_group", &indirect_layout, &indirect.resources()),
            bind::group(device, "dlpv/probe_group", &probe_layout, &scene.probe.resources()),
        ];
        Self {
            params,
            step_params,
            extent: settings.extent,
            scene_box,
            shadows: *shadows,
            scene_maps: scene_maps.map(|(rsm, _, _)| rsm),
            probe,
            sets,
            injected,
            inject,
            seed,
            propagate,
            dispatches,
            first_sums,
            volumes,
            rho_band2,
            vpl_gather,
            gather: Dispatch {
                pipeline: gather,
                groups: gather_groups,
                workgroups: [internal_size.0.div_ceil(8), internal_size.1.div_ceil(8), 1],
            },
            indirect,
            stale: Moved::ALL,
            stale_photo: false,
            gather_again: false,
            bounce_at_rest: params.virtual_bounce() && !settings.virtual_bounce_moving,
            bounce_gathers: 0,
        }
    }

    /// The visibility maps of V_ρ's parts (with `dlpv.virtual_bounce`).
    pub fn visibility_maps(&self) -> Option<VisibilityMapsView<'_>> {
        self.vpl_gather.as_ref().and_then(|g| g.visibility_maps())
    }

    /// The volumes' uniform (where the cube lies, the fixed-point scale).
    pub fn params(&self) -> DlpvParams {
        self.params
    }

    /// Moves the cube to follow the virtual content and the probe's maps with it.
    fn follow(&mut self, queue: &wgpu::Queue, geometry: &crate::scene_gpu::Geometry) {
        let res = self.params.info.x;
        let (origin, side) = place(geometry.virtual_box(), self.scene_box, self.extent);
        self.params.origin = origin.extend(side / res as f32);
        for buffer in &self.step_params {
            queue.write_buffer(buffer, 0, bytemuck::bytes_of(&self.params.origin));
        }
        let cube = (origin, origin + Vec3::splat(side));
        self.probe.follow(queue, cube, self.scene_box, &self.shadows);
        if let Some(gather) = &mut self.vpl_gather {
            gather.follow(queue, geometry.virtual_box(), &self.params);
        }
    }

    /// Turns the virtual surfaces' bounce on or off in every dispatch's uniform (volume.wgsl
    /// `virtual_bounce`), the volumes made for it.
    fn set_virtual_bounce(&mut self, queue: &wgpu::Queue, on: bool) {
        self.params.gathered.w =
            (self.params.gathered.w & !VIRTUAL_BOUNCE_BIT) | if on { VIRTUAL_BOUNCE_BIT } else { 0 };
        let offset = std::mem::offset_of!(DlpvParams, gathered) as u64;
        for buffer in &self.step_params {
            queue.write_buffer(buffer, offset, bytemuck::bytes_of(&self.params.gathered));
        }
    }
}

impl LightTransport for DlpvMethod {
    fn prepare(&mut self, queue: &wgpu::Queue, change: &FrameChange) {
        if change.geometry_moved || change.vertices_deformed {
            // The cube follows the virtual content (spec §2.12.7: "kept synchronous").
            self.follow(queue, change.geometry);
            self.stale = self.stale.union(change.geometry.moved_casters());
        }
        if let Some(layers) = change.moved_light_layers {
            if let Some(rsm) = &mut self.scene_maps {
                rsm.set_layers(queue, layers);
            }
            self.stale = Moved::ALL;
        }
        // The virtual surfaces' bounce while the content and the lights rest; a frame in which
        // they move leaves it out (`dlpv.virtual_bounce_moving`), the next at rest gathers it.
        if self.bounce_at_rest {
            let moving = change.geometry_moved || change.vertices_deformed || change.moved_light_layers.is_some();
            if moving == self.params.virtual_bounce() {
                self.set_virtual_bounce(queue, !moving);
                self.bounce_gathers = if moving { 0 } else { 2 };
            }
        }
        // The photo's light in the gathered volumes follows the camera and the photo, and the
        // cells the pixels read (the gathered bounce light) the camera.
        self.stale_photo |= (change.camera_moved || change.photo_changed)
            && (self.params.gathered.y == 1 || self.params.gathered.w != 0);
    }

    fn record(&mut self, rec: &mut Recorder, rasterizer: &Rasterizer) {
        // A new photo or camera alone: the maps are as they were, V_ρ is gathered again; so
        // once after the maps were drawn anew, with the virtual surfaces' bounce: their
        // surfaces' VPLs (vpl_aggregate.wgsl `cell_vpls`) read the last gather's V_ρ, zero
        // before a still's first frame.
        let again =
            std::mem::take(&mut self.stale_photo) || std::mem::take(&mut self.gather_again) || self.bounce_gathers > 0;
        let bounce = self.params.virtual_bounce();
        if let (false, true, Some(gather)) = (self.stale.any(), again, &self.vpl_gather) {
            gather.record(rec, bounce);
            self.bounce_gathers = self.bounce_gathers.saturating_sub(1);
        }
        let moved = std::mem::take(&mut self.stale);
        if moved.any() {
            // The scene lights' maps (only those of the casters that moved) and the probe's
            // (which follow the cube) in one raster pass and one resolve pass.
            let scene_maps: Vec<_> = self.scene_maps.iter().map(|rsm| (rsm, moved)).collect();
            self.probe.record_with(rec, rasterizer, &scene_maps);
            // The VPLs before V_ρ is cleared below (their virtual surfaces read it).
            if let Some(gather) = &self.vpl_gather {
                gather.record_vpls(rec, bounce);
                self.gather_again = bounce;
            }
            rec.encoder.clear_buffer(&self.injected, 0, None);
            rec.encoder.clear_buffer(&self.first_sums, 0, None);
            let res = self.params.info.x;
            rec.compute(Self::INJECT_LABEL, |pass| {
                pass.set_pipeline(&self.inject);
                for set in self.sets.iter().filter(|s| s.pairs > 0) {
                    let groups = set.resolution.div_ceil(8);
                    pass.set_bind_group(0, &set.group, &[]);
                    pass.dispatch_workgroups(groups, groups, set.pairs);
                }
            });
            rec.compute(Self::PROPAGATE_LABEL, |pass| {
                for (k, group) in self.dispatches.iter().enumerate() {
                    pass.set_pipeline(if k == 0 { &self.seed } else { &self.propagate });
                    pass.set_bind_group(0, group, &[]);
                    // x, y: cells; z: cells × accumulated volume × channel (propagate.wgsl).
                    let volumes = VOLUMES as u32 - self.params.gathered.x;
                    pass.dispatch_workgroups(res / 4, res / 4, res / 4 * 3 * volumes);
                }
            });
            if let Some(gather) = &self.vpl_gather {
                if self.params.gathered.x == 1 {
                    // V_ρ's cells beyond those gathered are never read: zero.
                    rec.encoder.clear_buffer(&self.volumes, 0, Some(self.params.info.y as u64 * CELL_BYTES));
                    rec.encoder.clear_buffer(&self.rho_band2, 0, None);
                }
                gather.record_gather_pass(rec, bounce);
            }
        }
        rec.compute(Self::LABEL, |pass| self.gather.record(pass));
    }

    fn indirect(&self) -> Option<&IndirectLight> {
        Some(&self.indirect)
    }

    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}
