//! The directional lights the probe is split into (median cut, `ibl::probe_lights`) and their
//! real-only and virtual-only maps around a delta method's volume: as wide as the volume's
//! bounding sphere, deep enough toward each light to hold everything of the scene there. `dlpv`
//! injects their texels; both delta methods shadow the probe's light with them (spec §2.3's
//! suggested upgrade of ambient occlusion to directional occlusion), sharp where the probe's
//! light comes from a small bright source, which a volume's wide cones or coarse cells blur.

use super::rsm::RsmPass;
use crate::raster::Rasterizer;
use crate::scene_gpu::{GpuLight, GpuScene, Moved, ShadowLayer, pack_lights};
use bytemuck::{Pod, Zeroable};
use glam::{UVec4, Vec3, Vec4};
use mrshade_core::flags::Realness;
use mrshade_core::settings::{PROBE_LIGHTS_MAX, ShadowSettings};
use mrshade_gpu::shader::compute_pipeline;
use mrshade_gpu::timing::Recorder;
use mrshade_gpu::{GpuContext, bind, wgsl};
use mrshade_scene::Light;
use wgpu::util::DeviceExt;

/// The probe's directional lights on the GPU.
pub struct ProbeSet {
    /// The lights, as split from the probe.
    pub lights: Vec<Light>,
    /// Their `GpuLight`s.
    pub buffer: wgpu::Buffer,
}

/// One probe light as the per-pixel passes read it (`ProbeLookup` in probe_maps.wgsl): all
/// that a shadow test of its maps needs, in the fewest words and operations. Those passes
/// test every pixel against every light (32 by default); with the light, its layer's
/// `clip_from_world` and its pair read and combined in the loop, the test was two thirds of
/// `dlpv`'s merge.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct ProbeLookup {
    /// Continuous texel column of world point p in the light's maps: ⟨s, (p, 1)⟩.
    pub s: Vec4,
    /// Its texel row: ⟨t, (p, 1)⟩.
    pub t: Vec4,
    /// xyz: unit direction toward the light; w: the maps' bias, half a texel (m).
    pub toward_bias: Vec4,
    /// rgb: intensity × colour.
    pub intensity: Vec4,
    /// Real-only layer, virtual-only layer, the light's angular radius (f32 bits), 0.
    pub maps: UVec4,
}

/// The lookups of `pairs` (`layer_pairs`, w the angular radius) of `lights` whose maps of
/// side `resolution` are `layers` (`shadow_resolution`: the shadow maps' side, to which
/// `pack_lights` sized each light's texel).
pub fn probe_lookups(
    lights: &[GpuLight],
    layers: &[ShadowLayer],
    pairs: &[UVec4],
    resolution: u32,
    shadow_resolution: u32,
) -> Vec<ProbeLookup> {
    let res = resolution as f32;
    pairs
        .iter()
        .map(|pair| {
            let light = &lights[pair.z as usize];
            let m = layers[pair.x as usize].clip_from_world;
            // Orthographic (clip w = 1): texel = ((ndc.x + 1) / 2, (1 − ndc.y) / 2) × side.
            debug_assert_eq!(m.row(3), Vec4::W, "a probe light's map is orthographic");
            let toward = -light.direction_real.truncate();
            // Half a texel of the map, whose side is the light's shadow texel size at unit
            // distance × the shadow maps' side (pack_lights).
            let bias = 0.5 * light.cone.z * shadow_resolution as f32 / res;
            ProbeLookup {
                s: (m.row(0) + Vec4::W) * (0.5 * res),
                t: (Vec4::W - m.row(1)) * (0.5 * res),
                toward_bias: toward.extend(bias),
                intensity: light.intensity,
                maps: UVec4::new(pair.x, pair.y, pair.w, 0),
            }
        })
        .collect()
}

/// The probe's lights and their layers: maps as wide as the cube's bounding sphere (where
/// their texels matter) but deep enough toward the light to hold everything of the scene
/// there (the walls and ceiling of a room hide the sky from what is inside).
pub fn probe_layers(
    lights: &[Light],
    cube: (Vec3, Vec3),
    scene_box: Option<(Vec3, Vec3)>,
    shadows: &ShadowSettings,
) -> (Vec<GpuLight>, Vec<ShadowLayer>) {
    let (gpu_lights, mut layers) = pack_lights(lights, Some(cube), shadows);
    let center = (cube.0 + cube.1) * 0.5;
    let radius = bounding_radius(Some(cube));
    for layer in &mut layers {
        let dir = lights[layer.light as usize].direction();
        let toward_light = scene_box.map_or(0.0, |b| {
            mrshade_core::math::box_corners(b).iter().map(|c| (*c - center).dot(-dir)).fold(0.0, f32::max)
        });
        let back = toward_light.max(radius) * 1.01 + 1e-3;
        let eye = center - dir * back;
        let proj = glam::camera::rh::proj::directx::orthographic(-radius, radius, -radius, radius, back + radius, 0.0);
        layer.clip_from_world = proj * crate::scene_gpu::look_to(eye, dir);
    }
    (gpu_lights, layers)
}

impl ProbeSet {
    /// `lights`' maps around `cube` (`label`: the GPU objects' prefix).
    pub fn new(
        device: &wgpu::Device,
        label: &str,
        lights: Vec<Light>,
        cube: (Vec3, Vec3),
        scene_box: Option<(Vec3, Vec3)>,
        shadows: &ShadowSettings,
    ) -> (Self, Vec<GpuLight>, Vec<ShadowLayer>) {
        let (gpu_lights, layers) = probe_layers(&lights, cube, scene_box, shadows);
        let storage = |label: &str, contents: &[u8]| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            })
        };
        let set = Self {
            lights,
            buffer: storage(format!("{label}/probe_lights").as_str(), bytemuck::cast_slice(&gpu_lights)),
        };
        (set, gpu_lights, layers)
    }

    /// Moves the maps to cover `cube`; the lights and the layers for the RSM pass.
    pub fn follow(
        &self,
        queue: &wgpu::Queue,
        cube: (Vec3, Vec3),
        scene_box: Option<(Vec3, Vec3)>,
        shadows: &ShadowSettings,
    ) -> (Vec<GpuLight>, Vec<ShadowLayer>) {
        let (gpu_lights, layers) = probe_layers(&self.lights, cube, scene_box, shadows);
        queue.write_buffer(&self.buffer, 0, bytemuck::cast_slice(&gpu_lights));
        (gpu_lights, layers)
    }
}

/// Pairs of a set's layers: (real-only layer, virtual-only layer, light, 0), face by face.
pub fn layer_pairs(layers: &[ShadowLayer]) -> Vec<UVec4> {
    let real = layers.iter().enumerate().filter(|(_, l)| l.casters == Realness::Real);
    real.map(|(i, l)| {
        let face = layers[..i].iter().filter(|o| o.light == l.light && o.casters == Realness::Real).count();
        let virtual_layer = layers
            .iter()
            .enumerate()
            .filter(|(_, o)| o.light == l.light && o.casters == Realness::Virtual)
            .nth(face)
            .map(|(j, _)| j)
            .expect("every real layer has a virtual twin");
        UVec4::new(i as u32, virtual_layer as u32, l.light, 0)
    })
    .collect()
}

/// Half the diagonal of a box (what `pack_lights` covers a directional map with).
pub fn bounding_radius(bounds: Option<(Vec3, Vec3)>) -> f32 {
    bounds.map_or(1.0, |(lo, hi)| ((hi - lo).length() * 0.5).max(1e-3))
}

/// The probe's lights with their maps, for shadowing the probe's light per pixel
/// (shaders/lib/probe_maps.wgsl reads `resources()` as its three bindings).
pub struct ProbeMaps {
    /// The lights and their maps; `None` without a probe or with no lights asked for.
    drawn: Option<(ProbeSet, RsmPass)>,
    /// The lights as given, which `sample_lights(None)` restores.
    given: Vec<Light>,
    /// Whether the lights are drawn samples (`sample_lights`): points, whose shadows are sharp.
    sampled: bool,
    /// Per light: (real-only layer, virtual-only layer, light, its angular radius as f32 bits).
    pair_list: Vec<UVec4>,
    /// The same on the GPU (`dlpv`'s injection reads them).
    pairs: wgpu::Buffer,
    /// Per light: its `ProbeLookup` (the per-pixel passes read them).
    lookups: wgpu::Buffer,
    /// The shadow maps' side (pack_lights sizes the lights' texels to it).
    shadow_resolution: u32,
    /// (lights, map side, the soft test's search reach in texels, 0): the lookups carry the rest.
    info: wgpu::Buffer,
    /// Stands in for the maps' heights when there are none.
    unused: wgpu::Buffer,
    /// Side of the maps.
    resolution: u32,
    /// Per texel, the highest surface of its map within `soft_search_texels`
    /// (probe_maps_near.wgsl), for soft shadows only.
    near: Option<NearPass>,
}

/// The soft shadow test's blocker search reaches this share of a map's side at most
/// (shaders/lib/probe_maps_soft.wgsl): a blocker can stand the whole map's depth above a
/// point (the maps span the volume's bounding sphere), so a light of angular radius θ needs
/// res·tan θ texels; twelve taps over more than this miss a thin blocker.
const SOFT_SEARCH_SHARE: f32 = 0.15;

/// The blocker search's widest radius in texels of maps of side `resolution`.
fn soft_search_texels(resolution: u32) -> u32 {
    (SOFT_SEARCH_SHARE * resolution as f32).ceil() as u32
}

/// The maps' highest surface near each texel, as two passes (rows, then columns).
struct NearPass {
    pipeline: wgpu::ComputePipeline,
    /// Rows: heights → `rows`; columns: `rows` → `near`.
    groups: [wgpu::BindGroup; 2],
    near: wgpu::Buffer,
    resolution: u32,
    layers: u32,
}

impl NearPass {
    fn new(device: &wgpu::Device, label: &str, rsm: &RsmPass) -> Self {
        let bytes = rsm.heights.size();
        let buffer = |name: &str| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(&format!("{label}/{name}")),
                size: bytes,
                usage: wgpu::BufferUsages::STORAGE,
                mapped_at_creation: false,
            })
        };
        let (rows, near) = (buffer("probe_heights_rows"), buffer("probe_heights_near"));
        let cs = wgpu::ShaderStages::COMPUTE;
        let layout = bind::layout(
            device,
            &format!("{label}/probe_near_layout"),
            &[bind::storage(0, cs), bind::storage_rw(1, cs), bind::uniform(2, cs)],
        );
        let pipeline = compute_pipeline(device, &format!("{label}/probe_near"), NEAR_SHADER, &[&layout]);
        let reach = soft_search_texels(rsm.resolution) + 1;
        let group = |axis: u32, source: &wgpu::Buffer, target: &wgpu::Buffer| {
            let size = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(&format!("{label}/probe_near_size_{axis}")),
                contents: bytemuck::bytes_of(&UVec4::new(rsm.resolution, rsm.layers, reach, axis)),
                usage: wgpu::BufferUsages::UNIFORM,
            });
            bind::group(
                device,
                &format!("{label}/probe_near_group_{axis}"),
                &layout,
                &[source.as_entire_binding(), target.as_entire_binding(), size.as_entire_binding()],
            )
        };
        let groups = [group(0, &rsm.heights, &rows), group(1, &rows, &near)];
        Self { pipeline, groups, near, resolution: rsm.resolution, layers: rsm.layers }
    }

    fn record(&self, rec: &mut Recorder) {
        let groups = self.resolution.div_ceil(8);
        rec.compute("probe-maps-near", |pass| {
            pass.set_pipeline(&self.pipeline);
            for group in &self.groups {
                pass.set_bind_group(0, group, &[]);
                pass.dispatch_workgroups(groups, groups, self.layers);
            }
        });
    }
}

/// The near-surface passes' module (shaders/lib/lights.wgsl for `NO_RSM_HEIGHT`).
pub const NEAR_SHADER: &str = wgsl!("../../shaders/lib/lights.wgsl", "probe_maps_near.wgsl");

impl ProbeMaps {
    /// The maps of side `resolution` around `cube` of `lights` (each with its angular radius,
    /// `ibl::probe_lights_with_spread`; `label`: the GPU objects' prefix), with the highest
    /// surface near each texel when `soft_shadows` (shaders/lib/probe_maps_soft.wgsl).
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        ctx: &GpuContext,
        rasterizer: &Rasterizer,
        scene: &GpuScene,
        label: &str,
        lights: Vec<(Light, f32)>,
        resolution: u32,
        cube: (Vec3, Vec3),
        scene_box: Option<(Vec3, Vec3)>,
        shadows: &ShadowSettings,
        soft_shadows: bool,
    ) -> Self {
        let device = &ctx.device;
        let spreads: Vec<f32> = lights.iter().map(|(_, spread)| *spread).collect();
        let lights: Vec<Light> = lights.into_iter().map(|(light, _)| light).collect();
        let given = lights.clone();
        let drawn = (!lights.is_empty()).then(|| {
            let (set, gpu_lights, layers) = ProbeSet::new(device, label, lights, cube, scene_box, shadows);
            let rsm = RsmPass::new(ctx, rasterizer, scene, &set.buffer, &layers, resolution, shadows.resolution, false);
            let pairs = layer_pairs(&layers);
            let pairs =
                pairs.into_iter().map(|p| UVec4 { w: spreads[p.z as usize].to_bits(), ..p }).collect::<Vec<_>>();
            let lookups = probe_lookups(&gpu_lights, &layers, &pairs, resolution, shadows.resolution);
            (set, rsm, pairs, lookups)
        });
        let (pairs, mut lookups) = drawn.as_ref().map_or_else(Default::default, |d| (d.2.clone(), d.3.clone()));
        let mut pair_words = pairs.clone();
        pair_words.resize(pairs.len().max(1), UVec4::ZERO);
        // A uniform array of `PROBE_LIGHTS_MAX` (probe_maps.wgsl), bound whole.
        debug_assert!(pairs.len() <= PROBE_LIGHTS_MAX as usize, "at most {PROBE_LIGHTS_MAX} probe lights");
        lookups.resize(PROBE_LIGHTS_MAX as usize, ProbeLookup::zeroed());
        let init = |name: &str, contents: &[u8], usage| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(&format!("{label}/{name}")),
                contents,
                usage,
            })
        };
        let pairs_buffer = init("probe_pairs", bytemuck::cast_slice(&pair_words), wgpu::BufferUsages::STORAGE);
        let lookups = init(
            "probe_lookups",
            bytemuck::cast_slice(&lookups),
            wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        );
        let info = UVec4::new(pairs.len() as u32, resolution, soft_search_texels(resolution), 0);
        let info = init("probe_info", bytemuck::bytes_of(&info), wgpu::BufferUsages::UNIFORM);
        let unused = init("no_probe_lights", &[0; 256], wgpu::BufferUsages::STORAGE);
        let near = drawn.as_ref().filter(|_| soft_shadows).map(|(_, rsm, _, _)| NearPass::new(device, label, rsm));
        Self {
            near,
            drawn: drawn.map(|(set, rsm, _, _)| (set, rsm)),
            given,
            sampled: false,
            pair_list: pairs,
            pairs: pairs_buffer,
            lookups,
            shadow_resolution: shadows.resolution,
            info,
            unused,
            resolution,
        }
    }

    /// Moves the maps to cover `cube` (drawn again by the next `record`).
    pub fn follow(
        &mut self,
        queue: &wgpu::Queue,
        cube: (Vec3, Vec3),
        scene_box: Option<(Vec3, Vec3)>,
        shadows: &ShadowSettings,
    ) {
        if let Some((set, rsm)) = &mut self.drawn {
            let (gpu_lights, layers) = set.follow(queue, cube, scene_box, shadows);
            rsm.set_layers(queue, &layers);
            // Sampled lights are points: every one casts a sharp shadow (angular radius 0).
            let pairs: Vec<UVec4> =
                self.pair_list.iter().map(|p| if self.sampled { UVec4 { w: 0, ..*p } } else { *p }).collect();
            let lookups = probe_lookups(&gpu_lights, &layers, &pairs, self.resolution, self.shadow_resolution);
            queue.write_buffer(&self.lookups, 0, bytemuck::cast_slice(&lookups));
        }
    }

    /// Replaces the lights by `samples` (as many, in the same order: `ProbeRegions::sampled`),
    /// points whose shadows are all sharp, or with `None` restores the lights given to `new`
    /// with their angular radii; the maps then need drawing again (`record`). The mean of the
    /// maps' shadow tests over many samples is each region's power-weighted visibility.
    pub fn sample_lights(
        &mut self,
        queue: &wgpu::Queue,
        samples: Option<Vec<Light>>,
        cube: (Vec3, Vec3),
        scene_box: Option<(Vec3, Vec3)>,
        shadows: &ShadowSettings,
    ) {
        let Some((set, _)) = &mut self.drawn else { return };
        self.sampled = samples.is_some();
        set.lights = samples.unwrap_or_else(|| self.given.clone());
        debug_assert_eq!(set.lights.len(), self.given.len(), "one sample per light");
        self.follow(queue, cube, scene_box, shadows);
    }

    /// Whether the lights are drawn samples (`sample_lights`).
    pub fn sampled(&self) -> bool {
        self.sampled
    }

    /// Draws the maps.
    pub fn record(&self, rec: &mut Recorder, rasterizer: &Rasterizer) {
        self.record_with(rec, rasterizer, &[]);
    }

    /// Draws the maps, and `others` (the scene lights' maps, with the casters that moved for
    /// them) in the same passes.
    pub fn record_with(&self, rec: &mut Recorder, rasterizer: &Rasterizer, others: &[(&RsmPass, Moved)]) {
        let mut sets = others.to_vec();
        if let Some((_, rsm)) = &self.drawn {
            // The maps follow the virtual content's cube: every layer moves with it.
            sets.push((rsm, Moved::ALL));
        }
        RsmPass::record_sets(rec, rasterizer, &sets, false);
        if let Some(near) = &self.near {
            near.record(rec);
        }
    }

    /// The lights, the maps' texels and the pairs (`dlpv` injects the texels), and how many
    /// pairs of maps of which side; `None` without lights.
    pub fn maps(&self) -> Option<([&wgpu::Buffer; 3], u32, u32)> {
        let (set, rsm) = self.drawn.as_ref()?;
        Some(([&set.buffer, &rsm.texels, &self.pairs], self.pair_list.len() as u32, self.resolution))
    }

    /// The layout entries of `resources()`, bindings `first`… (compute).
    pub fn layout_entries(first: u32) -> [wgpu::BindGroupLayoutEntry; 4] {
        let cs = wgpu::ShaderStages::COMPUTE;
        [
            bind::uniform(first, cs),
            bind::storage(first + 1, cs),
            bind::uniform(first + 2, cs),
            bind::storage(first + 3, cs),
        ]
    }

    /// The lights' lookups, the maps' heights toward their lights, the info, and the highest
    /// surface near each texel (shaders/lib/probe_maps_soft.wgsl).
    pub fn resources(&self) -> [wgpu::BindingResource<'_>; 4] {
        let heights = match &self.drawn {
            Some((_, rsm)) => &rsm.heights,
            None => &self.unused,
        };
        let near = self.near.as_ref().map_or(&self.unused, |n| &n.near);
        [
            self.lookups.as_entire_binding(),
            heights.as_entire_binding(),
            self.info.as_entire_binding(),
            near.as_entire_binding(),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shaders_hold_as_many_lookups_as_the_settings_allow_lights() {
        let wgsl = include_str!("../../shaders/lib/probe_maps.wgsl");
        assert!(wgsl.contains(&format!("const PROBE_LIGHTS_MAX: u32 = {PROBE_LIGHTS_MAX}u;")));
    }
}
