//! Materials and their textures.

use super::buffers::{read_uri, view_bytes};
use super::describe;
use crate::budget::Budget;
use crate::images::{MAX_RADIANCE, decode_rgba8};
use crate::{AlphaMode, AssetSource, Material, Texture, TextureRef};
use anyhow::{Context, Result, bail};
use glam::{Vec3, Vec4};
use std::collections::HashMap;

/// Decoded textures, one per (glTF texture, colour space) used by a material slot.
#[derive(Default)]
pub struct TextureCache {
    by_key: HashMap<(usize, bool), usize>,
    textures: Vec<Texture>,
}

impl TextureCache {
    /// The texture of `info` decoded for sRGB colour (`srgb`) or linear data.
    fn get(
        &mut self,
        info_texture: gltf::Texture,
        srgb: bool,
        buffers: &[Vec<u8>],
        folder: &AssetSource,
        budget: &mut Budget,
    ) -> Result<TextureRef> {
        let key = (info_texture.index(), srgb);
        if let Some(&texture) = self.by_key.get(&key) {
            return Ok(TextureRef { texture });
        }
        let texture = decode_texture(&info_texture, srgb, buffers, folder, budget)
            .with_context(|| format!("texture {}", describe(Some(info_texture.index()), info_texture.name())))?;
        self.textures.push(texture);
        self.by_key.insert(key, self.textures.len() - 1);
        Ok(TextureRef { texture: self.textures.len() - 1 })
    }

    /// All decoded textures, indexed by `TextureRef::texture`.
    pub fn into_textures(self) -> Vec<Texture> {
        self.textures
    }
}

fn decode_texture(
    texture: &gltf::Texture,
    srgb: bool,
    buffers: &[Vec<u8>],
    folder: &AssetSource,
    budget: &mut Budget,
) -> Result<Texture> {
    let image = texture.source();
    let bytes = match image.source() {
        gltf::image::Source::View { view, .. } => view_bytes(&view, buffers)?.to_vec(),
        gltf::image::Source::Uri { uri, .. } => read_uri(uri, folder)?,
    };
    let decoded = decode_rgba8(&bytes, budget)
        .with_context(|| format!("image {} cannot be decoded", describe(Some(image.index()), image.name())))?;
    use gltf::texture::WrappingMode;
    let sampler = texture.sampler();
    Ok(Texture {
        name: texture.name().or(image.name()).unwrap_or("texture").to_string(),
        width: decoded.width(),
        height: decoded.height(),
        rgba8: decoded.into_raw(),
        srgb,
        repeat_u: sampler.wrap_s() != WrappingMode::ClampToEdge,
        repeat_v: sampler.wrap_t() != WrappingMode::ClampToEdge,
    })
}

/// Converts one glTF material, checking that every factor is in its valid range.
pub fn load_material(
    m: &gltf::Material,
    buffers: &[Vec<u8>],
    folder: &AssetSource,
    textures: &mut TextureCache,
    budget: &mut Budget,
    warnings: &mut Vec<String>,
) -> Result<Material> {
    let name = m.name().map(str::to_string).unwrap_or_else(|| format!("material {}", m.index().unwrap_or(0)));
    let mut slot = |info: Option<gltf::texture::Info>, srgb: bool, what: &str| -> Result<Option<TextureRef>> {
        let Some(info) = info else { return Ok(None) };
        if info.tex_coord() != 0 {
            warnings.push(format!(
                "material '{name}': {what} uses TEXCOORD_{} and is ignored (only TEXCOORD_0 is read)",
                info.tex_coord()
            ));
            return Ok(None);
        }
        textures.get(info.texture(), srgb, buffers, folder, budget).map(Some)
    };
    let pbr = m.pbr_metallic_roughness();
    let base_color_texture = slot(pbr.base_color_texture(), true, "baseColorTexture")?;
    let metallic_roughness_texture = slot(pbr.metallic_roughness_texture(), false, "metallicRoughnessTexture")?;
    let emissive_texture = slot(m.emissive_texture(), true, "emissiveTexture")?;
    let normal_texture = match m.normal_texture() {
        Some(n) if n.tex_coord() == 0 => Some((textures.get(n.texture(), false, buffers, folder, budget)?, n.scale())),
        _ => None,
    };
    let occlusion_texture = match m.occlusion_texture() {
        Some(o) if o.tex_coord() == 0 => {
            Some((textures.get(o.texture(), false, buffers, folder, budget)?, o.strength()))
        }
        _ => None,
    };

    let specular = m.specular();
    let volume = m.volume();
    let ignored: Vec<&str> = [
        specular.as_ref().and_then(|s| s.specular_texture()).map(|_| "specularTexture"),
        specular.as_ref().and_then(|s| s.specular_color_texture()).map(|_| "specularColorTexture"),
        m.transmission().and_then(|t| t.transmission_texture()).map(|_| "transmissionTexture"),
        volume.as_ref().and_then(|v| v.thickness_texture()).map(|_| "thicknessTexture"),
    ]
    .into_iter()
    .flatten()
    .collect();
    if !ignored.is_empty() {
        warnings.push(format!("material '{name}': {} ignored (factors are used)", ignored.join(", ")));
    }

    let alpha_mode = match m.alpha_mode() {
        gltf::material::AlphaMode::Opaque => AlphaMode::Opaque,
        gltf::material::AlphaMode::Mask => {
            warnings.push(format!("material '{name}': alphaMode MASK is rendered as OPAQUE (no alpha testing yet)"));
            AlphaMode::Mask(m.alpha_cutoff().unwrap_or(0.5))
        }
        gltf::material::AlphaMode::Blend => {
            warnings.push(format!("material '{name}': alphaMode BLEND is rendered as OPAQUE"));
            AlphaMode::Blend
        }
    };

    let material = Material {
        name: name.clone(),
        base_color: Vec4::from(pbr.base_color_factor()),
        base_color_texture,
        metallic: pbr.metallic_factor(),
        roughness: pbr.roughness_factor(),
        metallic_roughness_texture,
        normal_texture,
        occlusion_texture,
        emissive: Vec3::from(m.emissive_factor()) * m.emissive_strength().unwrap_or(1.0),
        emissive_texture,
        specular: specular.as_ref().map_or(1.0, |s| s.specular_factor()),
        specular_color: specular.as_ref().map_or(Vec3::ONE, |s| Vec3::from(s.specular_color_factor())),
        ior: m.ior().unwrap_or(1.5),
        transmission: m.transmission().map_or(0.0, |t| t.transmission_factor()),
        thickness: volume.as_ref().map_or(0.0, |v| v.thickness_factor()),
        attenuation_color: volume.as_ref().map_or(Vec3::ONE, |v| Vec3::from(v.attenuation_color())),
        attenuation_distance: volume.as_ref().map_or(f32::INFINITY, |v| v.attenuation_distance()),
        alpha_mode,
        double_sided: m.double_sided(),
    };
    check_ranges(&material)?;
    Ok(material)
}

/// Largest normal-map scale accepted: past it every normal lies in the tangent plane, and far
/// past it (1e39) the arithmetic overflows.
const MAX_NORMAL_SCALE: f32 = 1000.0;
/// Largest index of refraction accepted (real materials stay below 5).
const MAX_IOR: f32 = 100.0;

fn check_ranges(m: &Material) -> Result<()> {
    let unit = |v: f32, what: &str| -> Result<()> {
        if !(0.0..=1.0).contains(&v) {
            bail!("{what} {v} is outside [0, 1]");
        }
        Ok(())
    };
    for (i, c) in m.base_color.to_array().iter().enumerate() {
        unit(*c, &format!("baseColorFactor[{i}]"))?;
    }
    unit(m.metallic, "metallicFactor")?;
    unit(m.roughness, "roughnessFactor")?;
    unit(m.transmission, "transmissionFactor")?;
    for (i, c) in m.attenuation_color.to_array().iter().enumerate() {
        unit(*c, &format!("attenuationColor[{i}]"))?;
    }
    if !(m.emissive.is_finite() && m.emissive.min_element() >= 0.0 && m.emissive.max_element() <= MAX_RADIANCE) {
        bail!(
            "emissive {} (emissiveFactor × emissiveStrength, largest channel) must be between 0 and {MAX_RADIANCE:e}",
            mrshade_core::text::number(m.emissive.max_element())
        );
    }
    if let Some((_, scale)) = m.normal_texture
        && !(scale.is_finite() && scale.abs() <= MAX_NORMAL_SCALE)
    {
        bail!("normalTexture.scale {scale} must be between −{MAX_NORMAL_SCALE} and {MAX_NORMAL_SCALE}");
    }
    if let Some((_, strength)) = m.occlusion_texture {
        unit(strength, "occlusionTexture.strength")?;
    }
    if let AlphaMode::Mask(cutoff) = m.alpha_mode
        && !(cutoff.is_finite() && cutoff >= 0.0)
    {
        bail!("alphaCutoff {cutoff} must be ≥ 0");
    }
    if !(m.specular.is_finite()
        && m.specular >= 0.0
        && m.specular_color.is_finite()
        && m.specular_color.min_element() >= 0.0)
    {
        bail!("KHR_materials_specular factors must be finite and ≥ 0");
    }
    if !(m.ior == 0.0 || (1.0..=MAX_IOR).contains(&m.ior)) {
        bail!("ior {} must be between 1 and {MAX_IOR} (or 0)", m.ior);
    }
    if !(m.thickness.is_finite() && m.thickness >= 0.0) {
        bail!("thicknessFactor {} must be ≥ 0", m.thickness);
    }
    if m.attenuation_distance.is_nan() || m.attenuation_distance <= 0.0 {
        bail!("attenuationDistance {} must be > 0", m.attenuation_distance);
    }
    Ok(())
}
