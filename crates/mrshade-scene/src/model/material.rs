//! glTF metallic-roughness materials with the KHR extensions mrshade honours.

use glam::{Vec3, Vec4};

/// How a material's base-color alpha is used.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AlphaMode {
    /// Alpha ignored.
    Opaque,
    /// Fragments with alpha below the cutoff are discarded.
    Mask(f32),
    /// Alpha blending; rendered as opaque (the loader warns).
    Blend,
}

/// A texture slot of a material.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextureRef {
    /// Index into `Scene::textures`.
    pub texture: usize,
}

/// A decoded RGBA8 texture with its sampling state.
#[derive(Clone, Debug)]
pub struct Texture {
    /// For messages and GPU labels.
    pub name: String,
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// RGBA8 texels, row-major.
    pub rgba8: Vec<u8>,
    /// Whether the texels are sRGB-encoded colour (base color, emissive) or linear data.
    pub srgb: bool,
    /// Repeat (true) or clamp (false) along u.
    pub repeat_u: bool,
    /// Repeat (true) or clamp (false) along v.
    pub repeat_v: bool,
}

/// glTF 2.0 metallic-roughness material plus `KHR_materials_specular`, `_ior`,
/// `_transmission`, `_volume` and `_emissive_strength`.
#[derive(Clone, Debug)]
pub struct Material {
    /// Name for messages.
    pub name: String,
    /// Linear base color and alpha.
    pub base_color: Vec4,
    /// sRGB base color texture, multiplied with `base_color`.
    pub base_color_texture: Option<TextureRef>,
    /// Metalness in [0, 1].
    pub metallic: f32,
    /// Perceptual roughness in [0, 1].
    pub roughness: f32,
    /// Roughness in G, metalness in B.
    pub metallic_roughness_texture: Option<TextureRef>,
    /// Tangent-space normal map and its scale.
    pub normal_texture: Option<(TextureRef, f32)>,
    /// Ambient occlusion map (R) and its strength.
    pub occlusion_texture: Option<(TextureRef, f32)>,
    /// Emitted radiance (linear), `emissiveFactor × emissive_strength`.
    pub emissive: Vec3,
    /// sRGB emissive texture, multiplied with `emissive`.
    pub emissive_texture: Option<TextureRef>,
    /// `KHR_materials_specular.specularFactor`: strength of the dielectric specular lobe;
    /// 0 makes the surface purely Lambertian (contract).
    pub specular: f32,
    /// `KHR_materials_specular.specularColorFactor`: F0 tint of the dielectric lobe.
    pub specular_color: Vec3,
    /// `KHR_materials_ior.ior` (1.5 by default).
    pub ior: f32,
    /// `KHR_materials_transmission.transmissionFactor`.
    pub transmission: f32,
    /// `KHR_materials_volume.thicknessFactor` (metres, object scale).
    pub thickness: f32,
    /// `KHR_materials_volume.attenuationColor`.
    pub attenuation_color: Vec3,
    /// `KHR_materials_volume.attenuationDistance` (metres; infinite = clear).
    pub attenuation_distance: f32,
    /// Alpha handling.
    pub alpha_mode: AlphaMode,
    /// Whether back faces are lit as front faces.
    pub double_sided: bool,
}

impl Material {
    /// Moves its texture indices by `base` (its textures were appended after `base` others).
    pub(crate) fn offset_textures(&mut self, base: usize) {
        let slots = [
            self.base_color_texture.as_mut(),
            self.metallic_roughness_texture.as_mut(),
            self.normal_texture.as_mut().map(|(t, _)| t),
            self.occlusion_texture.as_mut().map(|(t, _)| t),
            self.emissive_texture.as_mut(),
        ];
        for slot in slots.into_iter().flatten() {
            slot.texture += base;
        }
    }
}

impl Default for Material {
    /// The glTF default material: white, fully rough dielectric.
    fn default() -> Self {
        Self {
            name: "default".into(),
            base_color: Vec4::ONE,
            base_color_texture: None,
            metallic: 1.0,
            roughness: 1.0,
            metallic_roughness_texture: None,
            normal_texture: None,
            occlusion_texture: None,
            emissive: Vec3::ZERO,
            emissive_texture: None,
            specular: 1.0,
            specular_color: Vec3::ONE,
            ior: 1.5,
            transmission: 0.0,
            thickness: 0.0,
            attenuation_color: Vec3::ONE,
            attenuation_distance: f32::INFINITY,
            alpha_mode: AlphaMode::Opaque,
            double_sided: false,
        }
    }
}

impl Material {
    /// The dielectric F0 of `KHR_materials_specular` with `KHR_materials_ior`:
    /// `((ior − 1)/(ior + 1))² · specularColor`, clamped to 1, times `specular`.
    pub fn dielectric_f0(&self) -> Vec3 {
        let r = (self.ior - 1.0) / (self.ior + 1.0);
        (r * r * self.specular_color).min(Vec3::ONE) * self.specular
    }
}
