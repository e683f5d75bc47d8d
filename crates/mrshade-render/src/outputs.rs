//! Reading results back: the composite and the AOVs a user debugs with.

use crate::passes::vpl::{GpuVpl, flags, kind};
use crate::renderer::Renderer;
use anyhow::Result;
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
        .chain(self.read_dir_aovs(ctx, &composite)?)
        .collect())
    }

    /// The `dir` method's AOVs: VPLs over the image, the ISM atlases, the split and merged
    /// indirect buffers and the probe's visibility ratio. Empty for other methods.
    fn read_dir_aovs(&self, ctx: &GpuContext, composite: &Composite) -> Result<Vec<Aov>> {
        let Some(dir) = &self.dir else { return Ok(Vec::new()) };
        let (iw, ih) = self.internal_size();
        let exposure = self.exposure();
        let visibility = self.read_probe_visibility(ctx)?.expect("dir method");
        let ratio_rgb = |v: &[[f32; 3]]| -> Vec<u8> {
            v.iter().flat_map(|r| r.map(|c| (c.clamp(0.0, 1.0) * 255.0 + 0.5) as u8)).collect()
        };
        let vpls = self.read_vpls(ctx)?;
        let IsmDepths { side, depths, .. } = self.read_ism_depths(ctx)?.expect("dir method");
        let far = 2.0 * dir.ism_resources.params.scene.w;
        let atlas = |depths: &[f32]| AovImage::Display {
            width: side,
            height: side,
            rgb: depths
                .iter()
                .flat_map(|&d| [if d.is_finite() { (255.0 * (1.0 - (d / far).clamp(0.0, 1.0))) as u8 } else { 0 }; 3])
                .collect(),
        };
        let scaled =
            |img: HdrImage| HdrImage { pixels: img.pixels.iter().map(|p| p.map(|c| c * exposure)).collect(), ..img };
        Ok(vec![
            Aov {
                name: "vpls",
                image: AovImage::Display {
                    width: composite.image.width,
                    height: composite.image.height,
                    rgb: self.vpl_overlay(&vpls, &composite.image),
                },
            },
            Aov { name: "vpls", image: AovImage::Table(vpl_table(&vpls)) },
            Aov { name: "ism_real", image: atlas(&depths.r) },
            Aov { name: "ism_virtual", image: atlas(&depths.rv) },
            Aov {
                name: "probe_visibility_rv",
                image: AovImage::Display { width: iw, height: ih, rgb: ratio_rgb(&visibility.rv) },
            },
            Aov {
                name: "probe_visibility_r",
                image: AovImage::Display { width: iw, height: ih, rgb: ratio_rgb(&visibility.r) },
            },
            Aov {
                name: "indirect_split_rv",
                image: AovImage::Linear(scaled(read_rgba16f(ctx, &dir.interleaved.light.rv)?)),
            },
            Aov {
                name: "indirect_rv",
                image: AovImage::Linear(scaled(read_rgba16f(ctx, &dir.filter.merged.light.rv)?)),
            },
            Aov { name: "indirect_r", image: AovImage::Linear(scaled(read_rgba16f(ctx, &dir.filter.merged.light.r)?)) },
        ])
    }

    /// The probe's visibility ratios (`dir` method): per internal pixel and color channel, the
    /// share of the probe's (cosine-weighted) light that reaches it in `L_rv` and in `L_r`;
    /// `None` for other methods.
    pub fn read_probe_visibility(&self, ctx: &GpuContext) -> Result<Option<Differential<Vec<[f32; 3]>>>> {
        let Some(dir) = &self.dir else { return Ok(None) };
        let merged = &dir.filter.merged;
        let weight = read_rgba16f(ctx, &merged.env_weight)?;
        let ratio = |visible: &Target| -> Result<Vec<[f32; 3]>> {
            let visible = read_rgba16f(ctx, visible)?;
            Ok(visible.pixels.iter().zip(&weight.pixels).map(|(v, w)| visibility_ratio(v, w)).collect())
        };
        Ok(Some(Differential { rv: ratio(&merged.env.rv)?, r: ratio(&merged.env.r)? }))
    }

    /// The merged, smoothed indirect light of both solutions (radiance, `dir` method).
    pub fn read_indirect(&self, ctx: &GpuContext) -> Result<Option<Differential<HdrImage>>> {
        let Some(dir) = &self.dir else { return Ok(None) };
        let m = &dir.filter.merged.light;
        Ok(Some(Differential { rv: read_rgba16f(ctx, &m.rv)?, r: read_rgba16f(ctx, &m.r)? }))
    }

    /// The imperfect shadow maps (`dir` method); `None` for other methods.
    pub fn read_ism_depths(&self, ctx: &GpuContext) -> Result<Option<IsmDepths>> {
        let Some(dir) = &self.dir else { return Ok(None) };
        let ism = &dir.ism_resources;
        let read = |buffer: &wgpu::Buffer| -> Result<Vec<f32>> {
            let raw: Vec<u32> = bytemuck::cast_slice(&readback::read_buffer(ctx, buffer)?).to_vec();
            Ok(raw.iter().map(|&v| if v == 0 { f32::INFINITY } else { f32::from_bits(u32::MAX - v) }).collect())
        };
        let depths = Differential { rv: read(&ism.atlas_virtual)?, r: read(&ism.atlas_real)? };
        Ok(Some(IsmDepths { side: ism.atlas_side(), tile: ism.params.tile.x, depths }))
    }

    /// This frame's VPLs (the `dir` method), empty otherwise.
    pub fn read_vpls(&self, ctx: &GpuContext) -> Result<Vec<GpuVpl>> {
        let Some(dir) = &self.dir else { return Ok(Vec::new()) };
        let parity = ((dir.frame() + 1) % 2) as usize;
        Ok(bytemuck::cast_slice(&readback::read_buffer(ctx, &dir.vpl.vpls[parity])?).to_vec())
    }

    /// Surface VPLs drawn over `image`: real VPLs of real light green, VPLs lit by virtual
    /// light cyan, VPLs on virtual surfaces orange, VPL3s (ir) red.
    fn vpl_overlay(&self, vpls: &[GpuVpl], image: &HdrImage) -> Vec<u8> {
        let mut rgb = image.to_srgb8();
        let (w, h) = (image.width as i32, image.height as i32);
        for v in vpls.iter().filter(|v| v.info.z == kind::SURFACE) {
            let clip = self.uniforms.clip_from_world * v.position.truncate().extend(1.0);
            if clip.w <= 0.0 {
                continue;
            }
            let x = ((clip.x / clip.w * 0.5 + 0.5) * w as f32) as i32;
            let y = ((0.5 - clip.y / clip.w * 0.5) * h as f32) as i32;
            let f = v.info.x;
            let color = if f & flags::IR != 0 {
                [255, 40, 40]
            } else if f & flags::REAL == 0 {
                [255, 160, 0]
            } else if f & flags::PATH_REAL != 0 {
                [40, 255, 60]
            } else {
                [0, 220, 255]
            };
            for dy in -1..=1 {
                for dx in -1..=1 {
                    let (px, py) = (x + dx, y + dy);
                    if px >= 0 && py >= 0 && px < w && py < h {
                        let i = ((py * w + px) * 3) as usize;
                        rgb[i..i + 3].copy_from_slice(&color);
                    }
                }
            }
        }
        rgb
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

/// Σw_c·V / Σw_c per channel; 1 where no environment VPL reached the pixel (as direct.wgsl).
fn visibility_ratio(visible: &[f32; 3], weight: &[f32; 3]) -> [f32; 3] {
    std::array::from_fn(|c| if weight[c] > 0.0 { visible[c] / weight[c] } else { 1.0 })
}

fn read_rgba16f(ctx: &GpuContext, target: &Target) -> Result<HdrImage> {
    let bytes = readback::read_texture(ctx, &target.texture)?;
    let halves: &[f16] = bytemuck::cast_slice(&bytes);
    let (width, height) = target.size();
    Ok(HdrImage {
        width,
        height,
        pixels: halves.chunks_exact(4).map(|t| [t[0].to_f32(), t[1].to_f32(), t[2].to_f32()]).collect(),
    })
}

/// The VPLs as CSV, one row per used slot.
fn vpl_table(vpls: &[GpuVpl]) -> String {
    let mut out = String::from(
        "slot,kind,source,bounces,real,ir,path_real,x,y,z,area,nx,ny,nz,power_r,power_g,power_b,power_ir_r,power_ir_g,power_ir_b\n",
    );
    for (slot, v) in vpls.iter().enumerate().filter(|(_, v)| v.info.z != kind::EMPTY) {
        let kind = if v.info.z == kind::SURFACE { "surface" } else { "directional" };
        let flag = |bit: u32| u32::from(v.info.x & bit != 0);
        let (p, n, e, i) = (v.position, v.normal, v.power, v.power_ir);
        out += &format!(
            "{slot},{kind},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n",
            v.info.y,
            v.info.w,
            flag(flags::REAL),
            flag(flags::IR),
            flag(flags::PATH_REAL),
            p.x,
            p.y,
            p.z,
            p.w,
            n.x,
            n.y,
            n.z,
            e.x,
            e.y,
            e.z,
            i.x,
            i.y,
            i.z
        );
    }
    out
}

/// The imperfect shadow-map atlases of one frame, read back.
pub struct IsmDepths {
    /// Atlas side (texels).
    pub side: u32,
    /// Tile side (texels); VPL `i`'s tile is column `i % (side / tile)`, row `i / (side / tile)`.
    pub tile: u32,
    /// Per texel of the real-only (`r`) and virtual-only (`rv`) atlases, row-major: the stored
    /// distance (m), infinite where nothing was splatted.
    pub depths: Differential<Vec<f32>>,
}
