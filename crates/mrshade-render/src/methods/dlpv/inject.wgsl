// Split injection (Franke §2.12.2–§2.12.4, Eq. 5.12–5.13). One invocation per texel of a
// pair of a light's reflective shadow maps, real-only and virtual-only (their nearer hit is
// R_ρ's texel, the real one R_μ's; a virtual light has no R_μ, all its light is change):
// - V_ρ: R_ρ's real VPLs, I(ω) = Φ/π·⟨n, ω⟩₊, for the virtual objects' indirect light. A
//   virtual object's own VPLs are left out: at the volume's resolution they light the object
//   they lie on (the thesis's "self-illumination", spec §2.12.9), which made the bunny of
//   desk-bunny 60 % too bright; light between virtual objects is lost with them;
// - V_μ: R_μ's VPLs, the real scene's own bounce light (the model of the photo's indirect
//   light: real pixels add it to L_r and L_rv, so that the α-scaled composite divides the
//   photo by a model that has it, as with the other methods);
// - indirect change: +R_ρ's VPL − R_μ's VPL, only where they differ (where a virtual surface is
//   nearer); texels seen by both cancel exactly instead of by subtractive blending;
// - direct change (lights split from the probe only; punctual shadows come from the shadow
//   maps): −Φ of the light on the real surface that the virtual one now hides, lobe along the
//   light's direction, half a cell toward the light. The positive half, light on the virtual
//   surface, is left out: propagated along the light it would relight the shadow it casts,
//   and virtual pixels are shaded directly.
// Each is splatted trilinearly, half a cell along its lobe (the thesis's guard against
// self-illumination), as fixed-point atomics (WGSL has no float atomics).

@group(0) @binding(0) var<uniform> params: DlpvParams;
@group(0) @binding(1) var<storage, read> rsm: array<RsmTexel>;
// Per pair: real-only layer, virtual-only layer, light, 1 if its direct change is injected.
@group(0) @binding(2) var<storage, read> pairs: array<vec4u>;
@group(0) @binding(3) var<storage, read> lights: array<Light>;
// Per source, per channel, per cell: four coefficients.
@group(0) @binding(4) var<storage, read_write> injected: array<atomic<i32>>;
@group(0) @binding(5) var<uniform> rsm_size: vec4u;

// A splat's fixed-point values at the eight cells around it: per corner (x, y, z bits of k)
// and channel, four coefficients, rounded per splat (so that the sums do not depend on the
// order of the additions: a tile's sum in workgroup memory equals the global atomics').
fn splat_corner(f: vec3f, corner: u32, coefficients: array<vec4f, 3>, ch: u32) -> vec4i {
    let o = vec3u(corner & 1u, (corner >> 1u) & 1u, corner >> 2u);
    let w3 = select(1.0 - f, f, vec3<bool>(o == vec3u(1u)));
    let w = w3.x * w3.y * w3.z * params.scale.x;
    return vec4i(round(coefficients[ch] * w));
}

// The lower of the eight cells a splat at `p` reaches, and its trilinear weights.
fn splat_base(p: vec3f) -> vec3i { return vec3i(floor(cell_coords(p) - 0.5)); }
fn splat_fraction(p: vec3f) -> vec3f {
    let x = cell_coords(p) - 0.5;
    return x - floor(x);
}

// Whether any of a splat's eight cells lies in the volume.
fn reaches_volume(base: vec3i) -> bool {
    return all(base >= vec3i(-1)) && all(base < vec3i(i32(params.info.x)));
}

// Adds a splat straight to the volume's atomics.
fn splat_global(source: u32, p: vec3f, coefficients: array<vec4f, 3>) {
    let base = splat_base(p);
    let f = splat_fraction(p);
    for (var corner = 0u; corner < 8u; corner++) {
        let c = base + vec3i(vec3u(corner & 1u, (corner >> 1u) & 1u, corner >> 2u));
        if (!cell_inside(c)) { continue; }
        let cell = cell_index(c);
        for (var ch = 0u; ch < 3u; ch++) {
            let q = splat_corner(f, corner, coefficients, ch);
            let at = ((source * 3u + ch) * cells() + cell) * 4u;
            for (var k = 0u; k < 4u; k++) {
                if (q[k] != 0) { atomicAdd(&injected[at + k], q[k]); }
            }
        }
    }
}

// A VPL's intensity coefficients: reflected flux Φ_r, lobe ⟨n, ω⟩₊/π.
fn vpl(texel: RsmTexel) -> array<vec4f, 3> {
    let reflected = texel.power.rgb * texel.albedo.rgb * (1.0 - texel.albedo.w);
    let lobe = sh4_clamped_cosine(texel.normal.xyz) / PI;
    return array<vec4f, 3>(lobe * reflected.r, lobe * reflected.g, lobe * reflected.b);
}

fn vpl_position(texel: RsmTexel) -> vec3f {
    return texel.position.xyz + 0.5 * cell_side() * texel.normal.xyz;
}

// Distance along the light's ray (for which of two hits is nearer).
fn light_depth(light: Light, p: vec3f) -> f32 {
    if (light.info.x == LIGHT_DIRECTIONAL) { return dot(p, light.direction_real.xyz); }
    return distance(p, light.position.xyz);
}

// What one texel pair injects.
struct Splat {
    source: u32,
    p: vec3f,
    c: array<vec4f, 3>,
}

const MAX_SPLATS: u32 = 5u;

struct Plan {
    count: u32,
    splats: array<Splat, MAX_SPLATS>,
}

fn add(plan: ptr<function, Plan>, source: u32, p: vec3f, c: array<vec4f, 3>) {
    (*plan).splats[(*plan).count] = Splat(source, p, c);
    (*plan).count += 1u;
}

fn negated(c: array<vec4f, 3>) -> array<vec4f, 3> { return array<vec4f, 3>(-c[0], -c[1], -c[2]); }

fn plan_of(id: vec3u) -> Plan {
    var plan: Plan;
    plan.count = 0u;
    let res = rsm_size.x;
    if (id.x >= res || id.y >= res || id.z >= rsm_size.y) { return plan; }
    let pair = pairs[id.z];
    let real = rsm[(pair.x * res + id.y) * res + id.x];
    let virt = rsm[(pair.y * res + id.y) * res + id.x];
    let light = lights[pair.z];
    let real_hit = real.position.w > 0.5;
    let virtual_hit = virt.position.w > 0.5;
    let virtual_nearer = virtual_hit && (!real_hit || light_depth(light, virt.position.xyz) < light_depth(light, real.position.xyz));
    if (light.direction_real.w < 0.5) {
        // A virtual light exists in the real+virtual solution only: R_μ is empty, and all
        // of R_ρ's bounce light is change.
        if (virtual_nearer) {
            add(&plan, SOURCE_INDIRECT, vpl_position(virt), vpl(virt));
        } else if (real_hit) {
            let r = vpl(real);
            add(&plan, SOURCE_RHO, vpl_position(real), r);
            add(&plan, SOURCE_INDIRECT, vpl_position(real), r);
        }
        return plan;
    }
    // V_ρ's real VPLs are V_μ's but for those a virtual surface hides: V_ρ's slot holds only
    // that difference, and the seed adds V_μ to it (half the atomics of injecting every
    // texel twice; the same sum).
    if (real_hit) {
        add(&plan, SOURCE_MU, vpl_position(real), vpl(real));
    }
    if (!virtual_nearer) { return plan; }
    add(&plan, SOURCE_INDIRECT, vpl_position(virt), vpl(virt));
    if (!real_hit) { return plan; }
    let hidden = negated(vpl(real));
    add(&plan, SOURCE_INDIRECT, vpl_position(real), hidden);
    add(&plan, SOURCE_RHO, vpl_position(real), hidden);
    if (pair.w == 1u) {
        // Lobe along the light (a direction, as SH of a delta), scaled so that the query on
        // this surface returns the irradiance taken away (the L1 projection of a delta
        // answers (1/4 + cos/2) of it).
        var d = light.direction_real.xyz;
        if (light.info.x != LIGHT_DIRECTIONAL) { d = normalize(real.position.xyz - light.position.xyz); }
        let cos_n = max(dot(-d, real.normal.xyz), 0.25);
        let lobe = sh4(d) / (0.25 + 0.5 * cos_n);
        let lost = -real.power.rgb;
        add(&plan, SOURCE_DIRECT, real.position.xyz - 0.5 * cell_side() * d, array<vec4f, 3>(lobe * lost.r, lobe * lost.g, lobe * lost.b));
    }
    return plan;
}

// A tile's splats are summed in workgroup memory first when their cells fit a 4³ block (the
// usual case: neighbouring texels land in neighbouring cells), then added to the volume once
// per touched value: 64 texels' adds to the same few cells otherwise queue on the same
// global atomics (the pass took 0.30 ms of a moving cornell frame on an H200).
const TILE_SIDE: i32 = 4;
const TILE_VALUES: u32 = 3072u; // 4 sources × 3 channels × 4³ cells × 4 coefficients
var<workgroup> tile: array<atomic<i32>, 3072>;
var<workgroup> tile_lo: array<atomic<i32>, 3>;
var<workgroup> tile_hi: array<atomic<i32>, 3>;
var<workgroup> tile_origin: vec3i;
var<workgroup> tile_fits: u32;

fn tile_index(source: u32, ch: u32, local: vec3i, k: u32) -> u32 {
    let cell = u32(local.x + TILE_SIDE * (local.y + TILE_SIDE * local.z));
    return ((source * 3u + ch) * 64u + cell) * 4u + k;
}

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3u, @builtin(local_invocation_index) lane: u32) {
    if (lane < 3u) {
        atomicStore(&tile_lo[lane], 1 << 30u);
        atomicStore(&tile_hi[lane], -(1 << 30u));
    }
    workgroupBarrier();
    let plan = plan_of(id);
    for (var i = 0u; i < plan.count; i++) {
        let base = splat_base(plan.splats[i].p);
        if (!reaches_volume(base)) { continue; }
        for (var a = 0u; a < 3u; a++) {
            atomicMin(&tile_lo[a], base[a]);
            atomicMax(&tile_hi[a], base[a]);
        }
    }
    workgroupBarrier();
    if (lane == 0u) {
        let lo = vec3i(atomicLoad(&tile_lo[0]), atomicLoad(&tile_lo[1]), atomicLoad(&tile_lo[2]));
        let hi = vec3i(atomicLoad(&tile_hi[0]), atomicLoad(&tile_hi[1]), atomicLoad(&tile_hi[2]));
        tile_origin = lo;
        // Empty (lo > hi) or within TILE_SIDE − 1 bases (each splat reaches one more cell).
        tile_fits = select(0u, 1u, all(hi - lo <= vec3i(TILE_SIDE - 2)));
    }
    if (workgroupUniformLoad(&tile_fits) == 0u) {
        for (var i = 0u; i < plan.count; i++) {
            splat_global(plan.splats[i].source, plan.splats[i].p, plan.splats[i].c);
        }
        return;
    }
    let origin = tile_origin;
    for (var i = 0u; i < plan.count; i++) {
        let s = plan.splats[i];
        let base = splat_base(s.p);
        if (!reaches_volume(base)) { continue; }
        let f = splat_fraction(s.p);
        for (var corner = 0u; corner < 8u; corner++) {
            let local = base - origin + vec3i(vec3u(corner & 1u, (corner >> 1u) & 1u, corner >> 2u));
            for (var ch = 0u; ch < 3u; ch++) {
                let q = splat_corner(f, corner, s.c, ch);
                for (var k = 0u; k < 4u; k++) {
                    if (q[k] != 0) { atomicAdd(&tile[tile_index(s.source, ch, local, k)], q[k]); }
                }
            }
        }
    }
    workgroupBarrier();
    for (var i = lane; i < TILE_VALUES; i += 64u) {
        let q = atomicLoad(&tile[i]);
        if (q == 0) { continue; }
        let k = i % 4u;
        let cell = (i / 4u) % 64u;
        let source_ch = i / 256u;
        let c = origin + vec3i(i32(cell % 4u), i32((cell / 4u) % 4u), i32(cell / 16u));
        if (!cell_inside(c)) { continue; }
        atomicAdd(&injected[(source_ch * cells() + cell_index(c)) * 4u + k], q);
    }
}
