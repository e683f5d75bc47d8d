//! Where a session's files come from: a folder on disk, or files compiled into the binary
//! (the embedded demo). Paths inside a session are relative to the file that names them.

use anyhow::{Context, Result, bail};
use std::path::{Path, PathBuf};

/// Files compiled into a program: `(path, bytes)` pairs.
pub type EmbeddedFiles = &'static [(&'static str, &'static [u8])];

/// A read-only set of files addressed by paths relative to one folder.
#[derive(Clone, Debug)]
pub enum AssetSource {
    /// Files under a directory.
    Dir(PathBuf),
    /// Files compiled into the program, seen from the folder `prefix` ("" or "a/b/").
    Embedded {
        /// The files.
        files: EmbeddedFiles,
        /// The folder that relative paths start from.
        prefix: String,
    },
}

impl AssetSource {
    /// Embedded files seen from their root folder.
    pub fn embedded(files: EmbeddedFiles) -> Self {
        AssetSource::Embedded { files, prefix: String::new() }
    }

    /// Reads `rel`, naming the full path in the error.
    pub fn read(&self, rel: &str) -> Result<Vec<u8>> {
        match self {
            AssetSource::Dir(base) => {
                let path = base.join(rel);
                if !path.is_file() {
                    bail!("file not found: {}", path.display());
                }
                std::fs::read(&path).with_context(|| format!("cannot read {}", path.display()))
            }
            AssetSource::Embedded { files, prefix } => {
                let wanted = format!("{prefix}{rel}");
                files
                    .iter()
                    .find(|(name, _)| *name == wanted)
                    .map(|(_, bytes)| bytes.to_vec())
                    .with_context(|| format!("file not found in the embedded assets: {wanted}"))
            }
        }
    }

    /// How to show `rel` to a user.
    pub fn display(&self, rel: &str) -> String {
        match self {
            AssetSource::Dir(base) => base.join(rel).display().to_string(),
            AssetSource::Embedded { prefix, .. } => format!("<embedded>/{prefix}{rel}"),
        }
    }

    /// The source for paths relative to the folder that holds `rel`.
    pub fn folder_of(&self, rel: &str) -> AssetSource {
        let parent = Path::new(rel).parent().unwrap_or(Path::new(""));
        match self {
            AssetSource::Dir(base) => AssetSource::Dir(base.join(parent)),
            AssetSource::Embedded { files, prefix } => {
                let parent = parent.to_string_lossy();
                let prefix = if parent.is_empty() { prefix.clone() } else { format!("{prefix}{parent}/") };
                AssetSource::Embedded { files, prefix }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    static FILES: EmbeddedFiles = &[("a.txt", b"A"), ("sub/b.txt", b"B")];

    #[test]
    fn embedded_paths_are_relative_to_the_referring_file() {
        let root = AssetSource::embedded(FILES);
        assert_eq!(root.read("a.txt").unwrap(), b"A");
        let sub = root.folder_of("sub/scene.gltf");
        assert_eq!(sub.read("b.txt").unwrap(), b"B");
        assert!(sub.read("a.txt").unwrap_err().to_string().contains("sub/a.txt"));
    }

    #[test]
    fn missing_files_are_named() {
        let dir = AssetSource::Dir(PathBuf::from("/nonexistent"));
        assert!(dir.read("x.png").unwrap_err().to_string().contains("/nonexistent/x.png"));
    }
}
