//! Where a session's files come from: a folder on disk, or files compiled into the binary
//! (the embedded demo). Paths inside a session are relative to the file that names them.
//!
//! Files on disk are read only under allowed folders ([`ReadPolicy`]): the session's own, each
//! glTF's own, and those the user allows (`limits.allow_read`, `--allow-read`). Paths are
//! resolved (symbolic links and `..` included) before the check, so neither an absolute URI,
//! a `../../` chain nor a link leads out. Only regular files are read, never a directory, a
//! FIFO (which would block for ever) or a device, and never one larger than the file budget.

use anyhow::{Context, Result, bail};
use std::io::Read;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Files compiled into a program: `(path, bytes)` pairs.
pub type EmbeddedFiles = &'static [(&'static str, &'static [u8])];

/// Largest file read when no budget is given (the session file itself), in bytes.
pub const DEFAULT_MAX_FILE_BYTES: u64 = 1 << 30;

/// Which folders files may be read from, and how large a file may be.
#[derive(Clone, Debug)]
pub struct ReadPolicy {
    /// Canonical folders; a file must resolve to a path under one of them.
    roots: Vec<PathBuf>,
    /// Largest file read, in bytes.
    max_file_bytes: u64,
}

impl ReadPolicy {
    /// Reading under `roots` (made canonical; those that do not exist are skipped), files of
    /// at most `max_file_bytes`.
    pub fn new(roots: &[PathBuf], max_file_bytes: u64) -> Self {
        let roots = roots.iter().filter_map(|r| std::fs::canonicalize(r).ok()).collect();
        Self { roots, max_file_bytes }
    }

    fn with_root(&self, root: &Path) -> Self {
        let mut policy = self.clone();
        if let Ok(root) = std::fs::canonicalize(root)
            && !policy.roots.contains(&root)
        {
            policy.roots.push(root);
        }
        policy
    }

    fn allows(&self, canonical: &Path) -> bool {
        self.roots.iter().any(|root| canonical.starts_with(root))
    }
}

/// A read-only set of files addressed by paths relative to one folder.
#[derive(Clone, Debug)]
pub enum AssetSource {
    /// Files under a directory, read as `policy` allows.
    Dir {
        /// The folder that relative paths start from.
        folder: PathBuf,
        /// Where reads may lead.
        policy: Arc<ReadPolicy>,
    },
    /// Files compiled into the program, seen from the folder `prefix` ("" or "a/b/").
    Embedded {
        /// The files.
        files: EmbeddedFiles,
        /// The folder that relative paths start from.
        prefix: String,
    },
}

impl AssetSource {
    /// Files under `folder` (and nowhere else), of at most [`DEFAULT_MAX_FILE_BYTES`].
    pub fn dir(folder: impl Into<PathBuf>) -> Self {
        let folder = folder.into();
        let policy = ReadPolicy::new(std::slice::from_ref(&folder), DEFAULT_MAX_FILE_BYTES);
        AssetSource::Dir { folder, policy: Arc::new(policy) }
    }

    /// Files under `folder`, read as `policy` allows.
    pub fn dir_with_policy(folder: impl Into<PathBuf>, policy: ReadPolicy) -> Self {
        AssetSource::Dir { folder: folder.into(), policy: Arc::new(policy) }
    }

    /// Embedded files seen from their root folder.
    pub fn embedded(files: EmbeddedFiles) -> Self {
        AssetSource::Embedded { files, prefix: String::new() }
    }

    /// Reads `rel`, naming the full path in the error.
    pub fn read(&self, rel: &str) -> Result<Vec<u8>> {
        match self {
            AssetSource::Dir { folder, policy } => read_file(&folder.join(rel), policy),
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

    /// The folder on disk that relative paths start from (`None` for embedded files).
    pub fn folder(&self) -> Option<PathBuf> {
        match self {
            AssetSource::Dir { folder, .. } => Some(folder.clone()),
            AssetSource::Embedded { .. } => None,
        }
    }

    /// How to show `rel` to a user.
    pub fn display(&self, rel: &str) -> String {
        match self {
            AssetSource::Dir { folder, .. } => folder.join(rel).display().to_string(),
            AssetSource::Embedded { prefix, .. } => format!("<embedded>/{prefix}{rel}"),
        }
    }

    /// The source for paths relative to the folder that holds `rel`.
    pub fn folder_of(&self, rel: &str) -> AssetSource {
        let parent = Path::new(rel).parent().unwrap_or(Path::new(""));
        match self {
            AssetSource::Dir { folder, policy } => {
                AssetSource::Dir { folder: folder.join(parent), policy: policy.clone() }
            }
            AssetSource::Embedded { files, prefix } => {
                let parent = parent.to_string_lossy();
                let prefix = if parent.is_empty() { prefix.clone() } else { format!("{prefix}{parent}/") };
                AssetSource::Embedded { files, prefix }
            }
        }
    }

    /// The source for the files that the file `rel` names (a glTF's buffers and images):
    /// relative to its folder, which becomes an allowed folder too.
    pub fn files_named_by(&self, rel: &str) -> AssetSource {
        match self.folder_of(rel) {
            AssetSource::Dir { folder, policy } => {
                let policy = Arc::new(policy.with_root(&folder));
                AssetSource::Dir { folder, policy }
            }
            embedded => embedded,
        }
    }
}

/// Reads the regular file `path` if the policy allows it, with one-line errors that say why
/// not.
fn read_file(path: &Path, policy: &ReadPolicy) -> Result<Vec<u8>> {
    let shown = path.display();
    let canonical = match std::fs::canonicalize(path) {
        Ok(c) => c,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => bail!("file not found: {shown}"),
        Err(e) => bail!("cannot open {shown}: {e}"),
    };
    if !policy.allows(&canonical) {
        bail!(
            "{shown} is outside the folders this session may read ({}); allow it with \
             `--allow-read FOLDER` or the session's `limits.allow_read`",
            canonical.display()
        );
    }
    let meta = std::fs::metadata(&canonical).with_context(|| format!("cannot open {shown}"))?;
    if meta.is_dir() {
        bail!("{shown} is a directory, not a file");
    }
    if !meta.is_file() {
        bail!("{shown} is not a regular file (a FIFO, socket or device)");
    }
    if meta.len() > policy.max_file_bytes {
        bail!("{shown} holds {} MiB, more than `limits.file_mib` = {} allows", meta.len() >> 20, mib(policy));
    }
    let file = std::fs::File::open(&canonical).with_context(|| format!("cannot open {shown}"))?;
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    // A file that grows while it is read stops at the budget.
    file.take(policy.max_file_bytes + 1).read_to_end(&mut bytes).with_context(|| format!("cannot read {shown}"))?;
    if bytes.len() as u64 > policy.max_file_bytes {
        bail!("{shown} grew past `limits.file_mib` = {} while it was read", mib(policy));
    }
    Ok(bytes)
}

fn mib(policy: &ReadPolicy) -> u64 {
    policy.max_file_bytes >> 20
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
        let dir = AssetSource::dir("/nonexistent");
        assert!(dir.read("x.png").unwrap_err().to_string().contains("/nonexistent/x.png"));
    }

    #[test]
    fn reads_stay_inside_the_allowed_folders() {
        let tmp = tempfile::tempdir().unwrap();
        let inside = tmp.path().join("session");
        std::fs::create_dir_all(inside.join("sub")).unwrap();
        std::fs::write(inside.join("sub/ok.bin"), b"ok").unwrap();
        std::fs::write(tmp.path().join("secret.txt"), b"secret").unwrap();
        let source = AssetSource::dir(&inside);
        assert_eq!(source.read("sub/ok.bin").unwrap(), b"ok");
        assert_eq!(source.read("sub/../sub/ok.bin").unwrap(), b"ok");
        for escape in ["../secret.txt", "/etc/passwd", "sub/../../secret.txt"] {
            let err = source.read(escape).unwrap_err().to_string();
            assert!(err.contains("outside the folders") && err.contains("--allow-read"), "{escape}: {err}");
        }
        #[cfg(unix)]
        {
            std::os::unix::fs::symlink(tmp.path().join("secret.txt"), inside.join("link.txt")).unwrap();
            assert!(source.read("link.txt").unwrap_err().to_string().contains("outside the folders"));
        }
        // A glTF in a subfolder may read beside itself; a glTF may not name a file above it
        // unless that is allowed too.
        let allowed = ReadPolicy::new(&[inside.clone(), tmp.path().into()], DEFAULT_MAX_FILE_BYTES);
        assert_eq!(AssetSource::dir_with_policy(&inside, allowed).read("../secret.txt").unwrap(), b"secret");
    }

    #[test]
    fn only_regular_files_within_the_budget_are_read() {
        let tmp = tempfile::tempdir().unwrap();
        std::fs::create_dir(tmp.path().join("folder")).unwrap();
        std::fs::write(tmp.path().join("big.bin"), vec![0u8; 3 << 20]).unwrap();
        let source = AssetSource::dir(tmp.path());
        assert!(source.read("folder").unwrap_err().to_string().contains("is a directory"));
        let small = AssetSource::dir_with_policy(tmp.path(), ReadPolicy::new(&[tmp.path().into()], 2 << 20));
        let err = small.read("big.bin").unwrap_err().to_string();
        assert!(err.contains("3 MiB") && err.contains("limits.file_mib"), "{err}");
        #[cfg(unix)]
        {
            let fifo = tmp.path().join("fifo");
            assert!(std::process::Command::new("mkfifo").arg(&fifo).status().unwrap().success());
            assert!(source.read("fifo").unwrap_err().to_string().contains("not a regular file"));
        }
    }
}
