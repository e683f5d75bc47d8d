//! Budgets for what a session may make mrshade read and allocate (`[limits]`).
//!
//! Files come from anywhere. Every size an input implies (decoded pixels from an image's
//! header, accessor counts, the bytes a file holds) is checked against these budgets *before*
//! the allocation, with an error that names the input, the limit and how to raise it
//! (`--set limits.KEY=VALUE` or the session's `[limits]` table). The defaults hold a real
//! session with room to spare and keep a hostile one well under 4 GB of memory.

use super::check;
use serde::{Deserialize, Serialize};

/// Default of [`Limits::image_pixels`]: 64 Mi pixels (8192 × 8192, or a 11585 × 5792 probe).
pub const DEFAULT_IMAGE_PIXELS: u64 = 1 << 26;

/// The budgets of one session.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Limits {
    /// Largest decoded image (photo, probe, texture), in pixels, checked from the image's
    /// header before decoding. Default 64 Mi (8192 × 8192); at 16 bytes per pixel while
    /// decoding that is 1 GiB.
    pub image_pixels: u64,
    /// Largest file read (glTF, buffer, image, session), in MiB, checked before reading.
    /// Default 1024.
    pub file_mib: u64,
    /// Memory the decoded scene may take in all (buffers, vertices, indices, textures), in
    /// MiB, counted before each allocation. Default 2048.
    pub scene_mib: u64,
    /// Most punctual lights in a scene. Each needs up to 12 shadow-map and RSM layers and a
    /// compute-raster view per layer on the GPU. Default 32.
    pub lights: u32,
    /// GPU memory the renderer may allocate, in MiB, estimated from the scene, the output size
    /// and the settings before anything is allocated (on a CPU driver such as lavapipe, this
    /// is host memory). Default 4096.
    pub gpu_mib: u64,
    /// Most frames in a posed image sequence (`[sequence]`: the frames a `transforms.json`
    /// lists, or `frames`), checked while the list is read. Default 100000 (an hour at 30 fps).
    pub sequence_frames: u32,
    /// Folders, besides the session's own and each glTF's own, that files may be read from
    /// (relative to the session file, or absolute). By default a session and its glTF files
    /// read nothing outside their folders: a downloaded glTF cannot make mrshade read
    /// `/etc/passwd` or `../../secrets`. The command line adds to this with `--allow-read`.
    pub allow_read: Vec<String>,
}

impl Default for Limits {
    fn default() -> Self {
        Self {
            image_pixels: DEFAULT_IMAGE_PIXELS,
            file_mib: 1024,
            scene_mib: 2048,
            lights: 32,
            gpu_mib: 4096,
            sequence_frames: 100_000,
            allow_read: Vec::new(),
        }
    }
}

impl Limits {
    /// Checks every value; the error names the offending field.
    pub fn validate(&self) -> Result<(), String> {
        check(
            (1..=1 << 32).contains(&self.image_pixels),
            "limits.image_pixels",
            format!("must be between 1 and 2^32, got {}", self.image_pixels),
        )?;
        for (name, mib) in
            [("limits.file_mib", self.file_mib), ("limits.scene_mib", self.scene_mib), ("limits.gpu_mib", self.gpu_mib)]
        {
            check((1..=1 << 20).contains(&mib), name, format!("must be between 1 and 1048576 (1 TiB), got {mib}"))?;
        }
        check(self.lights <= 65536, "limits.lights", format!("must be at most 65536, got {}", self.lights))?;
        check(
            (1..=10_000_000).contains(&self.sequence_frames),
            "limits.sequence_frames",
            format!("must be between 1 and 10000000, got {}", self.sequence_frames),
        )
    }

    /// [`Limits::file_mib`] in bytes.
    pub fn file_bytes(&self) -> u64 {
        self.file_mib << 20
    }

    /// [`Limits::scene_mib`] in bytes.
    pub fn scene_bytes(&self) -> u64 {
        self.scene_mib << 20
    }

    /// [`Limits::gpu_mib`] in bytes.
    pub fn gpu_bytes(&self) -> u64 {
        self.gpu_mib << 20
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_valid_and_bad_values_name_their_field() {
        Limits::default().validate().unwrap();
        let l = Limits { image_pixels: 0, ..Default::default() };
        assert!(l.validate().unwrap_err().contains("limits.image_pixels"));
        let l = Limits { scene_mib: 0, ..Default::default() };
        assert!(l.validate().unwrap_err().contains("limits.scene_mib"));
        let l = Limits { sequence_frames: 0, ..Default::default() };
        assert!(l.validate().unwrap_err().contains("limits.sequence_frames"));
        assert!(toml::from_str::<Limits>("image_pixel = 5").is_err());
    }
}
