// `aggregate` of the gathered volumes (vpl.wgsl): one workgroup per block of
// `gather_info.w`² texels of a pair of maps, summed into VPLs by what they light: R_ρ's real
// texels (those no virtual surface hides, as V_ρ's injection: V_ρ and V_μ) and its virtual
// ones (V_ρ); with the bounce light gathered also the real texels a virtual surface hides
// (V_μ, and taken from V_Δ) and the virtual surfaces that hide them (added to V_Δ). A virtual
// lamp's light is all change: its real texels light V_ρ and V_Δ, never V_μ. With the photo's
// light (`photo_tiles`, vpl_photo.wgsl) V_ρ and V_μ leave the texels the camera sees to the
// photo; V_Δ keeps them.
@group(0) @binding(0) var<uniform> params: DlpvParams;
@group(0) @binding(1) var<storage, read> rsm: array<RsmTexel>;
@group(0) @binding(2) var<storage, read> pairs: array<vec4u>;
@group(0) @binding(3) var<storage, read> lights: array<Light>;
// The VPLs: a block's or a tile's appended where they hold any light.
@group(0) @binding(4) var<storage, read_write> vpls: array<GatherVpl>;
// The maps' side, pairs, unused, texels (or pixels) per block side.
@group(0) @binding(5) var<uniform> gather_info: vec4u;
@group(0) @binding(6) var<storage, read_write> vpl_count: atomic<u32>;
@group(0) @binding(7) var<uniform> cells_gathered: GatherInfo;
// Per cell two vec4f, cleared before the pass: the plane of a virtual surface the maps see in
// it (unit normal, ⟨n, p⟩; zero where none) and its diffuse albedo (`bounce_visible`).
@group(0) @binding(8) var<storage, read_write> planes: array<vec4f>;
// The accumulated volumes and V_ρ's band 2 as the last gather left them (volume_read.wgsl),
// for the light the virtual surfaces send on (`cell_vpls`).
@group(0) @binding(9) var<storage, read> volumes: array<vec4f>;
@group(0) @binding(10) var<storage, read> rho_band2: array<vec4f>;

// Marks the cell of virtual surface point `p` (normal `n`, diffuse albedo `albedo`) with its
// plane. Texels of one cell from several maps or faces race; any one's plane will do: the
// test that reads it (vpl_gather.wgsl `blocked`) asks only whether a path crosses a surface
// there, and a cell of a face holds that face's plane whichever texel wrote it.
fn mark_plane(p: vec3f, n: vec3f, albedo: vec3f) {
    let c = vec3i(floor(cell_coords(p)));
    if (!cell_inside(c)) { return; }
    let i = cell_index(c);
    planes[2u * i] = vec4f(n, dot(n, p));
    planes[2u * i + 1u] = vec4f(albedo, 1.0);
}

// One invocation per cell: a cell that holds a virtual surface's plane appends a VPL of the
// change (V_Δ) with the light that surface takes from V_ρ, E·albedo over the cell's share of
// the plane (h² / the normal's largest component), at the plane's point nearest the cell's
// centre. V_ρ is the last gather's (a frame late while the content moves; `VplGather`
// gathers once more after a still's first frame). The maps' VPLs of the virtual surfaces
// (`hiding`) carry their direct light; these their indirect light, which the blocked bounce
// light needs beside it: blocked alone, cornell's contact shadows were twice too dark.
@compute @workgroup_size(64)
fn cell_vpls(@builtin(global_invocation_id) id: vec3u) {
    let res = params.info.x;
    let i = id.x;
    if (i >= cells()) { return; }
    let plane = planes[2u * i];
    if (dot(plane.xyz, plane.xyz) < 0.25) { return; }
    let c = vec3f(f32(i % res), f32((i / res) % res), f32(i / (res * res)));
    let h = cell_side();
    let centre = params.origin.xyz + (c + 0.5) * h;
    let n = normalize(plane.xyz);
    let p = centre - (dot(n, centre) - plane.w) * n;
    let e = max(volume_irradiance(VOLUME_RHO, p, n), vec3f(0.0));
    let area = h * h / max(max(abs(n.x), abs(n.y)), abs(n.z));
    let flux = planes[2u * i + 1u].rgb * e * area;
    if (all(flux == vec3f(0.0))) { return; }
    var vpl: GatherVpl;
    vpl.position = vec4f(p, area);
    vpl.normal = vec4f(n, f32(VPL_DELTA));
    vpl.flux = vec4f(flux, 0.0);
    vpls[atomicAdd(&vpl_count, 1u)] = vpl;
}

// Appends the VPL of `sum`, lighting the volumes of `lights` (VPL_* bits), if it holds any
// light and the cells gathered lie (partly) in front of it (thread 0 of the workgroup, after
// the sums): a wall's outside, a floor's underside light none of them (the gather's time is
// the VPLs' count times the cells').
fn append(sum: Sum, lights: u32) {
    if (all(sum.flux.rgb == vec3f(0.0))) { return; }
    let vpl = to_vpl(sum, lights);
    let h = cell_side();
    let half = 0.5 * h * vec3f(cells_gathered.size.xyz);
    let centre = params.origin.xyz + h * vec3f(cells_gathered.chunks_first.yzw) + half;
    let n = vpl.normal.xyz;
    if (dot(n, centre - vpl.position.xyz) + dot(abs(n), half) <= 0.0) { return; }
    vpls[atomicAdd(&vpl_count, 1u)] = vpl;
}

// Texels (or pixels) summed: Σ reflected flux (rgb) and area (w); Σ w·position (xyz) and
// Σ w (w); Σ w·normal, w the flux's luminance.
struct Sum {
    flux: vec4f,
    position: vec4f,
    normal: vec4f,
}

const THREADS: u32 = 64u;
var<workgroup> partial: array<Sum, 64>;

fn plus(a: Sum, b: Sum) -> Sum {
    return Sum(a.flux + b.flux, a.position + b.position, a.normal + b.normal);
}

fn texel_sum(t: RsmTexel) -> Sum {
    let reflected = t.power.rgb * t.albedo.rgb * (1.0 - t.albedo.w);
    let w = dot(reflected, vec3f(0.2126, 0.7152, 0.0722)) + 1e-20;
    return Sum(vec4f(reflected, t.material.w), vec4f(t.position.xyz * w, w), vec4f(t.normal.xyz * w, 0.0));
}

fn to_vpl(sum: Sum, lights: u32) -> GatherVpl {
    var out: GatherVpl;
    let p = sum.position;
    let n = sum.normal.xyz;
    out.position = vec4f(select(vec3f(0.0), p.xyz / p.w, p.w > 0.0), sum.flux.w);
    out.normal = vec4f(select(vec3f(0.0, 0.0, 1.0), normalize(n), dot(n, n) > 0.0), f32(lights));
    out.flux = vec4f(sum.flux.rgb, 0.0);
    return out;
}

// The workgroup's sum of every invocation's `sum`, appended by invocation 0 as a VPL that
// lights the volumes of `lights` (called by all 64 invocations of a workgroup, from uniform
// control flow).
fn append_workgroup_sum(thread: u32, sum: Sum, lights: u32) {
    partial[thread] = sum;
    workgroupBarrier();
    for (var stride = THREADS / 2u; stride > 0u; stride = stride / 2u) {
        if (thread < stride) { partial[thread] = plus(partial[thread], partial[thread + stride]); }
        workgroupBarrier();
    }
    if (thread == 0u) { append(partial[0], lights); }
    workgroupBarrier();
}

@compute @workgroup_size(8, 8)
fn aggregate(@builtin(workgroup_id) block: vec3u, @builtin(local_invocation_id) local: vec3u,
             @builtin(local_invocation_index) thread: u32) {
    let res = gather_info.x;
    let side = gather_info.w;
    let pair = pairs[block.z];
    let light = lights[pair.z];
    let real_light = light.direction_real.w > 0.5;
    // A virtual light's light is in no photo: its maps keep every texel.
    let photo = params.gathered.y == 1u && real_light;
    let zero = Sum(vec4f(0.0), vec4f(0.0), vec4f(0.0));
    // Lit real texels; hidden ones the camera does not see, and those it sees; the virtual
    // texels that hide them.
    var lit = zero;
    var hidden = zero;
    var hidden_seen = zero;
    var hiding = zero;
    let per_thread = side / 8u;
    for (var j = 0u; j < per_thread; j++) {
        for (var i = 0u; i < per_thread; i++) {
            let x = block.x * side + local.x + 8u * i;
            let y = block.y * side + local.y + 8u * j;
            let real = rsm[(pair.x * res + y) * res + x];
            let virt = rsm[(pair.y * res + y) * res + x];
            let real_hit = real.position.w > 0.5;
            if (bounce_visible() && virt.position.w > 0.5) {
                mark_plane(virt.position.xyz, virt.normal.xyz, virt.albedo.rgb * (1.0 - virt.albedo.w));
            }
            if (virtual_nearer(light, real, virt)) {
                hiding = plus(hiding, texel_sum(virt));
                if (real_hit && real_light) {
                    if (photo && seen_by_camera(real.position.xyz, real.normal.xyz, cell_side())) {
                        hidden_seen = plus(hidden_seen, texel_sum(real));
                    } else {
                        hidden = plus(hidden, texel_sum(real));
                    }
                }
                continue;
            }
            if (!real_hit) { continue; }
            if (photo && seen_by_camera(real.position.xyz, real.normal.xyz, cell_side())) { continue; }
            lit = plus(lit, texel_sum(real));
        }
    }
    let gathered_bounce = !bounce_propagated();
    let lit_lights = select(VPL_RHO | VPL_DELTA, VPL_RHO | VPL_MU, real_light);
    append_workgroup_sum(thread, lit, select(VPL_RHO, lit_lights, gathered_bounce));
    // Most blocks hold no virtual surface: one sum, not four (each a reduction with its
    // barriers; four in every block took the pass from 0.09 to 0.19 ms on cornell at 1080p).
    if (hiding.position.w > 0.0) { block_changes = 1u; }
    if (workgroupUniformLoad(&block_changes) == 0u) { return; }
    // V_ρ as Franke's R_ρ injects it: the lit virtual texels light the virtual objects too
    // (one bounce between them: a torus's hole, blocks facing each other), and the real
    // surfaces the camera sees in the virtual content's shadow take from it the light of the
    // photo that the shadow removes (`VPL_RHO_HIDDEN`). Without either, cornell's virtual faces
    // beside its shadowed walls took 16–30 % too much light and desk-spot-real's too little
    // (docs/benchmarks.md, 2026-12-06).
    if (!gathered_bounce) {
        append_workgroup_sum(thread, hidden_seen, VPL_RHO_HIDDEN);
        append_workgroup_sum(thread, hiding, VPL_RHO);
        return;
    }
    append_workgroup_sum(thread, hidden, VPL_MU | VPL_DELTA_HIDDEN);
    append_workgroup_sum(thread, hidden_seen, VPL_DELTA_HIDDEN | VPL_RHO_HIDDEN);
    append_workgroup_sum(thread, hiding, VPL_DELTA | VPL_RHO);
}

// Set by any invocation of the workgroup whose texels a virtual surface hides (every one
// writes the same value).
var<workgroup> block_changes: u32;
