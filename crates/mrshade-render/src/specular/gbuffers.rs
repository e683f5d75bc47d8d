//! The reflection and refraction G-buffers in camera screen space (reflections spec §2.10,
//! Tables T6.1–T6.2): what the trace writes per traced pixel and the resolve reads.

use mrshade_gpu::Target;

/// The reflection and refraction G-buffers of one frame (the stage's AOVs).
pub struct SpecularGBuffers {
    /// Hit position and triangle + 1 (0: left the scene; xyz is then the direction).
    pub reflection_hit: Target,
    /// Last ray direction; w: the roughness the probe is looked up with if the ray left.
    pub reflection_dir: Target,
    /// Accumulated Fresnel · transmittance (rgb), 1 in w where traced.
    pub reflection_weight: Target,
    /// The refraction branch's hit, as `reflection_hit`.
    pub refraction_hit: Target,
    /// The refraction branch's direction, as `reflection_dir`.
    pub refraction_dir: Target,
    /// The refraction branch's weight, as `reflection_weight`.
    pub refraction_weight: Target,
    /// Real pixels: where the same reflected ray ends in the real-only world.
    pub reflection_real_hit: Target,
    /// Real pixels: where the same refracted ray ends in the real-only world.
    pub refraction_real_hit: Target,
}

impl SpecularGBuffers {
    pub(super) fn new(device: &wgpu::Device, size: (u32, u32)) -> Self {
        let usage =
            wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_SRC;
        let wide = wgpu::TextureFormat::Rgba32Float;
        let half = wgpu::TextureFormat::Rgba16Float;
        let t = |label: &str, format| Target::new_2d(device, &format!("specular/{label}"), size, format, usage);
        Self {
            reflection_hit: t("reflection_hit", wide),
            reflection_dir: t("reflection_dir", half),
            reflection_weight: t("reflection_weight", half),
            refraction_hit: t("refraction_hit", wide),
            refraction_dir: t("refraction_dir", half),
            refraction_weight: t("refraction_weight", half),
            reflection_real_hit: t("reflection_real_hit", wide),
            refraction_real_hit: t("refraction_real_hit", wide),
        }
    }

    pub(super) fn all(&self) -> [&Target; 8] {
        [
            &self.reflection_hit,
            &self.reflection_dir,
            &self.reflection_weight,
            &self.refraction_hit,
            &self.refraction_dir,
            &self.refraction_weight,
            &self.reflection_real_hit,
            &self.refraction_real_hit,
        ]
    }
}
