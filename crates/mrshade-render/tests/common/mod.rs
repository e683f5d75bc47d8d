//! Tiny synthetic sessions rendered on the test GPU (lavapipe in CI).
#![allow(dead_code)]

pub mod dvct;

use glam::{Vec3, Vec4};
use mrshade_core::{Differential, HdrImage};
use mrshade_gpu::GpuContext;
use mrshade_render::Renderer;
use mrshade_render::uniforms::FrameUniforms;
use mrshade_scene::{Session, SessionOverrides};
use mrshade_testkit::gltf::{GltfBuilder, quad, quat, write_exr, write_png};
use serde_json::json;

/// A scene under construction with its photo and probe.
pub struct Setup {
    pub gltf: GltfBuilder,
    pub size: (u32, u32),
    pub photo: Box<dyn Fn(u32, u32) -> [u8; 3]>,
    pub probe: Option<[f32; 3]>,
    /// The probe is black below the horizon.
    pub sky_only: bool,
    /// Radiance of a 2×2-texel sun in the probe, 45° above the horizon toward −z.
    pub sun: Option<[f32; 3]>,
    /// The sun's side in the probe's texels (5.6° each; default 2), an even number up to 14.
    pub sun_texels: u32,
    /// Radiance of the probe's half toward +x, if it differs from `probe`'s.
    pub probe_plus_x: Option<[f32; 3]>,
    /// Keys at the top of the session file (before any table).
    pub top_toml: String,
    /// Tables appended to the session file.
    pub extra_toml: String,
    /// Models written beside the scene as `<name>.gltf` (for `[[insert]]` tables).
    pub models: Vec<(String, GltfBuilder)>,
}

impl Setup {
    /// A camera 1 m above the origin looking straight down (yfov 1 rad), square image.
    pub fn top_down(size: u32) -> Self {
        let mut gltf = GltfBuilder::new();
        gltf.camera_node("camera", 1.0, None, [0.0, 1.0, 0.0], quat([1.0, 0.0, 0.0], -std::f32::consts::FRAC_PI_2));
        // Small shadow maps keep lavapipe fast; 512 texels resolve these scenes' shadows.
        let extra_toml = "[shadows]\nresolution = 512\n".to_string();
        Self {
            gltf,
            size: (size, size),
            photo: Box::new(|_, _| [128, 128, 128]),
            probe: None,
            sky_only: false,
            sun: None,
            sun_texels: 2,
            probe_plus_x: None,
            top_toml: "method = \"direct\"\n".into(),
            extra_toml,
            models: Vec::new(),
        }
    }

    /// A real floor under a dim sky with a small bright sun 45° up toward −z, seen from above
    /// (48² pixels).
    pub fn sun_over_floor() -> Self {
        let mut s = Self::top_down(48);
        s.probe = Some([0.02, 0.02, 0.02]);
        s.sun = Some([200.0, 200.0, 200.0]);
        s.plane(0.5, 0.0, 0.5, true);
        s
    }

    /// Adds a Lambertian quad of half size `half` at height `y`.
    pub fn plane(&mut self, half: f32, y: f32, albedo: f32, real: bool) -> &mut Self {
        let m = self.gltf.material(mrshade_testkit::gltf::lambert("plane", [albedo; 3]));
        let mesh = self.gltf.mesh(&quad(half), Some(m), true);
        self.gltf.node(json!({"name": "plane", "mesh": mesh, "translation": [0.0, y, 0.0], "extras": {"real": real}}));
        self
    }

    /// Adds a Lambertian box.
    pub fn cube(&mut self, center: [f32; 3], half: f32, real: bool) -> &mut Self {
        let m = self.gltf.material(mrshade_testkit::gltf::lambert("cube", [0.7; 3]));
        let mesh = self.gltf.mesh(&mrshade_testkit::gltf::cuboid([half; 3]), Some(m), true);
        self.gltf.node(json!({"name": "cube", "mesh": mesh, "translation": center, "extras": {"real": real}}));
        self
    }

    /// Adds a light pointing straight down from `position`.
    pub fn light(&mut self, light: serde_json::Value, position: [f32; 3], real: bool) -> &mut Self {
        let l = self.gltf.light(light);
        let down = quat([1.0, 0.0, 0.0], -std::f32::consts::FRAC_PI_2);
        self.gltf.node(json!({"name": "light", "translation": position, "rotation": down,
            "extensions": {"KHR_lights_punctual": {"light": l}}, "extras": {"real": real}}));
        self
    }

    /// Writes everything and loads the session.
    pub fn session(&self) -> (tempfile::TempDir, Session) {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        self.gltf.write_gltf(d, "scene");
        for (name, model) in &self.models {
            model.write_gltf(d, name);
        }
        write_png(&d.join("photo.png"), self.size.0, self.size.1, &self.photo);
        let mut toml = "scene = \"scene.gltf\"\nbackground = \"photo.png\"\nexposure = 1.0\n".to_string();
        toml += &self.top_toml;
        if let Some(c) = self.probe {
            let (sky_only, sun, plus_x) = (self.sky_only, self.sun, self.probe_plus_x);
            let half = self.sun_texels / 2;
            // u = atan2(x, −z) / 2π = 0 toward −z (texel columns 63 and 0), 1/4 toward +x
            // (columns 0–31 are the half toward +x); v = 45° / 180° (between rows 7 and 8).
            let in_sun = move |x: u32, y: u32| (x < half || x >= 64 - half) && (8 - half..8 + half).contains(&y);
            write_exr(&d.join("probe.exr"), 64, 32, move |x, y| match (sun, plus_x) {
                (Some(s), _) if in_sun(x, y) => s,
                _ if sky_only && y >= 16 => [0.0; 3],
                (_, Some(p)) if x < 32 => p,
                _ => c,
            });
            toml += "[environment]\nimage = \"probe.exr\"\n";
        }
        toml += &self.extra_toml;
        std::fs::write(d.join("session.toml"), toml).unwrap();
        let session = Session::load(&d.join("session.toml"), &SessionOverrides::default()).unwrap();
        (dir, session)
    }

    /// Renders one frame.
    pub fn render(&self) -> Rendered {
        let (_dir, session) = self.session();
        Rendered::new(session)
    }
}

/// A rendered frame with everything needed to inspect it.
pub struct Rendered {
    pub ctx: GpuContext,
    pub session: Session,
    pub renderer: Renderer,
    pub radiance: Differential<HdrImage>,
}

impl Rendered {
    pub fn new(session: Session) -> Self {
        let ctx = mrshade_testkit::gpu();
        let mut renderer = Renderer::new(&ctx, &session).unwrap();
        renderer.render_frames(&ctx, session.output.frames, |_| {}).unwrap();
        let radiance = renderer.read_radiance(&ctx).unwrap();
        Self { ctx, session, renderer, radiance }
    }

    /// Two points (at NDC depths 1 and 0.5) on the camera ray through internal pixel (x, y)'s centre.
    fn pixel_ray(&self, x: u32, y: u32) -> (Vec3, Vec3) {
        let u = FrameUniforms::new(&self.session, &self.session.view_at(0), 0, 1);
        let (w, h) = u.internal_size();
        let ndc = |depth: f32| {
            let p = u.world_from_clip
                * Vec4::new(
                    (x as f32 + 0.5) / w as f32 * 2.0 - 1.0,
                    1.0 - (y as f32 + 0.5) / h as f32 * 2.0,
                    depth,
                    1.0,
                );
            p.truncate() / p.w
        };
        (ndc(1.0), ndc(0.5))
    }

    /// Where the centre of internal pixel (x, y) hits the plane y = `height`.
    pub fn world_on_plane(&self, x: u32, y: u32, height: f32) -> Vec3 {
        let (a, b) = self.pixel_ray(x, y);
        let t = (height - a.y) / (b.y - a.y);
        a + (b - a) * t
    }

    /// Where the centre of internal pixel (x, y) hits the plane x = `at`.
    pub fn world_on_plane_x(&self, x: u32, y: u32, at: f32) -> Vec3 {
        let (a, b) = self.pixel_ray(x, y);
        let t = (at - a.x) / (b.x - a.x);
        a + (b - a) * t
    }

    /// Index of the internal pixel whose centre sees the floor (y = 0) nearest to `target`.
    pub fn floor_pixel(&self, target: Vec3) -> usize {
        let w = self.radiance.rv.width;
        let (x, y) = (0..w * self.radiance.rv.height)
            .map(|i| (i % w, i / w))
            .min_by_key(|&(x, y)| (self.world_on_plane(x, y, 0.0).distance(target) * 1e5) as u32)
            .unwrap();
        (y * w + x) as usize
    }

    /// Renders one more frame with `photo` uploaded (a live stream's frame: the photo counts
    /// as changed, and the view as moving).
    pub fn render_with_photo(&mut self, photo: &dyn Fn(u32, u32) -> [u8; 3]) {
        let (w, h) = (self.session.output.width, self.session.output.height);
        let rgb: Vec<u8> = (0..h).flat_map(|y| (0..w).flat_map(move |x| photo(x, y))).collect();
        let packed = mrshade_render::passes::upload::PackedPhoto::from_srgb8(&rgb, (w, h));
        let camera = self.renderer.session_camera();
        let mut profiler = mrshade_gpu::timing::profiler(&self.ctx, false).unwrap();
        let inputs =
            mrshade_render::FrameInputs { photo: Some(&packed), ..mrshade_render::FrameInputs::camera(camera) };
        self.renderer.render_untimed(&self.ctx, &mut profiler, &inputs).unwrap();
    }

    pub fn l_rv(&self, x: u32, y: u32) -> Vec3 {
        Vec3::from(self.radiance.rv.get(x, y))
    }

    pub fn l_r(&self, x: u32, y: u32) -> Vec3 {
        Vec3::from(self.radiance.r.get(x, y))
    }
}

/// Lambertian radiance of a surface with normal +Y at `p` lit by a point/spot light.
pub fn lambert_point(albedo: f32, intensity: f32, light: Vec3, p: Vec3, spot_factor: f32) -> f32 {
    let to = light - p;
    let d2 = to.length_squared();
    let cos = (to / d2.sqrt()).y.max(0.0);
    albedo / std::f32::consts::PI * intensity * spot_factor * cos / d2
}

/// Relative difference.
pub fn rel(a: f32, b: f32) -> f32 {
    (a - b).abs() / b.abs().max(1e-6)
}

/// Whether the segment from `a` to `b` passes through the axis-aligned box (centre, half size).
pub fn segment_hits_box(a: Vec3, b: Vec3, center: Vec3, half: f32) -> bool {
    let (lo, hi) = (center - Vec3::splat(half), center + Vec3::splat(half));
    let d = b - a;
    let (mut t0, mut t1) = (0.0f32, 1.0f32);
    for i in 0..3 {
        if d[i].abs() < 1e-9 {
            if a[i] < lo[i] || a[i] > hi[i] {
                return false;
            }
        } else {
            let (mut ta, mut tb) = ((lo[i] - a[i]) / d[i], (hi[i] - a[i]) / d[i]);
            if ta > tb {
                std::mem::swap(&mut ta, &mut tb);
            }
            t0 = t0.max(ta);
            t1 = t1.min(tb);
            if t0 > t1 {
                return false;
            }
        }
    }
    true
}

/// A box in a test scene.
#[derive(Clone, Copy)]
pub struct Blocker {
    pub center: Vec3,
    pub half: f32,
}

/// How a plane pixel relates to a light and some blockers, with a safety margin around
/// shadow edges (PCF softens them).
#[derive(Debug, PartialEq)]
pub enum ShadowClass {
    /// The camera does not see the plane here, or the pixel is near a shadow edge.
    Unknown,
    /// Clearly in the shadow of the blockers.
    Shadowed,
    /// Clearly lit.
    Lit,
}

pub fn classify(camera: Vec3, p: Vec3, light: Vec3, blockers: &[Blocker], margin: f32) -> ShadowClass {
    if blockers.iter().any(|b| segment_hits_box(camera, p, b.center, b.half + margin)) {
        return ShadowClass::Unknown;
    }
    if blockers.iter().any(|b| segment_hits_box(p, light, b.center, b.half - margin)) {
        ShadowClass::Shadowed
    } else if !blockers.iter().any(|b| segment_hits_box(p, light, b.center, b.half + margin)) {
        ShadowClass::Lit
    } else {
        ShadowClass::Unknown
    }
}

/// A mirror material (metal, smooth) and a clear glass one.
pub fn mirror() -> serde_json::Value {
    json!({"name": "mirror", "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1], "metallicFactor": 1.0, "roughnessFactor": 0.0}})
}

pub fn glass() -> serde_json::Value {
    json!({"name": "glass", "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1], "metallicFactor": 0.0, "roughnessFactor": 0.0},
        "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0}, "KHR_materials_ior": {"ior": 1.5},
            "KHR_materials_volume": {"thicknessFactor": 0.1, "attenuationColor": [0.6, 0.9, 0.7], "attenuationDistance": 0.2}}})
}
