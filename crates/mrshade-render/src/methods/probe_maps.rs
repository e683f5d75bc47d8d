//! The directional lights the probe is split into (median cut, `ibl::probe_lights`) and their
//! real-only and virtual-only maps around a delta method's volume: as wide as the volume's
//! bounding sphere, deep enough toward each light to hold everything of the scene there. `dlpv`
//! injects their texels; both delta methods shadow the probe's light with them (spec §2.3's
//! suggested upgrade of ambient occlusion to directional occlusion), sharp where the probe's
//! light comes from a small bright source, which a volume's wide cones or coarse cells blur.

use super::rsm::RsmPass;
use crate::raster::Rasterizer;
use crate::scene_gpu::{GpuLight, GpuScene, ShadowLayer, pack_lights};
use glam::{UVec4, Vec3};
use mrshade_core::flags::Realness;
use mrshade_core::settings::ShadowSettings;
use mrshade_gpu::timing::Recorder;
use mrshade_gpu::{GpuContext, bind};
use mrshade_scene::Light;
use wgpu::util::DeviceExt;

/// The probe's directional lights on the GPU.
pub struct ProbeSet {
    /// The lights, as split from the probe.
    pub lights: Vec<Light>,
    /// Their `GpuLight`s.
    pub buffer: wgpu::Buffer,
    /// `clip_from_world` of their layers (the per-pixel passes look up visibility).
    pub clip_from_world: wgpu::Buffer,
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
    ) -> (Self, Vec<ShadowLayer>) {
        let (gpu_lights, layers) = probe_layers(&lights, cube, scene_box, shadows);
        let storage = |label: &str, contents: &[u8]| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            })
        };
        let clips: Vec<glam::Mat4> = layers.iter().map(|l| l.clip_from_world).collect();
        let set = Self {
            lights,
            buffer: storage(format!("{label}/probe_lights").as_str(), bytemuck::cast_slice(&gpu_lights)),
            clip_from_world: storage(format!("{label}/probe_clip_from_world").as_str(), bytemuck::cast_slice(&clips)),
        };
        (set, layers)
    }

    /// Moves the maps to cover `cube`; the layers for the RSM pass.
    pub fn follow(
        &self,
        queue: &wgpu::Queue,
        cube: (Vec3, Vec3),
        scene_box: Option<(Vec3, Vec3)>,
        shadows: &ShadowSettings,
    ) -> Vec<ShadowLayer> {
        let (gpu_lights, layers) = probe_layers(&self.lights, cube, scene_box, shadows);
        let clips: Vec<glam::Mat4> = layers.iter().map(|l| l.clip_from_world).collect();
        queue.write_buffer(&self.buffer, 0, bytemuck::cast_slice(&gpu_lights));
        queue.write_buffer(&self.clip_from_world, 0, bytemuck::cast_slice(&clips));
        layers
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
/// (shaders/lib/probe_maps.wgsl reads `resources()` as its five bindings).
pub struct ProbeMaps {
    /// The lights and their maps; `None` without a probe or with no lights asked for.
    drawn: Option<(ProbeSet, RsmPass)>,
    /// Per light: (real-only layer, virtual-only layer, light, its angular radius as f32 bits).
    pairs: wgpu::Buffer,
    /// (lights, map side, shadow-map resolution, 0).
    info: wgpu::Buffer,
    /// Stands in for the lights, matrices and texels when there are none.
    unused: wgpu::Buffer,
    /// Number of pairs (one per light).
    count: u32,
    /// Side of the maps.
    resolution: u32,
}

impl ProbeMaps {
    /// The maps of side `resolution` around `cube` of `lights` (each with its angular radius,
    /// `ibl::probe_lights_with_spread`; `label`: the GPU objects' prefix).
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
    ) -> Self {
        let device = &ctx.device;
        let spreads: Vec<f32> = lights.iter().map(|(_, spread)| *spread).collect();
        let lights: Vec<Light> = lights.into_iter().map(|(light, _)| light).collect();
        let drawn = (!lights.is_empty()).then(|| {
            let (set, layers) = ProbeSet::new(device, label, lights, cube, scene_box, shadows);
            let rsm = RsmPass::new(ctx, rasterizer, scene, &set.buffer, &layers, resolution, shadows.resolution, false);
            let pairs = layer_pairs(&layers);
            let pairs =
                pairs.into_iter().map(|p| UVec4 { w: spreads[p.z as usize].to_bits(), ..p }).collect::<Vec<_>>();
            (set, rsm, pairs)
        });
        let pairs = drawn.as_ref().map_or_else(Vec::new, |d| d.2.clone());
        let mut pair_words = pairs.clone();
        pair_words.resize(pairs.len().max(1), UVec4::ZERO);
        let init = |name: &str, contents: &[u8], usage| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(&format!("{label}/{name}")),
                contents,
                usage,
            })
        };
        let pairs_buffer = init("probe_pairs", bytemuck::cast_slice(&pair_words), wgpu::BufferUsages::STORAGE);
        let info = UVec4::new(pairs.len() as u32, resolution, shadows.resolution, 0);
        let info = init("probe_info", bytemuck::bytes_of(&info), wgpu::BufferUsages::UNIFORM);
        let unused = init("no_probe_lights", &[0; 256], wgpu::BufferUsages::STORAGE);
        Self {
            drawn: drawn.map(|(set, rsm, _)| (set, rsm)),
            pairs: pairs_buffer,
            info,
            unused,
            count: pairs.len() as u32,
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
            let layers = set.follow(queue, cube, scene_box, shadows);
            rsm.set_layers(queue, &layers);
        }
    }

    /// Draws the maps.
    pub fn record(&self, rec: &mut Recorder, rasterizer: &Rasterizer) {
        if let Some((_, rsm)) = &self.drawn {
            rsm.record_maps(rec, rasterizer, false);
        }
    }

    /// The lights, the maps' texels and the pairs (`dlpv` injects the texels), and how many
    /// pairs of maps of which side; `None` without lights.
    pub fn maps(&self) -> Option<([&wgpu::Buffer; 3], u32, u32)> {
        let (set, rsm) = self.drawn.as_ref()?;
        Some(([&set.buffer, &rsm.texels, &self.pairs], self.count, self.resolution))
    }

    /// The layout entries of `resources()`, bindings `first`… (compute).
    pub fn layout_entries(first: u32) -> [wgpu::BindGroupLayoutEntry; 5] {
        let cs = wgpu::ShaderStages::COMPUTE;
        [
            bind::storage(first, cs),
            bind::storage(first + 1, cs),
            bind::storage(first + 2, cs),
            bind::storage(first + 3, cs),
            bind::uniform(first + 4, cs),
        ]
    }

    /// The lights, their layers' `clip_from_world`, the maps' heights toward their lights, the
    /// pairs and the info.
    pub fn resources(&self) -> [wgpu::BindingResource<'_>; 5] {
        let (lights, clips, heights) = match &self.drawn {
            Some((set, rsm)) => (&set.buffer, &set.clip_from_world, &rsm.heights),
            None => (&self.unused, &self.unused, &self.unused),
        };
        [
            lights.as_entire_binding(),
            clips.as_entire_binding(),
            heights.as_entire_binding(),
            self.pairs.as_entire_binding(),
            self.info.as_entire_binding(),
        ]
    }
}
