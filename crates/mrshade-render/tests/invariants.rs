//! Exact invariants of differential rendering (architecture guide §5.6, tier 3): no virtual
//! content gives the photo back; with every object real `L_rv == L_r`; the composite pass
//! computes exactly the documented formula.

mod common;

use mrshade_core::settings::Method;

use common::{Rendered, Setup};
use mrshade_core::flags::{SURFACE_COVERED, SURFACE_REAL};
use mrshade_core::settings::CompositeSettings;
use serde_json::json;

const SIZE: u32 = 32;

/// A textured photo, real plane and box, a real lamp and the probe; `virtual_cube` adds a
/// cube whose flag is `real: false` (or `true`, when `cube_is_real`).
fn scene(virtual_cube: bool, cube_is_real: bool, extra: &str) -> Setup {
    let mut s = Setup::top_down(SIZE);
    s.photo = Box::new(|x, y| [(x * 7 % 256) as u8, (y * 5 + 40) as u8, ((x + y) * 3) as u8]);
    s.probe = Some([0.6, 0.7, 0.9]);
    s.extra_toml += extra;
    s.plane(2.0, 0.0, 0.4, true).cube([-0.2, 0.1, 0.1], 0.1, true).light(
        json!({"type": "spot", "intensity": 1.5, "spot": {"innerConeAngle": 0.5, "outerConeAngle": 0.9}}),
        [0.2, 0.8, 0.0],
        true,
    );
    if virtual_cube {
        s.cube([0.1, 0.15, -0.05], 0.08, cube_is_real);
    }
    s
}

fn photo_bytes(s: &Setup) -> Vec<u8> {
    (0..SIZE * SIZE).flat_map(|i| (s.photo)(i % SIZE, i / SIZE)).collect()
}

fn composite_bytes(r: &Rendered) -> Vec<u8> {
    r.renderer.read_composite(&r.ctx).unwrap().image.to_srgb8()
}

/// Settings per method that keep these tests fast: `dir` over a few frames (its multiple
/// bounces and smoothing run from frame 2 on).
fn method_toml(method: Method) -> String {
    let frames = match method {
        Method::Dir => "[output]\nframes = 3\n",
        _ => "",
    };
    format!("method = \"{}\"\n{frames}", method.name())
}

#[test]
fn no_virtual_content_returns_the_photo() {
    for method in Method::ALL {
        for extra in ["", "[output]\nsupersample = 2\n", "[composite]\nmode = \"additive\"\n"] {
            let toml = method_toml(*method);
            let (top, table) = toml.split_once('\n').unwrap();
            if extra.starts_with("[output]") && !table.is_empty() {
                continue; // `dir`'s [output] table is already given
            }
            let mut s = scene(false, false, &format!("{table}{extra}"));
            s.top_toml = format!("{top}\n");
            let r = s.render();
            let (photo, out) = (photo_bytes(&s), composite_bytes(&r));
            let max = photo.iter().zip(&out).map(|(a, b)| a.abs_diff(*b)).max().unwrap();
            assert!(max <= 1, "max difference {max}/255 with {} and {extra:?}", method.name());
            assert_eq!(photo, out, "in fact bit-exact ({} {extra:?})", method.name());
        }
    }
}

/// With every object real `L_rv == L_r`; so are both solutions' indirect light and probe
/// visibility, which every method that computes indirect light writes as AOVs
/// (`IndirectLight::aovs`).
#[test]
fn with_every_object_real_l_rv_equals_l_r_exactly() {
    use mrshade_render::outputs::AovImage;
    for method in Method::ALL {
        let toml = method_toml(*method);
        let (top, table) = toml.split_once('\n').unwrap();
        let mut s = scene(true, true, table);
        s.top_toml = format!("{top}\n");
        let r = s.render();
        assert_eq!(r.radiance.rv.pixels, r.radiance.r.pixels, "{}", method.name());
        let aovs = r.renderer.read_aovs(&r.ctx).unwrap();
        let find = |name: &str| aovs.iter().find(|a| a.name == name).map(|a| &a.image);
        if *method == Method::Direct {
            assert!(find("indirect_rv").is_none(), "direct computes no indirect light");
            continue;
        }
        let pairs = [("indirect_rv", "indirect_r"), ("probe_visibility_rv", "probe_visibility_r")];
        for (rv, r_name) in pairs {
            let (a, b) = (find(rv), find(r_name));
            let (Some(a), Some(b)) = (a, b) else { panic!("{}: no {rv} / {r_name} AOV", method.name()) };
            match (a, b) {
                (AovImage::Linear(a), AovImage::Linear(b)) => {
                    assert_eq!(a.pixels, b.pixels, "{}: {rv} ≠ {r_name}", method.name());
                    assert!(a.pixels.iter().any(|p| p.iter().any(|&c| c > 0.0)), "{}: {rv} is black", method.name());
                }
                (AovImage::Display { rgb: a, .. }, AovImage::Display { rgb: b, .. }) => {
                    assert_eq!(a, b, "{}: {rv} ≠ {r_name}", method.name())
                }
                _ => panic!("{}: {rv} and {r_name} differ in kind", method.name()),
            }
        }
    }
}

#[test]
fn a_virtual_object_changes_the_photo() {
    let s = scene(true, false, "");
    let r = s.render();
    let (photo, out) = (photo_bytes(&s), composite_bytes(&r));
    let changed = photo.chunks(3).zip(out.chunks(3)).filter(|(a, b)| a != b).count();
    assert!(changed > 20, "only {changed} pixels changed");
}

#[test]
fn the_composite_is_the_documented_formula() {
    for mode in ["alpha", "additive"] {
        let s = scene(true, false, &format!("[composite]\nmode = \"{mode}\"\n"));
        let r = s.render();
        let settings = r.session.settings.composite;
        let composite = r.renderer.read_composite(&r.ctx).unwrap();
        let flags = r.renderer.read_flags(&r.ctx).unwrap();
        let e = r.session.exposure;
        let mut virtual_pixels = 0;
        #[allow(clippy::needless_range_loop, reason = "one index walks six parallel images")]
        for i in 0..(SIZE * SIZE) as usize {
            // The photo is uploaded as half floats (passes/upload).
            let photo = r.session.background.pixels[i].map(|v| half::f16::from_f32(v).to_f32());
            let (rv, lr) = (r.radiance.rv.pixels[i], r.radiance.r.pixels[i]);
            let is_virtual = flags[i] & SURFACE_COVERED != 0 && flags[i] & SURFACE_REAL == 0;
            virtual_pixels += is_virtual as u32;
            for c in 0..3 {
                let expected = if is_virtual {
                    e * rv[c]
                } else {
                    (photo[c] + CompositeSettings::alpha(&settings, photo[c], e * lr[c]) * e * (rv[c] - lr[c])).max(0.0)
                };
                let got = composite.image.pixels[i][c];
                assert!(
                    (got - expected).abs() <= 1e-5 * (1.0 + expected.abs()),
                    "{mode} pixel {i} channel {c}: {got} vs {expected}"
                );
            }
            assert_eq!(composite.coverage[i], if is_virtual { 1.0 } else { 0.0 });
        }
        assert!(virtual_pixels > 10);
    }
}
