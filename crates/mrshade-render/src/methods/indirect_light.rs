//! The contract between a light-transport method and the stages after it: the indirect
//! light that direct lighting adds and shadows the probe's light with. Any method that
//! computes indirect light fills one; the `dir` method's interleaved, history and merged
//! buffers have the same layout.

use crate::outputs::{Aov, AovImage, read_rgba16f};
use anyhow::Result;
use mrshade_core::{Differential, HdrImage};
use mrshade_gpu::{GpuContext, Target, bind};

/// Format of the indirect buffers.
pub const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// What a light-transport method hands to direct lighting (the neutral contract between
/// stages, not a method's private buffer): indirect light of both solutions and the
/// environment visibility sums, per color channel (rgb: Σw_c·V_rv, Σw_c·V_r and Σw_c, with w_c = a VPL's power in channel c · cos θ).
pub struct IndirectLight {
    /// Indirect `L_rv` and `L_r`.
    pub light: Differential<Target>,
    /// Environment visibility sums Σw_c·V of both solutions.
    pub env: Differential<Target>,
    /// Environment weight sums Σw_c, the ratios' denominators.
    pub env_weight: Target,
}

/// Number of targets in [`IndirectLight`].
pub const TARGETS: usize = 5;

impl IndirectLight {
    /// `FORMAT` targets named `<label>/rv`, `/r`, `/env_rv`, `/env_r`, `/env_weight`.
    pub fn new(device: &wgpu::Device, label: &str, size: (u32, u32)) -> Self {
        let usage =
            wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_SRC;
        let t = |name: &str| Target::new_2d(device, &format!("{label}/{name}"), size, FORMAT, usage);
        Self {
            light: Differential { rv: t("rv"), r: t("r") },
            env: Differential { rv: t("env_rv"), r: t("env_r") },
            env_weight: t("env_weight"),
        }
    }

    /// The targets in binding order (rv, r, env_rv, env_r, env_weight).
    pub fn all(&self) -> [&Target; TARGETS] {
        [&self.light.rv, &self.light.r, &self.env.rv, &self.env.r, &self.env_weight]
    }

    /// Layout entries of the targets as sampled textures from binding `first`.
    pub fn sampled_entries(first: u32) -> [wgpu::BindGroupLayoutEntry; TARGETS] {
        let cs = wgpu::ShaderStages::COMPUTE;
        let t = wgpu::TextureSampleType::Float { filterable: false };
        std::array::from_fn(|i| bind::texture(first + i as u32, cs, t, wgpu::TextureViewDimension::D2))
    }

    /// Layout entries of the targets as storage textures from binding 0 (what
    /// shaders/lib/indirect_out.wgsl declares in group 2).
    pub fn storage_entries() -> [wgpu::BindGroupLayoutEntry; TARGETS] {
        std::array::from_fn(|i| bind::storage_texture(i as u32, FORMAT))
    }

    /// The bind group resources of the targets.
    pub fn resources(&self) -> [wgpu::BindingResource<'_>; TARGETS] {
        self.all().map(|t| wgpu::BindingResource::TextureView(&t.view))
    }

    /// Size of the targets.
    pub fn size(&self) -> (u32, u32) {
        self.env_weight.size()
    }

    /// The indirect light of both solutions (radiance).
    pub fn read_light(&self, ctx: &GpuContext) -> Result<Differential<HdrImage>> {
        Ok(Differential { rv: read_rgba16f(ctx, &self.light.rv)?, r: read_rgba16f(ctx, &self.light.r)? })
    }

    /// The probe's visibility ratios: per internal pixel and color channel, the share of the
    /// probe's (cosine-weighted) light that reaches it in `L_rv` and in `L_r`.
    pub fn read_probe_visibility(&self, ctx: &GpuContext) -> Result<Differential<Vec<[f32; 3]>>> {
        let weight = read_rgba16f(ctx, &self.env_weight)?;
        let ratio = |visible: &Target| -> Result<Vec<[f32; 3]>> {
            let visible = read_rgba16f(ctx, visible)?;
            Ok(visible.pixels.iter().zip(&weight.pixels).map(|(v, w)| visibility_ratio(v, w)).collect())
        };
        Ok(Differential { rv: ratio(&self.env.rv)?, r: ratio(&self.env.r)? })
    }

    /// The AOVs of every method that computes indirect light: `indirect_rv`, `indirect_r`
    /// (camera values: radiance × `exposure`) and `probe_visibility_rv`, `_r` (the ratios as
    /// 8-bit images), at the internal size.
    pub fn aovs(&self, ctx: &GpuContext, exposure: f32) -> Result<Vec<Aov>> {
        let (w, h) = self.size();
        let visibility = self.read_probe_visibility(ctx)?;
        let ratio_rgb = |v: &[[f32; 3]]| -> Vec<u8> {
            v.iter().flat_map(|r| r.map(|c| (c.clamp(0.0, 1.0) * 255.0 + 0.5) as u8)).collect()
        };
        let light = self.read_light(ctx)?;
        let scaled =
            |img: HdrImage| HdrImage { pixels: img.pixels.iter().map(|p| p.map(|c| c * exposure)).collect(), ..img };
        Ok(vec![
            Aov {
                name: "probe_visibility_rv",
                image: AovImage::Display { width: w, height: h, rgb: ratio_rgb(&visibility.rv) },
            },
            Aov {
                name: "probe_visibility_r",
                image: AovImage::Display { width: w, height: h, rgb: ratio_rgb(&visibility.r) },
            },
            Aov { name: "indirect_rv", image: AovImage::Linear(scaled(light.rv)) },
            Aov { name: "indirect_r", image: AovImage::Linear(scaled(light.r)) },
        ])
    }
}

/// Σw_c·V / Σw_c per channel; 1 where no light of the probe was weighed at the pixel (as
/// direct.wgsl).
fn visibility_ratio(visible: &[f32; 3], weight: &[f32; 3]) -> [f32; 3] {
    std::array::from_fn(|c| if weight[c] > 0.0 { visible[c] / weight[c] } else { 1.0 })
}

/// A method's light at any surface point, not only where the camera looks: what the
/// specular stage shades the surfaces with that reflections and refractions reach off screen
/// (reflections spec §2.5: hit surfaces are shaded "with all primary lights and all VPLs").
/// The VPLs of `shaders/lib/vpl.wgsl` with their imperfect shadow maps, evaluated by
/// `shaders/lib/vpl_light.wgsl`; a method without VPLs hands on none.
pub struct PointLight<'a> {
    /// The VPL buffers of both parities (each frame writes one, keeping the other's VPLs).
    pub vpls: &'a [wgpu::Buffer; 2],
    /// Which of `vpls` the frame recorded last wrote.
    pub parity: usize,
    /// The ISMs' `IsmParams` uniform.
    pub ism_params: &'a wgpu::Buffer,
    /// The ISM atlas of the real casters.
    pub ism_real: &'a wgpu::Buffer,
    /// The ISM atlas of the virtual casters.
    pub ism_virtual: &'a wgpu::Buffer,
    /// VPL slots.
    pub count: u32,
    /// Lower bound of the VPL–receiver distance (m) in the geometry term.
    pub d_min: f32,
    /// Each point takes every `stride`-th VPL (scaled by `stride`), the subset rotating over
    /// pixels and frames: `dir` gives its interleave factor I (a quarter of the VPLs at the
    /// default 4), the cost of all of them being 0.45 ms at 1080p for a glass and a mirror.
    pub stride: u32,
}
