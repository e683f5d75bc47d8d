//! Where the gather of vpl_gather.rs works: the cells it gathers and V_ρ's among them
//! (`GatherInfo`, the uniform vpl.wgsl mirrors), and the chunks its VPLs are summed in, whose
//! partial sums vpl_gather.wgsl `gather_sum` adds up.

use super::DlpvParams;
use super::vpl_gather::{GATHERED_BOUNCE, GATHERED_RHO};
use bytemuck::{Pod, Zeroable};
use glam::{IVec3, UVec3, UVec4, Vec3};

/// Mirrors `GatherInfo` in vpl.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(super) struct GatherInfo {
    /// x: chunks of the VPLs; yzw: the first cell gathered.
    pub(super) chunks_first: UVec4,
    /// xyz: cells gathered along each axis; w: parts with visibility maps at most along each
    /// axis (visibility.rs `map_room`).
    pub(super) size: UVec4,
    /// xyz: the first cell of V_ρ's (`rho_cells`); w: the index of the first of the virtual
    /// surfaces' cells' VPLs (vpl_aggregate.wgsl `cell_vpls`).
    pub(super) rho_first: UVec4,
    /// xyz: one past its last cell; w: the chunks the VPLs of V_ρ's blocks are gathered in
    /// (`rho_chunks`: `chunks_first.x` and the extra ones of `rho_partials`).
    pub(super) rho_end: UVec4,
}

impl GatherInfo {
    /// `room`: parts with visibility maps along each axis; `cell_base`: the first cell VPL;
    /// `rho_room`: bytes of `rho_partials`.
    pub(super) fn new(
        chunks: u32,
        virtual_box: Option<(Vec3, Vec3)>,
        params: &DlpvParams,
        gathered: u32,
        [room, cell_base]: [u32; 2],
        rho_room: u64,
    ) -> Self {
        let (first, size) = cells_read(virtual_box, params, gathered);
        let (rho_first, rho_size) = rho_cells(virtual_box, params);
        let mut info = Self {
            chunks_first: UVec4::from((chunks, first)),
            size: size.extend(room),
            rho_first: rho_first.extend(cell_base),
            rho_end: (rho_first + rho_size).extend(chunks),
        };
        if gathered & GATHERED_RHO != 0 {
            let [lo, hi] = info.rho_blocks();
            let cells = (hi - lo).element_product() as u64 * 64;
            let extra =
                (rho_room / (cells * partial_cell_bytes(gathered)).max(1)).min(((RHO_SPLIT - 1) * chunks) as u64);
            info.rho_end.w = chunks + extra as u32;
        }
        info
    }

    /// The blocks of 4³ cells of the gathered box that hold V_ρ's cells, the first and one past
    /// the last (vpl_gather.wgsl `rho_blocks_first`, `rho_blocks_end`).
    pub(super) fn rho_blocks(&self) -> [UVec3; 2] {
        let c = self.chunks_first;
        let first = UVec3::new(c.y, c.z, c.w);
        [(self.rho_first.truncate() - first) / 4, ((self.rho_end.truncate() - first + 3) / 4).min(self.blocks())]
    }

    /// The gathered box's blocks of 4³ cells along each axis.
    pub(super) fn blocks(&self) -> UVec3 {
        (self.size.truncate() + 3) / 4
    }
}

/// V_ρ's blocks gather the VPLs in up to this many times the chunks of the others: they take
/// V_ρ's nine coefficients, and with `dlpv.virtual_bounce` the cells' VPLs and the paths'
/// test, several times the others' work per VPL, and a dispatch lasts as long as its longest
/// workgroup.
const RHO_SPLIT: u32 = 4;

/// Bytes of one cell's partial sums over one chunk (vpl_gather.wgsl `partials`): V_ρ's bands
/// 0–2 (seven vec4f), with the bounce light V_Δ's and V_μ's bands 0–1 (three each).
pub(super) fn partial_cell_bytes(gathered: u32) -> u64 {
    16 * if gathered & GATHERED_BOUNCE != 0 { 13 } else { 7 }
}

/// The cells gathered: with the bounce light (real pixels read any) every one; for V_ρ alone
/// its cells (`rho_cells`).
fn cells_read(virtual_box: Option<(Vec3, Vec3)>, params: &DlpvParams, gathered: u32) -> (UVec3, UVec3) {
    if gathered & GATHERED_BOUNCE != 0 {
        return (UVec3::ZERO, UVec3::splat(params.info.x));
    }
    rho_cells(virtual_box, params)
}

/// The cells of V_ρ that virtual pixels read: those of the virtual content's box and one cell
/// around it (the merge reads half a cell off a surface, trilinearly: at most the next cell
/// out), within the volume, all of it without virtual content. Others are left at zero.
fn rho_cells(virtual_box: Option<(Vec3, Vec3)>, params: &DlpvParams) -> (UVec3, UVec3) {
    let res = params.info.x;
    let all = (UVec3::ZERO, UVec3::splat(res));
    let Some((lo, hi)) = virtual_box else { return all };
    let origin = params.origin.truncate();
    let h = params.origin.w;
    let cell = |p: Vec3| ((p - origin) / h).floor().as_ivec3();
    let first = (cell(lo) - 1).clamp(IVec3::ZERO, IVec3::splat(res as i32 - 1)).as_uvec3();
    let last = (cell(hi) + 1).clamp(IVec3::ZERO, IVec3::splat(res as i32 - 1)).as_uvec3();
    (first, last + 1 - first)
}

/// Bytes of `rho_partials`, V_ρ's blocks' extra chunks: up to `RHO_SPLIT` times the others'
/// where `RHO_PARTIAL_BYTES` holds them (all cells the bound; GatherInfo::new takes as many as
/// fit the blocks of the frame).
pub(super) fn rho_room(cells: u64, partial: u64, chunks: u32, gathered: u32) -> u64 {
    if gathered & GATHERED_RHO == 0 {
        return 0;
    }
    RHO_PARTIAL_BYTES.min(cells * partial * ((RHO_SPLIT - 1) * chunks) as u64)
}

/// Chunks the VPLs are gathered in: as many as `PARTIAL_BYTES` of partial sums hold (`partial`
/// bytes per cell), 1 to 16.
pub(super) fn chunks(cells: u64, partial: u64) -> u32 {
    (PARTIAL_BYTES / (cells * partial)).clamp(1, 16) as u32
}

/// Bytes of the gather's partial sums at most: the chunks are as many as fit (16 at most).
/// 48 MiB: seven chunks of 32³ cells with V_ρ's band 2 (13 vec4f a cell), as many as without
/// it at 32 MiB; four took the gather from 0.18 to 0.28 ms on cornell at 1080p on the H100
/// (docs/benchmarks.md, 2026-12-06).
const PARTIAL_BYTES: u64 = 48 << 20;

/// Bytes of the partial sums of V_ρ's blocks' extra chunks at most (`RHO_SPLIT`).
const RHO_PARTIAL_BYTES: u64 = 48 << 20;

#[cfg(test)]
mod tests {
    use super::*;
    use mrshade_core::settings::DlpvSettings;

    /// `rho_blocks` is the box of the blocks vpl_gather.wgsl's workgroups take as V_ρ's (a
    /// block whose cells reach V_ρ's box), for every place of a small box in the volume.
    #[test]
    fn v_rhos_blocks_are_those_whose_cells_reach_its_box() {
        let settings = DlpvSettings::default();
        let params = DlpvParams::new(&settings, Vec3::ZERO, 32.0, 1.0);
        for (lo, hi) in [(0.2, 3.9), (4.0, 8.0), (5.5, 20.1), (27.0, 31.9), (-3.0, 40.0)] {
            let virtual_box = Some((Vec3::new(lo, 7.3, 12.0), Vec3::new(hi, 9.0, 12.5)));
            let info = GatherInfo::new(7, virtual_box, &params, GATHERED_RHO | GATHERED_BOUNCE, [0, 0], 0);
            let [first, end] = info.rho_blocks();
            for b in 0..8u32 {
                let block = UVec3::new(b, b, b);
                let cell = block * 4;
                let reaches =
                    cell.cmplt(info.rho_end.truncate()).all() && (cell + 4).cmpgt(info.rho_first.truncate()).all();
                assert_eq!(reaches, block.cmpge(first).all() && block.cmplt(end).all(), "box {lo}..{hi}, block {b}");
            }
            assert_eq!(info.rho_end.w, 7, "no room: V_ρ's blocks take the others' chunks");
        }
    }

    /// V_ρ's blocks take up to `RHO_SPLIT` times the chunks where the room holds them, fewer
    /// where it holds fewer.
    #[test]
    fn v_rhos_blocks_take_as_many_chunks_as_their_room_holds() {
        let settings = DlpvSettings::default();
        let params = DlpvParams::new(&settings, Vec3::ZERO, 32.0, 1.0);
        let gathered = GATHERED_RHO | GATHERED_BOUNCE;
        let virtual_box = Some((Vec3::splat(10.2), Vec3::splat(13.8)));
        let chunk_bytes = |info: &GatherInfo| {
            let [first, end] = info.rho_blocks();
            (end - first).element_product() as u64 * 64 * partial_cell_bytes(gathered)
        };
        let full = GatherInfo::new(7, virtual_box, &params, gathered, [0, 0], u64::MAX);
        assert_eq!(full.rho_end.w, 7 * RHO_SPLIT);
        let some = GatherInfo::new(7, virtual_box, &params, gathered, [0, 0], 5 * chunk_bytes(&full) + 1);
        assert_eq!(some.rho_end.w, 12);
    }
}
