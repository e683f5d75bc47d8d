//! Caustics of punctual lights (light tracing, `caustics`) against answers known in closed
//! form: a spot seen in a mirror, the power through a glass slab, and the differential
//! halves with virtual mirrors and blockers.

mod common;

use common::{Builder, lambert, point_on_plane};
use glam::Vec3;
use mrshade_core::flags::Realness::{self, Real, Virtual};
use mrshade_core::settings::ReferenceSettings;
use mrshade_reference::bsdf::fresnel_dielectric;
use mrshade_reference::lights::spot_factor;
use mrshade_reference::{CausticSettings, ReferenceImage, render_with};
use mrshade_scene::{Material, Session};
use std::f32::consts::PI;

const W: u32 = 64;
const H: u32 = 48;

fn render(session: &Session, photons: u64) -> ReferenceImage {
    render_with(session, None, &CausticSettings { photons_per_light: Some(photons) }, &|_, _| {})
}

fn mirror(reflectance: f32) -> Material {
    Material {
        name: "mirror".into(),
        base_color: Vec3::splat(reflectance).extend(1.0),
        metallic: 1.0,
        roughness: 0.0,
        ..Material::default()
    }
}

/// The mean of `f(x, y)` over the pixels of the `size × size` block at (`x0`, `y0`).
fn block(x0: u32, y0: u32, size: u32, f: impl Fn(u32, u32) -> f32) -> f32 {
    let mut sum = 0.0;
    for y in y0..y0 + size {
        for x in x0..x0 + size {
            sum += f(x, y);
        }
    }
    sum / (size * size) as f32
}

// A spot 1 m above a white-ish floor shines up at a horizontal mirror 2 m above the floor;
// the camera, 1.5 m up, looks straight down at the floor. The floor sees only the mirror
// image of the spot: at (0, 3, 0), shining down.
const LAMP: Vec3 = Vec3::new(0.0, 1.0, 0.0);
const MIRROR_Y: f32 = 2.0;
const CONES: (f32, f32) = (0.15, 0.35);
const INTENSITY: f32 = 3.0;
const ALBEDO: f32 = 0.5;
const REFLECTANCE: f32 = 0.8;

fn mirror_scene(mirror_realness: Realness) -> Builder {
    let mut b = Builder::new(Vec3::new(0.0, 1.5, 0.0), Vec3::NEG_Y);
    b.floor(5.0, 0.0, lambert(ALBEDO), Real).floor(2.0, MIRROR_Y, mirror(REFLECTANCE), mirror_realness).spot(
        LAMP,
        Vec3::Y,
        INTENSITY,
        CONES,
        Real,
    );
    b
}

/// The floor's radiance at `p` under the mirrored spot: ρ/π · R(θ) · I · t(θ)² · cos θ / d²,
/// with the metal's Schlick Fresnel R toward its base colour at the mirror's incidence angle
/// (which is the angle θ from the vertical).
fn mirrored_spot(p: Vec3) -> f32 {
    let image = Vec3::new(LAMP.x, 2.0 * MIRROR_Y - LAMP.y, LAMP.z);
    let to = image - p;
    let d = to.length();
    let cos = to.y / d;
    let reflectance = REFLECTANCE + (1.0 - REFLECTANCE) * (1.0 - cos).powi(5);
    ALBEDO / PI * reflectance * INTENSITY * spot_factor(cos, CONES.0, CONES.1) * cos / (d * d)
}

/// The closed form's mean over pixel (`x`, `y`) (a 4×4 grid: the render box-filters it).
fn expected(session: &Session, x: u32, y: u32) -> f32 {
    let mut sum = 0.0;
    for j in 0..4 {
        for i in 0..4 {
            let (px, py) = (x as f32 + (i as f32 + 0.5) / 4.0, y as f32 + (j as f32 + 0.5) / 4.0);
            sum += mirrored_spot(point_on_plane(session, px, py, 0.0));
        }
    }
    sum / 16.0
}

/// 8×8 blocks over the image: the centre, the inner cone's edge and the falloff.
const BLOCKS: [(u32, u32); 5] = [(28, 20), (0, 0), (56, 40), (0, 20), (28, 0)];

fn check_mirrored_spot(session: &Session, image: &mrshade_core::HdrImage, what: &str) {
    let mut worst = 0.0f32;
    for (x0, y0) in BLOCKS {
        let got = block(x0, y0, 8, |x, y| image.get(x, y)[0]);
        let want = block(x0, y0, 8, |x, y| expected(session, x, y));
        eprintln!(
            "{what}: block ({x0}, {y0}): {got:.5} vs closed form {want:.5} ({:+.2}%)",
            100.0 * (got / want - 1.0)
        );
        worst = worst.max((got / want - 1.0).abs());
    }
    assert!(worst < 0.03, "{what}: worst block off by {:.1}%", 100.0 * worst);
}

#[test]
fn a_spot_in_a_mirror_lights_the_floor_as_its_mirror_image_times_the_reflectance() {
    let session = mirror_scene(Real).session(W, H, ReferenceSettings { spp: 4, ..Default::default() });
    let out = render(&session, 1 << 19);
    check_mirrored_spot(&session, &out.l_rv, "L_rv");
    // Everything is real: both halves are the same numbers, and the composite is the photo.
    assert_eq!(out.l_rv.pixels, out.l_r.pixels);
    assert_eq!(out.composite.pixels, session.background.pixels);
    // Per pixel, within Monte Carlo noise of the closed form.
    let mut errors: Vec<f32> = (0..H)
        .flat_map(|y| (0..W).map(move |x| (x, y)))
        .map(|(x, y)| (out.l_rv.get(x, y)[0] / expected(&session, x, y) - 1.0).abs())
        .collect();
    errors.sort_by(f32::total_cmp);
    let (median, worst) = (errors[errors.len() / 2], errors[errors.len() - 1]);
    eprintln!("per pixel: median error {:.1}%, worst {:.1}%", 100.0 * median, 100.0 * worst);
    assert!(median < 0.05 && worst < 0.3, "median {median}, worst {worst}");
    // Deterministic for a seed, on any number of threads.
    assert_eq!(render(&session, 1 << 19).l_rv.pixels, out.l_rv.pixels);
}

#[test]
fn the_power_through_a_glass_slab_is_the_fresnel_and_beer_lambert_transmittance() {
    // A spot 3 m above the floor shines down through a 10 cm slab of absorbing glass whose
    // bottom is 2 m up; the camera, 1.9 m up under the slab, looks straight down and sees
    // the whole caustic. Shadow rays stop at the slab, so the floor is lit by the caustic alone.
    let (intensity, cones, height, thickness, ior) = (2.0f32, (0.12f32, 0.2f32), 3.0f32, 0.1f32, 1.5f32);
    let (attenuation, distance) = (0.7f32, 0.1f32);
    let glass = Material {
        name: "glass".into(),
        metallic: 0.0,
        roughness: 0.0,
        transmission: 1.0,
        ior,
        thickness,
        attenuation_color: Vec3::splat(attenuation),
        attenuation_distance: distance,
        ..Material::default()
    };
    let camera_height = 1.9;
    let slab = |realness| {
        let mut b = Builder::new(Vec3::new(0.0, camera_height, 0.0), Vec3::NEG_Y);
        b.floor(5.0, 0.0, lambert(ALBEDO), Real).spot_down(Vec3::Y * height, intensity, cones, Real);
        if let Some(realness) = realness {
            b.cuboid(
                Vec3::new(0.0, 2.0 + thickness / 2.0, 0.0),
                Vec3::new(1.0, thickness / 2.0, 1.0),
                glass.clone(),
                realness,
            );
        }
        b.session(W, H, ReferenceSettings { spp: 4, ..Default::default() })
    };
    // Power on the floor from the rendered radiance: E = πL/ρ, and every pixel covers the
    // same floor area, camera_height² times its area on the image plane at distance 1.
    let power = |image: &mrshade_core::HdrImage| {
        let tan_half = (0.8f32 * 0.5).tan();
        let pixel_area = (2.0 * tan_half * W as f32 / H as f32 / W as f32) * (2.0 * tan_half / H as f32);
        let sum: f64 = image.pixels.iter().map(|p| p[0] as f64).sum();
        sum as f32 * PI / ALBEDO * camera_height * camera_height * pixel_area
    };
    // Closed form: 2π I ∫ t(θ)² T(θ) sin θ dθ, with T the slab's transmittance along θ:
    // Fresnel F at both faces (equal by reciprocity), absorption a = e^(−σ·thickness/cos θt)
    // per crossing, and the light reflected back and forth inside: (1 − F)² a / (1 − F² a²).
    let sigma = -attenuation.ln() / distance;
    let transmittance = |cos: f32| {
        let (f, cos_t) = fresnel_dielectric(cos, 1.0 / ior);
        let a = (-sigma * thickness / cos_t).exp();
        (1.0 - f) * (1.0 - f) * a / (1.0 - f * f * a * a)
    };
    let integral = |with_slab: bool| {
        let n = 20_000;
        let step = cones.1 / n as f32;
        let mut sum = 0.0f64;
        for i in 0..n {
            let theta = (i as f32 + 0.5) * step;
            let t = if with_slab { transmittance(theta.cos()) } else { 1.0 };
            sum += (spot_factor(theta.cos(), cones.0, cones.1) * t * theta.sin() * step) as f64;
        }
        2.0 * PI * intensity * sum as f32
    };
    let (open, through) = (integral(false), integral(true));
    let unblocked = power(&render(&slab(None), 0).l_rv);
    let caustic = render(&slab(Some(Real)), 1 << 19);
    let got = power(&caustic.l_rv);
    eprintln!(
        "power: unblocked {unblocked:.5} (closed form {open:.5}); through the slab {got:.5} (closed form {through:.5}, \
         T = {:.4})",
        through / open
    );
    assert!((unblocked / open - 1.0).abs() < 0.01, "the direct light's power {unblocked} vs {open}");
    assert!((got / through - 1.0).abs() < 0.01, "the caustic's power {got} vs {through}");
    assert_eq!(caustic.l_rv.pixels, caustic.l_r.pixels);
    // A virtual slab: its caustic, and its shadow, are in L_rv only; L_r keeps the direct light.
    let virtual_slab = render(&slab(Some(Virtual)), 1 << 19);
    assert_eq!(virtual_slab.l_rv.pixels, caustic.l_rv.pixels);
    assert!((power(&virtual_slab.l_r) / open - 1.0).abs() < 0.01);
}

#[test]
fn sunlight_through_a_glass_slab_lights_the_floor_by_the_transmitted_irradiance() {
    // A directional light straight down through a clear slab like the one above: under its
    // middle the caustic's radiance is ρ/π · E · (1 − F)² / (1 − F²), F = 0.04 at both faces
    // and the light reflected back and forth inside summed.
    let glass = Material {
        name: "glass".into(),
        metallic: 0.0,
        roughness: 0.0,
        transmission: 1.0,
        thickness: 0.1,
        ..Material::default()
    };
    let irradiance = 2.0;
    let mut b = Builder::new(Vec3::new(0.0, 1.9, 0.0), Vec3::NEG_Y);
    b.floor(5.0, 0.0, lambert(ALBEDO), Real).cuboid(Vec3::new(0.0, 2.05, 0.0), Vec3::new(1.5, 0.05, 1.5), glass, Real);
    b.scene.lights.push(mrshade_scene::Light {
        name: "sun".into(),
        kind: mrshade_scene::LightKind::Directional,
        intensity: Vec3::splat(irradiance),
        world_from_light: glam::Mat4::from_rotation_x(-std::f32::consts::FRAC_PI_2),
        realness: Real,
    });
    let session = b.session(W, H, ReferenceSettings { spp: 4, ..Default::default() });
    let out = render(&session, 1 << 18);
    // Camera paths add light that the slab's underside reflects from the sunlit floor around
    // it (L D S D E, about 1%): the caustic is what the photons add to them.
    let camera_paths = render(&session, 0);
    let f = fresnel_dielectric(1.0, 1.0 / 1.5).0;
    let want = ALBEDO / PI * irradiance * (1.0 - f) * (1.0 - f) / (1.0 - f * f);
    let got = block(16, 8, 32, |x, y| out.l_rv.get(x, y)[0] - camera_paths.l_rv.get(x, y)[0]);
    eprintln!("floor under the slab: {got:.5} vs closed form {want:.5} ({:+.2}%)", 100.0 * (got / want - 1.0));
    assert!((got / want - 1.0).abs() < 0.01, "{got} vs {want}");
}

#[test]
fn a_virtual_mirror_casts_its_caustic_in_l_rv_only() {
    let session = mirror_scene(Virtual).session(W, H, ReferenceSettings { spp: 4, ..Default::default() });
    let out = render(&session, 1 << 19);
    check_mirrored_spot(&session, &out.l_rv, "L_rv, virtual mirror");
    assert!(out.l_r.pixels.iter().all(|p| *p == [0.0; 3]), "no mirror, no light on the floor in L_r");
    // The composite adds the caustic to the photo of the (real) floor.
    let (photo, composite) = (session.background.get(32, 24)[0], out.composite.get(32, 24)[0]);
    assert!(composite > photo + 0.1, "{composite} vs photo {photo}");
}

#[test]
fn a_virtual_blocker_removes_a_real_mirrors_caustic_from_l_rv_only() {
    // A black virtual plate between the lamp and the real mirror (above the camera, unseen).
    let mut b = mirror_scene(Real);
    b.floor(1.0, 1.75, lambert(0.0), Virtual);
    let session = b.session(W, H, ReferenceSettings { spp: 4, ..Default::default() });
    let out = render(&session, 1 << 19);
    check_mirrored_spot(&session, &out.l_r, "L_r, virtual blocker");
    assert!(out.l_rv.pixels.iter().all(|p| *p == [0.0; 3]), "the plate blocks the caustic in L_rv");
    // The composite darkens the photo where the real caustic was.
    let (photo, composite) = (session.background.get(32, 24)[0], out.composite.get(32, 24)[0]);
    assert!(composite < photo - 0.01, "{composite} vs photo {photo}");
}

/// The cost of the caustics pass on two benchmark scenes with delta surfaces (`desk-glass`,
/// `desk-mirror`) lit by the real desk lamp of `desk-spot-real`, at the benchmark test's
/// 160×120 and 32 spp with the default photon count. Run with `--ignored --nocapture`; with
/// `CAUSTICS_PNG_DIR` set, it writes the composites there.
#[test]
#[ignore]
fn cost_of_the_caustics_pass_on_benchmark_scenes() {
    use mrshade_scene::SessionOverrides;
    let dir = std::path::PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/benchmark"));
    let overrides = SessionOverrides { set: vec!["reference.spp=32".into()], ..Default::default() };
    let lamp = Session::load(&dir.join("desk-spot-real/session.toml"), &overrides).unwrap().scene.lights;
    for scene in ["desk-glass", "desk-mirror"] {
        let mut session = Session::load(&dir.join(scene).join("session.toml"), &overrides).unwrap();
        session.scene.lights = lamp.clone();
        // The fastest of three runs (the machine may be busy).
        let time = |photons| {
            let mut best = f32::INFINITY;
            let mut out = None;
            for _ in 0..3 {
                let started = std::time::Instant::now();
                out = Some(render_with(&session, None, &CausticSettings { photons_per_light: photons }, &|_, _| {}));
                best = best.min(started.elapsed().as_secs_f32());
            }
            (out.unwrap(), best)
        };
        let (without, t0) = time(Some(0));
        let (with, t1) = time(None);
        let (o, w) = (&session.output, session.settings.reference);
        let photons = mrshade_reference::caustics::default_photons(o.width, o.height, w.spp);
        let gain: f32 = (with.l_rv.pixels.iter().zip(&without.l_rv.pixels)).map(|(a, b)| a[0] - b[0]).sum();
        eprintln!(
            "{scene}: {t0:.2} s without caustics, {t1:.2} s with {photons} photons (+{:.0}%); caustic adds {:.3} to \
             Σ L_rv (red)",
            100.0 * (t1 / t0 - 1.0),
            gain
        );
        if let Ok(out) = std::env::var("CAUSTICS_PNG_DIR") {
            let mut caustic = with.l_rv.clone();
            for (c, b) in caustic.pixels.iter_mut().zip(&without.l_rv.pixels) {
                *c = std::array::from_fn(|i| (c[i] - b[i]) * 4.0);
            }
            for (name, c) in [("without", &without.composite), ("with", &with.composite), ("caustic-x4", &caustic)] {
                let path = std::path::Path::new(&out).join(format!("{scene}-{name}.png"));
                image::RgbImage::from_raw(c.width, c.height, c.to_srgb8()).unwrap().save(path).unwrap();
            }
        }
    }
}
