// `gather` of V_ρ gathered from VPLs (rho_vpl.wgsl): one invocation per cell of the virtual
// content's box and two cells around it (the only ones virtual pixels read). A VPL's patch
// of area A, exitance M = Φ/A, lights the cell's centre x with the irradiance of a disk
// facing it, E = Φ/π·cos_v / (d² + A/π) (exact on the disk's axis, no pole as d → 0). The
// emission cosine cos_v is seen from a cell behind the patch, as the injection shifts a VPL
// along its normal: the cells that straddle a lit surface, which the merge reads beside it
// trilinearly (a block's foot on a lit floor), see it, and grazing light is lighter.
// Measured against the clamped cosine from the patch itself (0 / ½ / 1 cell behind, region
// FLIP on lavapipe cornell 0.2022 / 0.1910 / 0.1861, desk-bunny 0.1299 / 0.1277 / 0.1262,
// desk-spot-real 0.1795 / 0.1660 / 0.1631): one bounce gathered leaves the virtual faces
// short of light (cornell's mean 0.80–0.87 of the answer from the patch itself, 0.87–0.96
// with a cell), and so did the half-cell lift of the centres in front, docs/benchmarks.md.

@group(0) @binding(0) var<uniform> params: DlpvParams;
@group(0) @binding(1) var<storage, read> vpls: array<GatherVpl>;
// The accumulated V_ρ, V_Δ, V_μ; this pass writes V_ρ.
@group(0) @binding(2) var<storage, read_write> volumes: array<vec4f>;
struct RhoGatherInfo {
    // x: VPLs in all; yzw: the first cell gathered
    vpls_first: vec4u,
    // xyz: cells gathered along each axis
    size: vec4u,
}
@group(0) @binding(3) var<uniform> gather_info: RhoGatherInfo;

@compute @workgroup_size(4, 4, 4)
fn gather(@builtin(global_invocation_id) id: vec3u) {
    if (any(id >= gather_info.size.xyz)) { return; }
    let at = id + gather_info.vpls_first.yzw;
    let h = cell_side();
    let x = params.origin.xyz + (vec3f(at) + 0.5) * h;
    var c = array<vec4f, 3>(vec4f(0.0), vec4f(0.0), vec4f(0.0));
    for (var i = 0u; i < gather_info.vpls_first.x; i++) {
        let vpl = vpls[i];
        let n = vpl.normal.xyz;
        let d = x - vpl.position.xyz;
        let dist2 = max(dot(d, d), 1e-12);
        let to_cell = d * inverseSqrt(dist2);
        let behind = d + h * n;
        let cos_v = dot(n, behind) * inverseSqrt(max(dot(behind, behind), 1e-12));
        if (cos_v <= 0.0) { continue; }
        let e = vpl.flux.rgb * (cos_v / (PI * (dist2 + vpl.position.w / PI)));
        let y = sh4(to_cell);
        c[0] += e.r * y;
        c[1] += e.g * y;
        c[2] += e.b * y;
    }
    let cell = cell_index(vec3i(at));
    for (var ch = 0u; ch < 3u; ch++) {
        volumes[ch * cells() + cell] = c[ch] * (h * h);
    }
}




