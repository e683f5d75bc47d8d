//! Precomputed radiance transfer for rigid virtual objects (Franke §2.4, `[ibl] virtual =
//! "prt"`): transfer vectors with self-shadowing baked per vertex on the CPU on first use and
//! cached next to the session ([`cache`]), evaluated per pixel against the probe's SH
//! coefficients in each object's frame (`passes::probe_sh`). Deforming instances and pixels
//! without transfer fall back to plain SH irradiance.
//! Inputs: camera visibility buffer, geometry, transfer, SH coefficients. Output:
//! `irradiance` (rgb; a = 1 where PRT applies).

mod bake;
pub mod cache;

pub use bake::bake;

use crate::passes::probe_sh::ProbeShPass;
use crate::scene_gpu::Geometry;
use mrshade_core::flags::Realness;
use mrshade_gpu::timing::{Dispatch, Recorder};
use mrshade_gpu::{GpuContext, Target, bind, wgsl};
use mrshade_scene::Session;
use wgpu::util::DeviceExt;

/// The scene's baked transfer: which instances have it, and `coefficients` floats per vertex
/// of the scene's vertex buffer.
pub struct Transfer {
    /// Scene instance indices with transfer, in the order of their SH frames (1, 2, …).
    pub instances: Vec<u32>,
    /// SH coefficients per vertex: 9 or 16 (`ibl.prt_coefficients`).
    pub coefficients: usize,
    /// `coefficients` floats per vertex (zero for primitives without transfer).
    pub per_vertex: Vec<f32>,
    /// What could not be done (the cache not written).
    pub warnings: Vec<String>,
}

impl Transfer {
    /// Bakes (or reads from the session folder's cache) the transfer of every rigid virtual
    /// instance's primitive, `samples` rays per vertex, `coefficients` SH coefficients.
    pub fn of(session: &Session, geometry: &Geometry, samples: u32, coefficients: usize) -> Self {
        let scene = &session.scene;
        let cache_path = session.folder.as_ref().map(|f| f.join(cache::FILE_NAME));
        let mut store = cache_path.as_deref().map(cache::Cache::read).unwrap_or_default();
        let vertex_count: usize = scene.primitives.iter().map(|p| p.positions.len()).sum();
        let n = coefficients;
        let mut per_vertex = vec![0.0f32; vertex_count * n];
        let mut baked = vec![false; scene.primitives.len()];
        let mut instances = Vec::new();
        for (i, inst) in scene.instances.iter().enumerate() {
            let prim = &scene.primitives[inst.primitive];
            if inst.realness != Realness::Virtual || prim.is_deformable() || prim.positions.is_empty() {
                continue;
            }
            instances.push(i as u32);
            if std::mem::replace(&mut baked[inst.primitive], true) {
                continue;
            }
            let key = cache::key(prim, samples, n);
            let transfer = store.get_or_bake(key, prim.positions.len() * n, || bake(prim, samples, n));
            let base = geometry.base_vertex[inst.primitive] as usize * n;
            per_vertex[base..base + transfer.len()].copy_from_slice(transfer);
        }
        let mut warnings = Vec::new();
        if let Some(path) = &cache_path
            && let Err(e) = store.write_if_changed(path)
        {
            warnings.push(format!("cannot cache the baked PRT at {} ({e}); it will be baked again", path.display()));
        }
        Self { instances, coefficients, per_vertex, warnings }
    }
}

/// The per-pixel evaluation.
pub struct PrtPass {
    /// The pass over the internal size.
    dispatch: Dispatch,
    /// PRT irradiance (rgb) and where it applies (a).
    pub irradiance: Target,
}

impl PrtPass {
    /// GPU timing label.
    pub const LABEL: &'static str = "prt";

    /// Binds the camera's `visibility`, the geometry, `transfer` and `probe_sh`'s coefficients.
    pub fn new(
        ctx: &GpuContext,
        frame: &wgpu::Buffer,
        visibility: &wgpu::Buffer,
        geometry: &Geometry,
        transfer: &Transfer,
        probe_sh: &ProbeShPass,
        size: (u32, u32),
    ) -> Self {
        let device = &ctx.device;
        let cs = wgpu::ShaderStages::COMPUTE;
        let storage = |label: &str, bytes: &[u8]| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: bytes,
                usage: wgpu::BufferUsages::STORAGE,
            })
        };
        let mut per_vertex = transfer.per_vertex.clone();
        per_vertex.resize(per_vertex.len().max(16), 0.0);
        let transfer_buffer = storage("prt/transfer", bytemuck::cast_slice(&per_vertex));
        let mut frames = vec![0u32; geometry.instance_count().max(1)];
        for (k, &i) in transfer.instances.iter().enumerate() {
            frames[i as usize] = k as u32 + 1;
        }
        let frames = storage("prt/instance_frame", bytemuck::cast_slice(&frames));
        let irradiance = Target::new_2d(
            device,
            "prt/irradiance",
            size,
            wgpu::TextureFormat::Rgba16Float,
            wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::TEXTURE_BINDING,
        );
        let mut entries = vec![bind::uniform(0, cs)];
        entries.extend((1..9).map(|b| bind::storage(b, cs)));
        entries.push(bind::storage_texture(9, wgpu::TextureFormat::Rgba16Float));
        let layout = bind::layout(device, "prt/layout", &entries);
        let group = bind::group(
            device,
            "prt/group",
            &layout,
            &[
                frame.as_entire_binding(),
                visibility.as_entire_binding(),
                geometry.instances.as_entire_binding(),
                geometry.vertices.as_entire_binding(),
                geometry.indices.as_entire_binding(),
                geometry.triangles.as_entire_binding(),
                transfer_buffer.as_entire_binding(),
                frames.as_entire_binding(),
                probe_sh.coefficients.as_entire_binding(),
                wgpu::BindingResource::TextureView(&irradiance.view),
            ],
        );
        let constants = [("COEFFICIENTS", transfer.coefficients as f64)];
        let pipeline =
            mrshade_gpu::shader::compute_pipeline_with(device, "prt", SHADER, "cs_main", &[&layout], &constants);
        let workgroups = [size.0.div_ceil(8), size.1.div_ceil(8), 1];
        Self { dispatch: Dispatch { pipeline, groups: vec![group], workgroups }, irradiance }
    }

    /// Evaluates every pixel.
    pub fn record(&self, rec: &mut Recorder) {
        rec.compute(Self::LABEL, |pass| self.dispatch.record(pass));
    }
}

/// The evaluation module.
pub const SHADER: &str = wgsl!(
    "../../shaders/lib/frame.wgsl",
    "../../shaders/lib/gbuffer.wgsl",
    "../../shaders/lib/instance.wgsl",
    "../../shaders/lib/triangles.wgsl",
    "prt.wgsl",
);
