//! OpenEXR files checked before the decoder sees them.
//!
//! The `exr` crate checks a file's header and bounds every chunk by the header's block size,
//! but the DWAA/DWAB decompressor trusts the counts inside each compressed chunk (AC and DC
//! coefficient counts, section sizes) and reserves memory for them: one changed byte in a real
//! probe asked for 8 GB. This reads the header (pixel count against the budget, before the
//! offset tables are even read), then walks the chunks and bounds each DWA chunk's counts by
//! what its block of pixels can hold.

use anyhow::{Context, Result, bail};
use exr::block::chunk::{Chunk, CompressedBlock};
use exr::compression::Compression;
use exr::meta::header::Header;
use std::io::Cursor;

/// Size of the DWA chunk header: eleven little-endian u64 counters.
const DWA_HEADER_BYTES: usize = 88;

/// The largest `width × height` of any layer of the EXR file `bytes`, from its header alone.
pub fn largest_layer(bytes: &[u8]) -> Result<(u32, u32)> {
    let meta = exr::meta::MetaData::read_from_buffered(Cursor::new(bytes), false)
        .map_err(|e| anyhow::anyhow!("cannot read the OpenEXR header: {e}"))?;
    let size =
        meta.headers.iter().map(|h| h.layer_size).max_by_key(|s| s.area()).context("the OpenEXR file has no layer")?;
    let side = |v: usize| u32::try_from(v).context("the OpenEXR data window is larger than 2^32 pixels");
    Ok((side(size.width())?, side(size.height())?))
}

/// Checks the counts of every DWA-compressed chunk against its block.
pub fn check_dwa_chunks(bytes: &[u8]) -> Result<()> {
    let reader = exr::block::read(Cursor::new(bytes), false)
        .map_err(|e| anyhow::anyhow!("cannot read the OpenEXR header: {e}"))?;
    let headers = reader.meta_data().headers.clone();
    if !headers.iter().any(|h| matches!(h.compression, Compression::DWAA(_) | Compression::DWAB(_))) {
        return Ok(());
    }
    let chunks = reader.all_chunks(false).map_err(|e| anyhow::anyhow!("cannot read the OpenEXR chunks: {e}"))?;
    for (index, chunk) in chunks.enumerate() {
        // Chunks the decoder will refuse anyway are its to report.
        let Ok(chunk) = chunk else { return Ok(()) };
        check_chunk(&chunk, &headers).with_context(|| format!("OpenEXR chunk {index} is corrupt"))?;
    }
    Ok(())
}

fn check_chunk(chunk: &Chunk, headers: &[Header]) -> Result<()> {
    let Some(header) = headers.get(chunk.layer_index) else { return Ok(()) };
    if !matches!(header.compression, Compression::DWAA(_) | Compression::DWAB(_)) {
        return Ok(());
    }
    let data = match &chunk.compressed_block {
        CompressedBlock::ScanLine(b) => &b.compressed_pixels_le,
        CompressedBlock::Tile(b) => &b.compressed_pixels_le,
        _ => return Ok(()),
    };
    let Ok(section) = header
        .get_block_data_indices(&chunk.compressed_block)
        .and_then(|tile| header.get_absolute_block_pixel_coordinates(tile))
    else {
        return Ok(());
    };
    let raw_bytes = section.size.area() * header.channels.bytes_per_pixel;
    // A block that did not shrink is stored raw, without a DWA header.
    if data.len() == raw_bytes || data.len() < DWA_HEADER_BYTES {
        return Ok(());
    }
    let counter = |i: usize| u64::from_le_bytes(data[8 * i..8 * i + 8].try_into().expect("8 bytes"));
    let round8 = |v: usize| v.div_ceil(8) as u64 * 8;
    let padded_pixels = round8(section.size.width()) * round8(section.size.height());
    let channels = header.channels.list.len() as u64;
    let byte_bound = 2 * raw_bytes as u64 + 1024;
    // (name, counter index, bound): sizes of the decoded sections, then coefficient counts.
    let checks = [
        ("unknown uncompressed size", 1, byte_bound),
        ("RLE uncompressed size", 6, byte_bound),
        ("RLE raw size", 7, byte_bound),
        ("AC coefficient count", 8, padded_pixels * channels),
        ("DC coefficient count", 9, padded_pixels.div_ceil(64) * channels),
    ];
    for (name, i, bound) in checks {
        if counter(i) > bound {
            bail!(
                "its DWA {name} exceeds what a block of {}×{} pixels holds",
                section.size.width(),
                section.size.height()
            );
        }
    }
    Ok(())
}
