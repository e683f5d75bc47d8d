//! A generated input: a session folder's files, made from a seed session by mutations chosen
//! from a number, so that the same number always makes the same case.

use crate::corpus::SEEDS;
use crate::mutate;
use arbitrary::Unstructured;
use std::collections::BTreeMap;
use std::path::Path;

/// One input: files of a session folder (`session.toml` first among them).
#[derive(Clone, Debug)]
pub struct Case {
    /// The case's number (its seed).
    pub number: u64,
    /// What was done to the seed, for the failure report.
    pub recipe: Vec<String>,
    /// File name → bytes.
    pub files: BTreeMap<String, Vec<u8>>,
}

impl Case {
    /// Makes case `number`: a seed session and one to four mutations of its files.
    pub fn generate(number: u64) -> Case {
        let entropy = entropy(number, 8192);
        let mut u = Unstructured::new(&entropy);
        let seed = &SEEDS[u.choose_index(SEEDS.len()).unwrap_or(0)];
        let files = seed.files.iter().map(|(n, b)| (n.to_string(), b.to_vec())).collect();
        let mut case = Case { number, recipe: vec![format!("seed {}", seed.name)], files };
        // Mostly one mutation, so that many cases get past the first check into the code
        // behind it (scene walk, BVH, path tracing); sometimes several.
        let rounds = [1, 1, 1, 1, 1, 2, 2, 3, 4][u.choose_index(9).unwrap_or(0)];
        for _ in 0..rounds {
            let step = mutate::apply(&mut case.files, &mut u);
            case.recipe.push(step);
        }
        case
    }

    /// Writes the files into `dir`, with `recipe.txt` saying how they were made.
    pub fn write(&self, dir: &Path) -> std::io::Result<()> {
        std::fs::create_dir_all(dir)?;
        for (name, bytes) in &self.files {
            std::fs::write(dir.join(name), bytes)?;
        }
        std::fs::write(dir.join("recipe.txt"), format!("case {}\n{}\n", self.number, self.recipe.join("\n")))
    }
}

/// `len` pseudo-random bytes from `number` (SplitMix64): the case's choices.
fn entropy(number: u64, len: usize) -> Vec<u8> {
    let mut state = number ^ 0x9e37_79b9_7f4a_7c15;
    let mut out = Vec::with_capacity(len + 8);
    while out.len() < len {
        state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        out.extend((z ^ (z >> 31)).to_le_bytes());
    }
    out.truncate(len);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_same_number_makes_the_same_case() {
        for n in [0, 1, 77, u64::MAX] {
            let (a, b) = (Case::generate(n), Case::generate(n));
            assert_eq!(a.files, b.files);
            assert_eq!(a.recipe, b.recipe);
        }
        assert_ne!(Case::generate(1).recipe, Case::generate(2).recipe);
    }
}
