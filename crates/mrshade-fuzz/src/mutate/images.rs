//! Image mutations: PNG header fields with valid checksums (sizes, bit depths, colour types),
//! damaged image data; EXR header and chunk bytes (sizes, offsets, DWA counts).

use super::bytes;
use arbitrary::Unstructured;
use std::collections::BTreeMap;

/// Mutates the photo `name` (PNG or JPEG).
pub fn mutate_photo(files: &mut BTreeMap<String, Vec<u8>>, name: &str, u: &mut Unstructured) -> String {
    let data = files.get_mut(name).expect("listed");
    if !data.starts_with(b"\x89PNG") || u.ratio(1, 4).unwrap_or(false) {
        return format!("{name}: {}", bytes::mutate(data, u));
    }
    // IHDR: width, height, bit depth, colour type at bytes 16..26; CRC over 12..29.
    if data.len() < 33 {
        return format!("{name}: too short");
    }
    let step = match u.int_in_range(0..=3u8).unwrap_or(0) {
        0 | 1 => {
            let sizes = [0u32, 1, 26000, 65535, 1 << 20, 0x7fff_ffff, u32::MAX];
            let (w, h) =
                (sizes[u.choose_index(sizes.len()).unwrap_or(0)], sizes[u.choose_index(sizes.len()).unwrap_or(0)]);
            data[16..20].copy_from_slice(&w.to_be_bytes());
            data[20..24].copy_from_slice(&h.to_be_bytes());
            format!("IHDR {w}×{h}")
        }
        2 => {
            let (depth, colour) = (
                [1u8, 2, 4, 8, 16, 3][u.choose_index(6).unwrap_or(0)],
                [0u8, 2, 3, 4, 6, 7][u.choose_index(6).unwrap_or(0)],
            );
            data[24] = depth;
            data[25] = colour;
            format!("IHDR depth {depth}, colour type {colour}")
        }
        _ => {
            let at = 33 + u.choose_index(data.len() - 33).unwrap_or(0);
            data[at] ^= 0x5a;
            format!("damaged byte {at}")
        }
    };
    let crc = crc32(&data[12..29]);
    data[29..33].copy_from_slice(&crc.to_be_bytes());
    format!("{name}: {step} (checksum fixed)")
}

/// Mutates `environment.exr`, mostly in its header and offset table.
pub fn mutate_probe(files: &mut BTreeMap<String, Vec<u8>>, u: &mut Unstructured) -> String {
    let Some(data) = files.get_mut("environment.exr") else { return "no probe".into() };
    let head = data.len().min(1024);
    if head > 8 && u.ratio(2, 3).unwrap_or(false) {
        let at = u.choose_index(head).unwrap_or(0);
        let v = [0u8, 0xff, 0x7f, 0x80, 0x10][u.choose_index(5).unwrap_or(0)];
        data[at] = v;
        return format!("environment.exr: byte {at} of the header = {v}");
    }
    format!("environment.exr: {}", bytes::mutate(data, u))
}

/// CRC-32 (ISO-HDLC), as PNG chunks carry it.
fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = u32::MAX;
    for &b in bytes {
        crc ^= b as u32;
        for _ in 0..8 {
            crc = if crc & 1 != 0 { (crc >> 1) ^ 0xedb8_8320 } else { crc >> 1 };
        }
    }
    !crc
}

#[cfg(test)]
mod tests {
    #[test]
    fn crc_of_iend() {
        assert_eq!(super::crc32(b"IEND"), 0xae42_6082);
    }
}
