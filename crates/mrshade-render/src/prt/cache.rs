//! Baked transfer cached next to the session (`prt_cache.bin` in its folder): baked on first
//! use, read afterwards. Keyed per primitive by a hash of its geometry, the sample count and
//! the coefficient count, so an edited model or another `ibl.prt_samples` or
//! `ibl.prt_coefficients` bakes again; a cache that cannot be read or written costs a bake,
//! never an error.

use std::collections::HashMap;
use std::hash::{Hash, Hasher};
use std::path::Path;

const MAGIC: &[u8; 8] = b"MRSPRT02";
/// The cache's file name in the session's folder.
pub const FILE_NAME: &str = "prt_cache.bin";

/// Transfer vectors by key (all of a primitive's, one vertex after the other).
#[derive(Default)]
pub struct Cache {
    entries: HashMap<u64, Vec<f32>>,
    changed: bool,
}

/// The key of a primitive's transfer at `samples` rays and `coefficients` SH coefficients.
pub fn key(primitive: &mrshade_scene::Primitive, samples: u32, coefficients: usize) -> u64 {
    let mut h = std::collections::hash_map::DefaultHasher::new();
    samples.hash(&mut h);
    coefficients.hash(&mut h);
    for p in primitive.positions.iter().chain(&primitive.normals) {
        p.to_array().map(f32::to_bits).hash(&mut h);
    }
    primitive.indices.hash(&mut h);
    h.finish()
}

impl Cache {
    /// Reads `path` (an empty cache where it is missing or unreadable).
    pub fn read(path: &Path) -> Self {
        let entries = std::fs::read(path).ok().and_then(|b| parse(&b)).unwrap_or_default();
        Self { entries, changed: false }
    }

    /// The transfer of `key`, `floats` floats, or bakes it with `bake`.
    pub fn get_or_bake(&mut self, key: u64, floats: usize, bake: impl FnOnce() -> Vec<f32>) -> &[f32] {
        if self.entries.get(&key).is_none_or(|t| t.len() != floats) {
            self.entries.insert(key, bake());
            self.changed = true;
        }
        &self.entries[&key]
    }

    /// Writes the cache if something was baked; the error says why it could not.
    pub fn write_if_changed(&self, path: &Path) -> std::io::Result<()> {
        if !self.changed {
            return Ok(());
        }
        let mut bytes = MAGIC.to_vec();
        bytes.extend((self.entries.len() as u64).to_le_bytes());
        for (key, transfer) in &self.entries {
            bytes.extend(key.to_le_bytes());
            bytes.extend((transfer.len() as u64).to_le_bytes());
            for v in transfer {
                bytes.extend(v.to_le_bytes());
            }
        }
        std::fs::write(path, bytes)
    }
}

fn parse(bytes: &[u8]) -> Option<HashMap<u64, Vec<f32>>> {
    let mut rest = bytes.strip_prefix(MAGIC)?;
    let u64_of = |rest: &mut &[u8]| -> Option<u64> {
        let (head, tail) = rest.split_first_chunk::<8>()?;
        *rest = tail;
        Some(u64::from_le_bytes(*head))
    };
    let count = u64_of(&mut rest)?;
    let mut entries = HashMap::new();
    for _ in 0..count {
        let key = u64_of(&mut rest)?;
        let floats = usize::try_from(u64_of(&mut rest)?).ok()?;
        if rest.len() < floats.checked_mul(4)? {
            return None;
        }
        let (data, tail) = rest.split_at(floats * 4);
        rest = tail;
        let values: Vec<f32> = data.chunks_exact(4).map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]])).collect();
        entries.insert(key, values);
    }
    rest.is_empty().then_some(entries)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_written_cache_reads_back_and_a_damaged_one_is_empty() {
        let dir = std::env::temp_dir().join(format!("mrshade-prt-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join(FILE_NAME);
        let mut cache = Cache::default();
        let t = cache.get_or_bake(7, 18, || [[1.0; 9], [2.0; 9]].concat()).to_vec();
        cache.write_if_changed(&path).unwrap();
        let mut again = Cache::read(&path);
        let back = again.get_or_bake(7, 18, || panic!("baked again")).to_vec();
        assert_eq!(back, t);
        std::fs::write(&path, b"MRSPRT01garbage").unwrap();
        assert!(Cache::read(&path).entries.is_empty());
        std::fs::remove_dir_all(&dir).ok();
    }
}
