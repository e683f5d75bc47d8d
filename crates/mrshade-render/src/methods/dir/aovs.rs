//! The `dir` method's AOVs and read-backs: VPLs over the image and as a table, the ISM
//! atlases, the split and merged indirect buffers and the probe's visibility ratios.

use super::DirMethod;
use super::vpl::{GpuVpl, flags, kind};
use crate::methods::AovView;
use crate::outputs::{Aov, AovImage, read_rgba16f};
use crate::uniforms::image_point;
use anyhow::Result;
use mrshade_core::{Differential, HdrImage};
use mrshade_gpu::{GpuContext, readback};

impl DirMethod {
    /// The `dir` method's own AOVs: VPLs over the image, the ISM atlases and the split
    /// (interleaved) indirect buffer; the merged one and the probe's visibility are every
    /// method's ([`IndirectLight::aovs`](crate::methods::IndirectLight::aovs)).
    pub(super) fn aovs(&self, ctx: &GpuContext, view: &AovView) -> Result<Vec<Aov>> {
        let (exposure, composite) = (view.exposure, view.composite);
        let vpls = self.read_vpls(ctx)?;
        let IsmDepths { side, depths, .. } = self.read_ism_depths(ctx)?;
        let far = 2.0 * self.ism_resources.params.scene.w;
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
                    rgb: vpl_overlay(&vpls, &composite.image, view.clip_from_world),
                },
            },
            Aov { name: "vpls", image: AovImage::Table(vpl_table(&vpls)) },
            Aov { name: "ism_real", image: atlas(&depths.r) },
            Aov { name: "ism_virtual", image: atlas(&depths.rv) },
            Aov {
                name: "indirect_split_rv",
                image: AovImage::Linear(scaled(read_rgba16f(ctx, &self.interleaved.light.rv)?)),
            },
        ])
    }

    /// The probe's visibility ratios of the merged buffers (see
    /// [`IndirectLight::read_probe_visibility`](crate::methods::IndirectLight::read_probe_visibility)).
    pub fn read_probe_visibility(&self, ctx: &GpuContext) -> Result<Differential<Vec<[f32; 3]>>> {
        self.filter.merged.read_probe_visibility(ctx)
    }

    /// The merged, smoothed indirect light of both solutions (radiance).
    pub fn read_indirect(&self, ctx: &GpuContext) -> Result<Differential<HdrImage>> {
        self.filter.merged.read_light(ctx)
    }

    /// The imperfect shadow maps.
    pub fn read_ism_depths(&self, ctx: &GpuContext) -> Result<IsmDepths> {
        let ism = &self.ism_resources;
        let read = |buffer: &wgpu::Buffer| -> Result<Vec<f32>> {
            let raw: Vec<u32> = bytemuck::cast_slice(&readback::read_buffer(ctx, buffer)?).to_vec();
            Ok(raw.iter().map(|&v| if v == 0 { f32::INFINITY } else { f32::from_bits(u32::MAX - v) }).collect())
        };
        let depths = Differential { rv: read(&ism.atlas_virtual)?, r: read(&ism.atlas_real)? };
        Ok(IsmDepths { side: ism.atlas_side(), tile: ism.params.tile.x, depths })
    }

    /// This frame's VPLs.
    pub fn read_vpls(&self, ctx: &GpuContext) -> Result<Vec<GpuVpl>> {
        let parity = ((self.frame + 1) % 2) as usize;
        Ok(bytemuck::cast_slice(&readback::read_buffer(ctx, &self.vpl.vpls[parity])?).to_vec())
    }
}

/// Surface VPLs drawn over `image`: real VPLs of real light green, VPLs lit by virtual
/// light cyan, VPLs on virtual surfaces orange, VPL3s (ir) red.
fn vpl_overlay(vpls: &[GpuVpl], image: &HdrImage, clip_from_world: glam::Mat4) -> Vec<u8> {
    let mut rgb = image.to_srgb8();
    let (w, h) = (image.width as i32, image.height as i32);
    for v in vpls.iter().filter(|v| v.info.z == kind::SURFACE) {
        let Some(at) = image_point(clip_from_world, v.position.truncate(), (image.width, image.height)) else {
            continue;
        };
        let (x, y) = (at.x as i32, at.y as i32);
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
