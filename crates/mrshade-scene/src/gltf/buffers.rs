//! Buffer and image bytes: the GLB `BIN` chunk, `data:` URIs, or files beside the glTF.

use super::describe;
use crate::AssetSource;
use crate::budget::Budget;
use anyhow::{Context, Result, bail};
use base64::Engine;

/// The bytes of every buffer, each at least as long as the glTF says.
pub fn load_buffers(
    document: &gltf::Document,
    mut blob: Option<Vec<u8>>,
    folder: &AssetSource,
    budget: &mut Budget,
) -> Result<Vec<Vec<u8>>> {
    let mut out = Vec::new();
    for buffer in document.buffers() {
        let what = format!("buffer {}", describe(Some(buffer.index()), buffer.name()));
        budget.charge(&what, buffer.length() as u64, 1)?;
        let data = match buffer.source() {
            gltf::buffer::Source::Bin => {
                blob.take().with_context(|| format!("{what} refers to the GLB BIN chunk, which is missing"))?
            }
            gltf::buffer::Source::Uri(uri) => read_uri(uri, folder).with_context(|| what.clone())?,
        };
        if data.len() < buffer.length() {
            bail!("{what} holds {} bytes but the glTF declares {}: the file is truncated", data.len(), buffer.length());
        }
        out.push(data);
    }
    Ok(out)
}

/// Reads a `data:` URI or a (percent-encoded) path relative to the glTF file.
pub fn read_uri(uri: &str, folder: &AssetSource) -> Result<Vec<u8>> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let (meta, payload) = rest.split_once(',').context("malformed data URI (no ',' separator)")?;
        if !meta.ends_with(";base64") {
            bail!("data URI is not base64-encoded ({})", mrshade_core::text::printable(meta));
        }
        return base64::engine::general_purpose::STANDARD
            .decode(payload)
            .map_err(|_| anyhow::anyhow!("data URI holds invalid base64"));
    }
    if uri.contains("://") {
        bail!("URI {} is not a relative path; mrshade reads local files only", mrshade_core::text::printable(uri));
    }
    folder.read(&percent_decode(uri))
}

/// URIs in glTF are percent-encoded (`my%20file.bin`).
fn percent_decode(s: &str) -> String {
    let hex = |b: u8| (b as char).to_digit(16);
    let bytes = s.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%'
            && i + 2 < bytes.len()
            && let (Some(hi), Some(lo)) = (hex(bytes[i + 1]), hex(bytes[i + 2]))
        {
            out.push((hi * 16 + lo) as u8);
            i += 3;
            continue;
        }
        out.push(bytes[i]);
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// The bytes of `view` inside its buffer, checked against the buffer's length.
pub fn view_bytes<'a>(view: &gltf::buffer::View, buffers: &'a [Vec<u8>]) -> Result<&'a [u8]> {
    let data = &buffers[view.buffer().index()];
    let end = view.offset().checked_add(view.length());
    match end {
        Some(end) if end <= data.len() => Ok(&data[view.offset()..end]),
        _ => bail!(
            "bufferView {} spans bytes {}..{} but its buffer has {} bytes",
            view.index(),
            view.offset(),
            view.offset().saturating_add(view.length()),
            data.len()
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percent_decoding() {
        assert_eq!(percent_decode("my%20file.bin"), "my file.bin");
        assert_eq!(percent_decode("100%"), "100%");
        assert_eq!(percent_decode("a%zzb"), "a%zzb");
    }

    #[test]
    fn data_uris() {
        let folder = AssetSource::dir("/nonexistent");
        let bytes = read_uri("data:application/octet-stream;base64,AAEC", &folder).unwrap();
        assert_eq!(bytes, vec![0, 1, 2]);
        assert!(read_uri("data:text/plain,hello", &folder).is_err());
        assert!(read_uri("https://example.com/a.bin", &folder).is_err());
    }
}
