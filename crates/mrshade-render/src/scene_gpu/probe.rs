//! The probe's image-based-lighting textures (see `crate::ibl`).

use crate::ibl::{DFG_SIZE, PreparedProbe, RADIANCE_LEVELS};
use half::f16;
use mrshade_core::HdrImage;
use mrshade_gpu::Target;
use mrshade_gpu::texture::write_level;
use mrshade_scene::Environment;

/// Prefiltered radiance (one mip per roughness level), irradiance, DFG table, and the sampler
/// of the contract's wrap (u repeats, v clamps).
pub struct GpuProbe {
    /// Radiance mip chain.
    pub radiance: Target,
    /// Irradiance map.
    pub irradiance: Target,
    /// Split-sum table (A, B).
    pub dfg: Target,
    /// Linear, u-repeat, v-clamp.
    pub sampler: wgpu::Sampler,
    /// Mips of `radiance`.
    pub radiance_mips: u32,
    /// The probe box-filtered, one mip per halving (`PreparedProbe::pyramid`).
    pub pyramid: Target,
    /// Mips of `pyramid`.
    pub pyramid_mips: u32,
}

const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

impl GpuProbe {
    /// Prefilters and uploads `environment`; without one, black 1×1 textures.
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, environment: Option<&Environment>) -> Self {
        let (radiance_levels, irradiance, pyramid_levels) = match environment {
            Some(env) => {
                let prepared = PreparedProbe::new(&env.image);
                (prepared.radiance, prepared.irradiance, prepared.pyramid)
            }
            None => {
                let black = HdrImage::filled(2, 1, [0.0; 3]);
                (vec![black.clone()], black.clone(), vec![black])
            }
        };
        let pyramid = upload(device, queue, "probe/pyramid", &pyramid_levels);
        let radiance = upload(device, queue, "probe/radiance", &radiance_levels);
        let irradiance = upload(device, queue, "probe/irradiance", std::slice::from_ref(&irradiance));
        let table = mrshade_core::brdf::dfg_table(DFG_SIZE, 256);
        let dfg_image =
            HdrImage { width: DFG_SIZE, height: DFG_SIZE, pixels: table.iter().map(|[a, b]| [*a, *b, 0.0]).collect() };
        let dfg = upload(device, queue, "probe/dfg", std::slice::from_ref(&dfg_image));
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("probe/sampler"),
            address_mode_u: wgpu::AddressMode::Repeat,
            address_mode_v: wgpu::AddressMode::ClampToEdge,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            mipmap_filter: wgpu::MipmapFilterMode::Linear,
            ..Default::default()
        });
        let radiance_mips = radiance_levels.len() as u32;
        debug_assert!(environment.is_none() || radiance_mips == RADIANCE_LEVELS);
        Self { radiance, irradiance, dfg, sampler, radiance_mips, pyramid, pyramid_mips: pyramid_levels.len() as u32 }
    }

    /// Layout entries of the probe's lighting at bindings 0–3 of a group, as shaders/lib/env.wgsl
    /// names them: env_radiance, env_irradiance, env_dfg_table, env_sampler.
    pub fn layout_entries(visibility: wgpu::ShaderStages) -> [wgpu::BindGroupLayoutEntry; 4] {
        use mrshade_gpu::bind;
        [
            bind::texture_float(0, visibility),
            bind::texture_float(1, visibility),
            bind::texture_float(2, visibility),
            bind::sampler(3, visibility, wgpu::SamplerBindingType::Filtering),
        ]
    }

    /// The resources of [`GpuProbe::layout_entries`], in binding order.
    pub fn resources(&self) -> [wgpu::BindingResource<'_>; 4] {
        use wgpu::BindingResource::{Sampler, TextureView};
        [
            TextureView(&self.radiance.view),
            TextureView(&self.irradiance.view),
            TextureView(&self.dfg.view),
            Sampler(&self.sampler),
        ]
    }
}

/// Uploads `levels` as the mip chain of one RGBA16F texture.
fn upload(device: &wgpu::Device, queue: &wgpu::Queue, label: &str, levels: &[HdrImage]) -> Target {
    let size = wgpu::Extent3d { width: levels[0].width, height: levels[0].height, depth_or_array_layers: 1 };
    let target = Target::new(
        device,
        label,
        size,
        levels.len() as u32,
        FORMAT,
        wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
    );
    for (level, img) in levels.iter().enumerate() {
        let texels: Vec<f16> = img.pixels.iter().flat_map(|p| [p[0], p[1], p[2], 1.0]).map(f16::from_f32).collect();
        write_level(queue, &target.texture, level as u32, (img.width, img.height), 8, bytemuck::cast_slice(&texels));
    }
    target
}
