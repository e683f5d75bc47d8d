//! Accessor checks before reading. The `gltf` crate's readers trust the file (a wrong type
//! is only a debug assertion; an out-of-range count wraps), so every accessor the loader
//! reads is checked here first: element type, component type, stride and byte ranges, the
//! sparse substitutions, and the memory its decoded elements will take (`limits.scene_mib`),
//! before anything is allocated: a sparse-only accessor may claim 2³¹ elements in 40 bytes.

use super::buffers::view_bytes;
use crate::budget::Budget;
use anyhow::{Result, bail};
use gltf::accessor::{DataType, Dimensions};

/// Checks that `accessor` holds `dims` elements of one of `types` and lies inside its
/// buffers, and charges its decoded elements (4 bytes per component) to `budget`. `what`
/// names it in errors (e.g. "POSITION").
pub fn check(
    accessor: &gltf::Accessor,
    what: &str,
    dims: Dimensions,
    types: &[DataType],
    buffers: &[Vec<u8>],
    budget: &mut Budget,
) -> Result<()> {
    let found = format!("{:?} {:?}", accessor.dimensions(), accessor.data_type());
    if accessor.dimensions() != dims || !types.contains(&accessor.data_type()) {
        let wanted: Vec<String> = types.iter().map(|t| format!("{dims:?} {t:?}")).collect();
        bail!("{what} accessor {} is {found}, expected {}", accessor.index(), wanted.join(" or "));
    }
    if accessor.count() == 0 {
        bail!("{what} accessor {} has count 0", accessor.index());
    }
    budget.charge(
        format_args!("{what} accessor {} ({} elements)", accessor.index(), accessor.count()),
        accessor.count() as u64,
        4 * dims.multiplicity() as u64,
    )?;
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
        check_sparse_indices(accessor, &indices, sparse.count(), what, buffers)?;
    }
    Ok(())
}

/// glTF 2.0 §3.6.2.3: sparse indices strictly increase and address elements of the accessor;
/// the reader would skip the others silently.
fn check_sparse_indices(
    accessor: &gltf::Accessor,
    indices: &gltf::accessor::sparse::Indices,
    count: usize,
    what: &str,
    buffers: &[Vec<u8>],
) -> Result<()> {
    if count > accessor.count() {
        bail!("{what} accessor {}: {count} sparse elements but only {} in all", accessor.index(), accessor.count());
    }
    let size = indices.index_type().size();
    let bytes = &view_bytes(&indices.view(), buffers)?[indices.offset()..];
    let mut previous: Option<u64> = None;
    for (i, raw) in bytes.chunks_exact(size).take(count).enumerate() {
        let index = raw.iter().rev().fold(0u64, |v, &b| v << 8 | b as u64);
        if index >= accessor.count() as u64 || previous.is_some_and(|p| index <= p) {
            bail!(
                "{what} accessor {}: sparse index {i} is not below the count ({}) or not above the index before it",
                accessor.index(),
                accessor.count()
            );
        }
        previous = Some(index);
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
