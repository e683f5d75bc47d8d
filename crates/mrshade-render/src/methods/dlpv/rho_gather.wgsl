// `gather` of V_ρ gathered from VPLs (rho_vpl.wgsl): one invocation per cell of the virtual
// content's box and two cells around it (the only ones virtual pixels read). A VPL's patch
// of area A, exitance M = Φ/A, lights the cell's centre x with the irradiance of a disk
// facing it, E = Φ/π·cos_v / (d² + A/π) (exact on the disk's axis, no pole as d → 0), cos_v
// its emission cosine toward the cell. (With the maps' VPLs alone, one bounce, the virtual
// faces of cornell took 0.80–0.87 of the answer's light, and a cosine seen from a cell behind
// the patch, lighter at grazing angles, scored better; with the photo's light, which holds
// every bounce, they take 0.94–0.99 and the plain cosine scores best: docs/benchmarks.md.)

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
        let cos_v = dot(n, to_cell);
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




