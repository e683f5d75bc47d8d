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
// The maps' and the photo's VPLs appended, then the cells' (`cell_vpls`, from
// `cells_gathered.rho_first.w` on).
@group(0) @binding(6) var<storage, read_write> vpl_count: array<atomic<u32>, 2>;
@group(0) @binding(7) var<uniform> cells_gathered: GatherInfo;
// Per cell two vec4f, written by `cell_vpls`: the mean plane of the virtual surfaces the maps
// see in it (unit normal, ⟨n, p⟩; zero where none) and their diffuse albedo (vpl_gather.wgsl
// `blocked` reads it).
@group(0) @binding(8) var<storage, read_write> planes: array<vec4f>;
// The accumulated volumes and V_ρ's band 2 as the last gather left them (volume_read.wgsl),
// for the light the virtual surfaces send on (`cell_vpls`).
@group(0) @binding(9) var<storage, read> volumes: array<vec4f>;
@group(0) @binding(10) var<storage, read> rho_band2: array<vec4f>;
// Per cell and way a surface can face (`PLANE_WAYS`: ±x, ±y, ±z, by its normal's largest
// component), `PLANE_SUMS` fixed-point sums over the virtual texels the maps see in it,
// cleared before the pass (`mark_plane`): integer sums are the same in whatever order the
// texels of many maps add to them, so that a still renders the same twice (one texel's plane,
// written by whichever came last, moved cornell's region FLIP by up to 0.002 from run to
// run). By way, so that a cell on a block's edge holds both its faces (one mean plane there,
// tilted between them, sent a third of a face's light along it).
@group(0) @binding(11) var<storage, read_write> plane_sums: array<atomic<i32>>;
// Per block of 4³ cells, `BLOCK_*` bits (volume.wgsl): `cell_vpls` flags the blocks of the
// cells within one of a virtual surface's, whose V_ρ it reads next time.
@group(0) @binding(12) var<storage, read_write> blocks_read: array<u32>;

const PLANE_WAYS: u32 = 6u;
// The sums of one way: the normal (3), its plane's offset from the cell's centre in cells
// (1), the diffuse albedo (3) and the texels.
const PLANE_SUMS: u32 = 8u;
// Fixed-point units per unit (a normal's component, an offset in cells, an albedo, each at
// most 1 in magnitude): `PLANE_TEXELS` of them sum to at most 2^30.
const PLANE_UNITS: f32 = 65536.0;
// Texels a way of a cell takes at most (a 2.4 cm cell holds about 1 500 of a 512² map over
// cornell's floor); those past it, in whatever order they come, are left out.
const PLANE_TEXELS: i32 = 16384;

fn fixed(x: f32) -> i32 { return i32(round(clamp(x, -1.0, 1.0) * PLANE_UNITS)); }

// The way unit normal `n` faces: 0–5 for +x, −x, +y, −y, +z, −z.
fn way_of(n: vec3f) -> u32 {
    let a = abs(n);
    let axis = select(select(2u, 1u, a.y >= a.z), 0u, a.x >= a.y && a.x >= a.z);
    return 2u * axis + select(1u, 0u, n[axis] >= 0.0);
}

// Adds the virtual surface point `p` (normal `n`, diffuse albedo `albedo`) to its cell's sums.
fn mark_plane(p: vec3f, n: vec3f, albedo: vec3f) {
    let c = vec3i(floor(cell_coords(p)));
    if (!cell_inside(c)) { return; }
    let at = (cell_index(c) * PLANE_WAYS + way_of(n)) * PLANE_SUMS;
    if (atomicAdd(&plane_sums[at + 7u], 1) >= PLANE_TEXELS) {
        atomicSub(&plane_sums[at + 7u], 1);
        return;
    }
    let centre = params.origin.xyz + (vec3f(c) + 0.5) * cell_side();
    // Within ±√3/2 cells: p lies in the cell.
    let offset = dot(n, p - centre) / cell_side();
    atomicAdd(&plane_sums[at], fixed(n.x));
    atomicAdd(&plane_sums[at + 1u], fixed(n.y));
    atomicAdd(&plane_sums[at + 2u], fixed(n.z));
    atomicAdd(&plane_sums[at + 3u], fixed(offset));
    atomicAdd(&plane_sums[at + 4u], fixed(albedo.r));
    atomicAdd(&plane_sums[at + 5u], fixed(albedo.g));
    atomicAdd(&plane_sums[at + 6u], fixed(albedo.b));
}

// The mean surface of one way of a cell: unit normal, offset from the centre (m), albedo and
// texels (0: none).
struct CellSurface {
    n: vec3f,
    offset: f32,
    albedo: vec3f,
    texels: f32,
}

fn cell_surface(at: u32) -> CellSurface {
    let texels = f32(atomicLoad(&plane_sums[at + 7u]));
    if (texels == 0.0) { return CellSurface(vec3f(0.0), 0.0, vec3f(0.0), 0.0); }
    let sum = vec3f(f32(atomicLoad(&plane_sums[at])), f32(atomicLoad(&plane_sums[at + 1u])),
                    f32(atomicLoad(&plane_sums[at + 2u])));
    let albedo = vec3f(f32(atomicLoad(&plane_sums[at + 4u])), f32(atomicLoad(&plane_sums[at + 5u])),
                       f32(atomicLoad(&plane_sums[at + 6u])));
    let offset = f32(atomicLoad(&plane_sums[at + 3u])) / PLANE_UNITS / texels * cell_side();
    return CellSurface(normalize(sum), offset, albedo / PLANE_UNITS / texels, texels);
}

// One invocation per cell: for each way its virtual texels face, a VPL of the light that
// surface takes from V_ρ, E·albedo over the cell's share of its mean plane (h² / the
// normal's largest component) times the way's share of the cell's texels (the two faces of
// a block's edge share its cell; each with the whole cell's plane, a curved bunny's cells
// sent out up to twice their light and its shadows on the desk went lighter), at the plane's
// point nearest the cell's centre; and in
// `planes` the plane of the way with the most texels, which the gather's paths test. The
// VPLs light V_ρ (one virtual surface lights another: on cornell the red wall's light off the
// cube's side brightens the tall block's foot by a third in the path tracer's answer, which
// the maps' direct light alone left out) and V_Δ (the content's own bounce light on real
// surfaces, without which its blocked light alone left cornell's contact shadows twice too
// dark). V_ρ is the last gather's (a frame late while the content moves; `VplGather` gathers
// once more after a still's first frame); the maps' VPLs of the virtual surfaces (`hiding`)
// carry their direct light.
@compute @workgroup_size(64)
fn cell_vpls(@builtin(global_invocation_id) id: vec3u) {
    let res = params.info.x;
    let i = id.x;
    if (i >= cells()) { return; }
    let h = cell_side();
    let c = vec3f(f32(i % res), f32((i / res) % res), f32(i / (res * res)));
    let centre = params.origin.xyz + (c + 0.5) * h;
    var most = 0.0;
    var plane = vec4f(0.0);
    var plane_albedo = vec4f(0.0);
    var texels = 0.0;
    for (var way = 0u; way < PLANE_WAYS; way++) {
        texels += f32(atomicLoad(&plane_sums[(i * PLANE_WAYS + way) * PLANE_SUMS + 7u]));
    }
    for (var way = 0u; way < PLANE_WAYS; way++) {
        let s = cell_surface((i * PLANE_WAYS + way) * PLANE_SUMS);
        if (s.texels == 0.0) { continue; }
        if (s.texels > most) {
            most = s.texels;
            plane = vec4f(s.n, dot(s.n, centre) + s.offset);
            plane_albedo = vec4f(s.albedo, 1.0);
        }
        let p = centre + s.offset * s.n;
        let e = max(volume_irradiance(VOLUME_RHO, p, s.n), vec3f(0.0));
        let area = h * h / max(max(abs(s.n.x), abs(s.n.y)), abs(s.n.z)) * s.texels / texels;
        let flux = s.albedo * e * area;
        if (all(flux == vec3f(0.0))) { continue; }
        var vpl: GatherVpl;
        vpl.position = vec4f(p, area);
        vpl.normal = vec4f(s.n, f32(VPL_RHO | VPL_DELTA | VPL_CELL));
        vpl.flux = vec4f(flux, 0.0);
        vpls[cells_gathered.rho_first.w + atomicAdd(&vpl_count[1], 1u)] = vpl;
    }
    planes[2u * i] = plane;
    planes[2u * i + 1u] = plane_albedo;
    // The blocks of the cells within one of it (those V_ρ is read from at its surface): the
    // gather sums V_ρ only in blocks a pixel reads or these.
    if (texels > 0.0) { flag_blocks(vec3i(c) - 1, vec3i(c) + 1, BLOCK_NEAR_VIRTUAL); }
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
    vpls[atomicAdd(&vpl_count[0], 1u)] = vpl;
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
            if (virtual_bounce() && virt.position.w > 0.5) {
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
