// VPL distribution across the primary light sources (Knecht §2.8): equal shares, user
// weights, or the shares of each source's summed VPL flux in the previous frame; and the
// cumulative flux of the previous frame's surface VPLs, from which the multiple-bounce source
// picks its sources (generate.wgsl, by binary search).

@group(0) @binding(0) var<uniform> params: VplParams;
@group(0) @binding(1) var<storage, read> sources: array<Source>;
@group(0) @binding(2) var<storage, read> previous: array<Vpl>;
@group(0) @binding(3) var<storage, read_write> ranges: array<vec4u>;
@group(0) @binding(4) var<storage, read_write> flux_cdf: array<f32>;

const MAX_SOURCES: u32 = 64u;
const THREADS: u32 = 256u;
var<workgroup> chunk_sums: array<f32, THREADS>;

// Inclusive prefix sum of the surface flux: each thread sums a run of VPLs, the runs are
// scanned (Hillis–Steele), then each thread writes its run.
fn scan_surface_flux(lane: u32) {
    let n = params.counts.x;
    let run = (n + THREADS - 1u) / THREADS;
    let first = min(lane * run, n);
    let end = min(first + run, n);
    var sum = 0.0;
    for (var i = first; i < end; i++) { sum += surface_flux(previous[i], params.scene.w); }
    chunk_sums[lane] = sum;
    workgroupBarrier();
    for (var offset = 1u; offset < THREADS; offset *= 2u) {
        let add = select(0.0, chunk_sums[lane - offset], lane >= offset);
        workgroupBarrier();
        chunk_sums[lane] += add;
        workgroupBarrier();
    }
    var acc = chunk_sums[lane] - sum;
    for (var i = first; i < end; i++) {
        acc += surface_flux(previous[i], params.scene.w);
        flux_cdf[i] = acc;
    }
}

@compute @workgroup_size(THREADS)
fn cs_main(@builtin(local_invocation_index) lane: u32) {
    scan_surface_flux(lane);
    if (lane == 0u) { distribute(); }
}

fn distribute() {
    let n = params.counts.x;
    let count = min(params.counts.z, MAX_SOURCES);
    var share: array<f32, 64>;
    var total = 0.0;
    if (params.modes.x == 2u) {
        for (var i = 0u; i < n; i++) {
            let s = previous[i].info.y;
            if (s < count) {
                share[s] += vpl_flux(previous[i], params.scene.w);
            }
        }
        for (var s = 0u; s < count; s++) { total += share[s]; }
        // Sources that sent nothing last frame (or the first frame) still get a little.
        for (var s = 0u; s < count; s++) {
            share[s] = select(1.0, share[s] / total + 0.05, total > 0.0);
        }
    } else {
        for (var s = 0u; s < count; s++) {
            share[s] = select(1.0, sources[s].weight.x, params.modes.x == 1u);
        }
    }
    total = 0.0;
    for (var s = 0u; s < count; s++) { total += share[s]; }
    var start = 0u;
    for (var s = 0u; s < count; s++) {
        var c = u32(floor(share[s] / max(total, 1e-30) * f32(n)));
        if (s == count - 1u) { c = n - start; }
        c = min(c, n - start);
        ranges[s] = vec4u(start, c, 0u, 0u);
        start += c;
    }
}
