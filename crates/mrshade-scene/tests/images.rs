//! Photo and probe decoding, including bad input.

use mrshade_core::color::srgb_u8_decode_table;
use mrshade_scene::budget::Budget;
use mrshade_scene::images::{decode_photo, decode_probe, encode_png_srgb};
use mrshade_testkit::gltf::{write_exr, write_png};

fn bytes_of(write: impl FnOnce(&std::path::Path), name: &str) -> Vec<u8> {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    write(&path);
    std::fs::read(path).unwrap()
}

#[test]
fn png_photos_decode_exactly_and_round_trip() {
    let png = bytes_of(|p| write_png(p, 16, 16, |x, y| [(x * 16) as u8, (y * 16) as u8, 200]), "photo.png");
    let photo = decode_photo(&png, &Budget::default()).unwrap();
    let table = srgb_u8_decode_table();
    assert_eq!(photo.get(3, 5), [table[48], table[80], table[200]]);
    // Encoding the decoded photo gives back the same PNG pixels.
    let again = image::load_from_memory(&encode_png_srgb(&photo).unwrap()).unwrap().to_rgb8();
    assert_eq!(again.as_raw(), image::load_from_memory(&png).unwrap().to_rgb8().as_raw());
}

#[test]
fn exr_photos_are_linear() {
    let exr = bytes_of(|p| write_exr(p, 4, 2, |_, _| [0.25, 2.0, 0.0]), "photo.exr");
    assert_eq!(decode_photo(&exr, &Budget::default()).unwrap().get(1, 1), [0.25, 2.0, 0.0]);
}

#[test]
fn probes_keep_their_dynamic_range_and_clamp_negative_ringing() {
    let exr =
        bytes_of(|p| write_exr(p, 8, 4, |x, _| if x == 0 { [3700.0, 1.0, -0.01] } else { [0.5; 3] }), "probe.exr");
    let (probe, warning) = decode_probe(&exr, &Budget::default()).unwrap();
    assert_eq!(probe.get(0, 0), [3700.0, 1.0, 0.0]);
    assert!(warning.is_none(), "negligible ringing is clamped silently");
    let exr = bytes_of(|p| write_exr(p, 8, 4, |x, _| if x == 0 { [-0.5, 1.0, 1.0] } else { [0.5; 3] }), "probe.exr");
    let (probe, warning) = decode_probe(&exr, &Budget::default()).unwrap();
    assert_eq!(probe.get(0, 3), [0.0, 1.0, 1.0]);
    assert!(warning.unwrap().contains("4 probe value(s) were negative"));
    let hdr = bytes_of(
        |p| {
            let img = image::Rgb32FImage::from_pixel(8, 4, image::Rgb([2.0, 1.0, 0.5]));
            image::DynamicImage::ImageRgb32F(img).save(p).unwrap()
        },
        "probe.hdr",
    );
    let (probe, warning) = decode_probe(&hdr, &Budget::default()).unwrap();
    assert!(warning.is_none());
    assert!((probe.get(3, 2)[0] - 2.0).abs() < 0.02);
}

#[test]
fn nan_and_inf_in_a_probe_are_errors() {
    for bad in [f32::NAN, f32::INFINITY] {
        let exr = bytes_of(
            |p| write_exr(p, 8, 4, |x, y| if (x, y) == (5, 2) { [bad, 0.0, 0.0] } else { [1.0; 3] }),
            "probe.exr",
        );
        let msg = format!("{:#}", decode_probe(&exr, &Budget::default()).unwrap_err());
        assert!(msg.contains("NaN or infinite") && msg.contains("(5, 2)"), "{msg}");
    }
}

#[test]
fn a_probe_must_be_equirectangular_and_hdr() {
    let exr = bytes_of(|p| write_exr(p, 8, 8, |_, _| [1.0; 3]), "square.exr");
    assert!(format!("{:#}", decode_probe(&exr, &Budget::default()).unwrap_err()).contains("twice as wide"));
    let png = bytes_of(|p| write_png(p, 8, 4, |_, _| [9, 9, 9]), "ldr.png");
    assert!(format!("{:#}", decode_probe(&png, &Budget::default()).unwrap_err()).contains("HDR image"));
}

#[test]
fn empty_zero_size_and_unknown_images_are_errors() {
    assert!(format!("{:#}", decode_photo(&[], &Budget::default()).unwrap_err()).contains("empty"));
    assert!(
        format!("{:#}", decode_photo(b"hello, not an image", &Budget::default()).unwrap_err()).contains("unrecognised")
    );
    // A PNG header that claims a 0×0 image.
    let mut png = b"\x89PNG\r\n\x1a\n\x00\x00\x00\x0dIHDR\x00\x00\x00\x00\x00\x00\x00\x00\x08\x02\x00\x00\x00".to_vec();
    png.extend_from_slice(&[0; 4]);
    let msg = format!("{:#}", decode_photo(&png, &Budget::default()).unwrap_err());
    assert!(msg.contains("decode") || msg.contains("empty"), "{msg}");
}
