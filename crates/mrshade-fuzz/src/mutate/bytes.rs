//! Byte-level mutations, for what structure-aware ones do not reach.

use arbitrary::Unstructured;

/// Flips, overwrites, truncates or repeats bytes of `data`; says what it did.
pub fn mutate(data: &mut Vec<u8>, u: &mut Unstructured) -> String {
    if data.is_empty() {
        data.push(u.arbitrary().unwrap_or(0));
        return "filled an empty file".into();
    }
    let at = u.choose_index(data.len()).unwrap_or(0);
    match u.int_in_range(0..=5u8).unwrap_or(0) {
        0 => {
            let bit = u.int_in_range(0..=7u8).unwrap_or(0);
            data[at] ^= 1 << bit;
            format!("flipped bit {bit} of byte {at}")
        }
        1 => {
            let value = [0u8, 0xff, 0x7f, 0x80, 0x01][u.choose_index(5).unwrap_or(0)];
            data[at] = value;
            format!("set byte {at} to {value}")
        }
        2 => {
            // A 32-bit word at a 4-byte boundary: lengths, counts, floats.
            let at = at & !3;
            if at + 4 <= data.len() {
                let words = [0u32, u32::MAX, 0x7fff_ffff, 0x8000_0000, 0x7f80_0000, 0x7fc0_0000, 0x7149_f2ca];
                let w = words[u.choose_index(words.len()).unwrap_or(0)];
                data[at..at + 4].copy_from_slice(&w.to_le_bytes());
            }
            format!("set the word at {at}")
        }
        3 => {
            data.truncate(at);
            format!("truncated to {at} bytes")
        }
        4 => {
            let n = u.int_in_range(1..=64usize).unwrap_or(1).min(data.len() - at);
            let piece = data[at..at + n].to_vec();
            data.splice(at..at, piece);
            format!("repeated {n} bytes at {at}")
        }
        _ => {
            let n = u.int_in_range(1..=16usize).unwrap_or(1).min(data.len() - at);
            data.drain(at..at + n);
            format!("removed {n} bytes at {at}")
        }
    }
}
