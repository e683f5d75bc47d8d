//! Reading results back: the composite and the AOVs a user debugs with.

use crate::methods::AovView;
use crate::renderer::Renderer;
use crate::specular::caustics::LandedPhoton;
use crate::uniforms::image_point;
use anyhow::{Context, Result};
use half::f16;
use mrshade_core::flags::{SURFACE_COVERED, SURFACE_REAL};
use mrshade_core::{Differential, HdrImage};
use mrshade_gpu::{GpuContext, Target, readback};

/// The composited frame.
pub struct Composite {
    /// Linear camera values (exposure applied), output size.
    pub image: HdrImage,
    /// Fraction of each pixel covered by virtual surfaces.
    pub coverage: Vec<f32>,
}

/// An AOV image: linear (saved as EXR) or for display (saved as PNG).
pub enum AovImage {
    /// Linear values.
    Linear(HdrImage),
    /// 8-bit RGB for viewing.
    Display {
        /// Width.
        width: u32,
        /// Height.
        height: u32,
        /// RGB bytes.
        rgb: Vec<u8>,
    },
    /// A table (saved as CSV).
    Table(String),
}

/// A named AOV.
pub struct Aov {
    /// File stem.
    pub name: &'static str,
    /// The image.
    pub image: AovImage,
}

impl Renderer {
    /// Reads the composite back.
    pub fn read_composite(&self, ctx: &GpuContext) -> Result<Composite> {
        let texels = readback::read_rgba32f(ctx, &self.composite_targets.composite.texture)?;
        let (width, height) = self.output_size();
        Ok(Composite {
            image: HdrImage { width, height, pixels: texels.iter().map(|t| [t[0], t[1], t[2]]).collect() },
            coverage: texels.iter().map(|t| t[3]).collect(),
        })
    }

    /// Reads `L_rv` and `L_r` (radiance, before exposure) at the internal size.
    pub fn read_radiance(&self, ctx: &GpuContext) -> Result<Differential<HdrImage>> {
        Ok(Differential { rv: read_rgba16f(ctx, &self.radiance.rv)?, r: read_rgba16f(ctx, &self.radiance.r)? })
    }

    /// Reads back the vertices of instance `index` as the passes see them (after this
    /// frame's skinning and morphing): positions and normals in its object space (world
    /// space for a skinned instance).
    pub fn read_instance_vertices(&self, ctx: &GpuContext, index: usize) -> Result<Vec<(glam::Vec3, glam::Vec3)>> {
        let geometry = &self.scene.geometry;
        let (first, count) = geometry.vertex_range(index);
        let bytes = readback::read_buffer(ctx, &geometry.vertices)?;
        let vertices: &[crate::scene_gpu::Vertex] = bytemuck::cast_slice(&bytes);
        let range = vertices.get(first..first + count).context("the instance's vertices lie outside the buffer")?;
        Ok(range.iter().map(|v| (glam::Vec3::from(v.position), glam::Vec3::from(v.normal))).collect())
    }

    /// Reads the G-buffer flag words at the internal size.
    pub fn read_flags(&self, ctx: &GpuContext) -> Result<Vec<u32>> {
        readback::read_r32u(ctx, &self.gbuffer.flags.texture)
    }

    /// Every AOV: radiance pair, α, the difference, virtual mask, normals, flags.
    pub fn read_aovs(&self, ctx: &GpuContext) -> Result<Vec<Aov>> {
        let radiance = self.read_radiance(ctx)?;
        let exposure = self.exposure();
        let difference = HdrImage {
            width: radiance.rv.width,
            height: radiance.rv.height,
            pixels: radiance
                .rv
                .pixels
                .iter()
                .zip(&radiance.r.pixels)
                .map(|(a, b)| std::array::from_fn(|c| exposure * (a[c] - b[c])))
                .collect(),
        };
        let composite = self.read_composite(ctx)?;
        let (w, h) = self.output_size();
        let (iw, ih) = self.internal_size();
        let flags = self.read_flags(ctx)?;
        let normals = read_rgba16f(ctx, &self.gbuffer.normal_roughness)?;
        let depth = readback::read_rgba32f(ctx, &self.gbuffer.depth_motion.texture)?;
        let positions = HdrImage {
            width: iw,
            height: ih,
            pixels: depth
                .iter()
                .enumerate()
                .map(|(i, d)| {
                    if d[0] == 0.0 {
                        return [0.0; 3];
                    }
                    let (x, y) = ((i as u32 % iw) as f32 + 0.5, (i as u32 / iw) as f32 + 0.5);
                    let ndc = glam::Vec4::new(x / iw as f32 * 2.0 - 1.0, 1.0 - y / ih as f32 * 2.0, d[0], 1.0);
                    let p = self.uniforms.world_from_clip * ndc;
                    (p.truncate() / p.w).to_array()
                })
                .collect(),
        };
        let display = |width, height, rgb| AovImage::Display { width, height, rgb };
        Ok(vec![
            Aov { name: "difference_signed", image: display(iw, ih, signed_colors(&difference)) },
            Aov { name: "difference", image: AovImage::Linear(difference) },
            Aov { name: "l_rv", image: AovImage::Linear(radiance.rv) },
            Aov { name: "l_r", image: AovImage::Linear(radiance.r) },
            Aov { name: "alpha", image: AovImage::Linear(read_rgba16f(ctx, &self.composite_targets.alpha)?) },
            Aov {
                name: "virtual_mask",
                image: display(w, h, composite.coverage.iter().flat_map(|&c| [(c * 255.0 + 0.5) as u8; 3]).collect()),
            },
            Aov {
                name: "normals",
                image: display(
                    iw,
                    ih,
                    normals
                        .pixels
                        .iter()
                        .flat_map(|n| n.map(|v| ((v * 0.5 + 0.5).clamp(0.0, 1.0) * 255.0 + 0.5) as u8))
                        .collect(),
                ),
            },
            Aov { name: "flags", image: display(iw, ih, flags.iter().flat_map(|&f| flag_color(f)).collect()) },
            Aov { name: "position", image: AovImage::Linear(positions) },
            Aov { name: "normal", image: AovImage::Linear(normals.clone()) },
        ]
        .into_iter()
        .chain(self.read_specular_aovs(ctx)?)
        .chain(match self.method.indirect() {
            Some(indirect) => indirect.aovs(ctx, exposure)?,
            None => Vec::new(),
        })
        .chain(self.method.read_aovs(
            ctx,
            &AovView {
                composite: &composite,
                clip_from_world: self.uniforms.clip_from_world,
                exposure,
                internal_size: (iw, ih),
            },
        )?)
        .collect())
    }
}

impl Renderer {
    /// The specular stage's AOVs (none without the stage): its light in camera values, its
    /// reflection and refraction G-buffers: hit positions (directions where the ray left the
    /// scene) and path weights (Fresnel · transmittance), and the caustic buffer: irradiance
    /// of the `L_rv` and the `L_r` photons (W/m², at 1/`caustics.buffer_divisor` size; alpha
    /// dropped: the photon count), and its coarse level (the photons farther apart than
    /// `caustics.splat_max`, at 1/8 of that size); the photon hits: the power (W) of the
    /// last frame's `L_rv` photons summed in the pixel each landed in.
    fn read_specular_aovs(&self, ctx: &GpuContext) -> Result<Vec<Aov>> {
        let Some(stage) = &self.specular else { return Ok(Vec::new()) };
        let g = &stage.gbuffers;
        let rgb32 = |target: &Target| -> Result<HdrImage> {
            let (width, height) = target.size();
            let texels = readback::read_rgba32f(ctx, &target.texture)?;
            Ok(HdrImage { width, height, pixels: texels.iter().map(|t| [t[0], t[1], t[2]]).collect() })
        };
        let linear = |name, image| Aov { name, image: AovImage::Linear(image) };
        Ok(vec![
            linear("specular_light", read_rgba16f(ctx, &self.specular_light)?),
            linear("reflection_hit", rgb32(&g.reflection_hit)?),
            linear("refraction_hit", rgb32(&g.refraction_hit)?),
            linear("reflection_weight", read_rgba16f(ctx, &g.reflection_weight)?),
            linear("refraction_weight", read_rgba16f(ctx, &g.refraction_weight)?),
            linear("caustics_rv", read_rgba16f(ctx, &stage.caustic_buffer.levels[0].rv)?),
            linear("caustics_r", read_rgba16f(ctx, &stage.caustic_buffer.levels[0].r)?),
            linear("caustics_coarse_rv", read_rgba16f(ctx, &stage.caustic_buffer.levels[1].rv)?),
            linear("caustics_coarse_r", read_rgba16f(ctx, &stage.caustic_buffer.levels[1].r)?),
            linear("photon_hits", self.photon_hits(ctx)?),
        ])
    }

    /// The caustic photons of the last frame that landed (none without caustics).
    pub fn read_photons(&self, ctx: &GpuContext) -> Result<Vec<LandedPhoton>> {
        match self.specular.as_ref().and_then(|s| s.caustics.as_ref()) {
            Some(caustics) => caustics.read_photons(ctx),
            None => Ok(Vec::new()),
        }
    }

    /// The `photon_hits` AOV at the internal size (black without photons).
    fn photon_hits(&self, ctx: &GpuContext) -> Result<HdrImage> {
        let (width, height) = self.internal_size();
        let mut image = HdrImage { width, height, pixels: vec![[0.0; 3]; (width * height) as usize] };
        for photon in self.read_photons(ctx)?.iter().filter(|p| p.kind < 2) {
            let Some(at) = image_point(self.uniforms.clip_from_world, photon.position, (width, height)) else {
                continue;
            };
            if (0.0..width as f32).contains(&at.x) && (0.0..height as f32).contains(&at.y) {
                let pixel = &mut image.pixels[at.y as usize * width as usize + at.x as usize];
                *pixel = (glam::Vec3::from(*pixel) + photon.power).to_array();
            }
        }
        Ok(image)
    }
}

/// Background black, real surfaces grey-blue, virtual surfaces orange.
fn flag_color(flags: u32) -> [u8; 3] {
    if flags & SURFACE_COVERED == 0 {
        [0, 0, 0]
    } else if flags & SURFACE_REAL != 0 {
        [90, 110, 160]
    } else {
        [240, 140, 40]
    }
}

/// Added light in green, removed light (shadows) in red, on black; ±0.25 saturates.
fn signed_colors(diff: &HdrImage) -> Vec<u8> {
    diff.pixels
        .iter()
        .flat_map(|p| {
            let v = (p[0] + p[1] + p[2]) / 3.0;
            let m = ((v.abs() / 0.25).min(1.0) * 255.0 + 0.5) as u8;
            if v >= 0.0 { [0, m, 0] } else { [m, 0, 0] }
        })
        .collect()
}

/// A `Rgba16Float` target read back as linear RGB.
pub(crate) fn read_rgba16f(ctx: &GpuContext, target: &Target) -> Result<HdrImage> {
    let bytes = readback::read_texture(ctx, &target.texture)?;
    let halves: &[f16] = bytemuck::cast_slice(&bytes);
    let (width, height) = target.size();
    Ok(HdrImage {
        width,
        height,
        pixels: halves.chunks_exact(4).map(|t| [t[0].to_f32(), t[1].to_f32(), t[2].to_f32()]).collect(),
    })
}
