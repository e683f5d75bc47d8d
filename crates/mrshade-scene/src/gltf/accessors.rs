//! Accessor checks before reading. The `gltf` crate's readers trust the file (a wrong type
//! is only a debug assertion; an out-of-range count wraps), so every accessor the loader
//! reads is checked here first: element type, component type, stride and byte ranges.

use super::buffers::view_bytes;
use anyhow::{Result, bail};
use gltf::accessor::{DataType, Dimensions};

/// Checks that `accessor` holds `dims` elements of one of `types` and lies inside its
/// buffers. `what` names it in errors (e.g. "POSITION").
pub fn check(
    accessor: &gltf::Accessor,
    what: &str,
    dims: Dimensions,
    types: &[DataType],
    buffers: &[Vec<u8>],
) -> Result<()> {
    let found = format!("{:?} {:?}", accessor.dimensions(), accessor.data_type());
    if accessor.dimensions() != dims || !types.contains(&accessor.data_type()) {
        let wanted: Vec<String> = types.iter().map(|t| format!("{dims:?} {t:?}")).collect();
        bail!("{what} accessor {} is {found}, expected {}", accessor.index(), wanted.join(" or "));
    }
    if accessor.count() == 0 {
        bail!("{what} accessor {} has count 0", accessor.index());
    }
    let elem = accessor.size();
    if let Some(view) = accessor.view() {
        check_range(&view, accessor.offset(), accessor.count(), elem, what, buffers)?;
    } else if accessor.sparse().is_none() {
        bail!("{what} accessor {} has neither a bufferView nor sparse data", accessor.index());
    }
    if let Some(sparse) = accessor.sparse() {
        let indices = sparse.indices();
        let index_size = indices.index_type().size();
        check_range(&indices.view(), indices.offset(), sparse.count(), index_size, what, buffers)?;
        let values = sparse.values();
        check_range(&values.view(), values.offset(), sparse.count(), elem, what, buffers)?;
    }
    Ok(())
}

/// `count` elements of `elem` bytes from `offset` with the view's stride fit in the view.
fn check_range(
    view: &gltf::buffer::View,
    offset: usize,
    count: usize,
    elem: usize,
    what: &str,
    buffers: &[Vec<u8>],
) -> Result<()> {
    let bytes = view_bytes(view, buffers)?;
    let stride = view.stride().unwrap_or(elem);
    if stride < elem {
        bail!("{what}: bufferView {} has stride {stride} < element size {elem}", view.index());
    }
    let end =
        (count.max(1) - 1).checked_mul(stride).and_then(|v| v.checked_add(offset)).and_then(|v| v.checked_add(elem));
    match end {
        Some(end) if end <= bytes.len() => Ok(()),
        _ => bail!(
            "{what}: {count} elements of {elem} bytes (stride {stride}, offset {offset}) do not fit in \
             bufferView {} of {} bytes",
            view.index(),
            bytes.len()
        ),
    }
}
