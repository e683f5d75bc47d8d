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
//   V_μ and the indirect change only when propagated (`dlpv.bounce_light`; by default they
//   are gathered from VPLs, vpl.wgsl);
// - direct change (lights split from the probe only; punctual shadows come from the shadow
//   maps): −Φ of the light on the real surface that the virtual one now hides, lobe along the
//   light's direction, half a cell toward the light, weighted by how broad the light is
//   (1 − probe_light_sharpness: the merge reads the sharp lights' shadow from their maps,
//   `dlpv.sharp_probe_shadows_deg`; every light when that is 0). The positive half, light on
//   the virtual surface, is left out: propagated along the light it would relight the shadow
//   it casts, and virtual pixels are shaded directly.
// Each is shifted half a cell along its lobe (the thesis's guard against self-illumination)
// and added to the cell it then lies in (`dlpv.splat = "cell"`, the thesis's) or to the
// eight around it by trilinear weights, as fixed-point atomics (WGSL has no float atomics).

@group(0) @binding(0) var<uniform> params: DlpvParams;
@group(0) @binding(1) var<storage, read> rsm: array<RsmTexel>;
// Per pair: real-only layer, virtual-only layer, light, and for the probe's lights their
// angular radius as f32 bits (probe_maps.rs).
@group(0) @binding(2) var<storage, read> pairs: array<vec4u>;
@group(0) @binding(3) var<storage, read> lights: array<Light>;
// Per source, per channel, per cell: four coefficients.
@group(0) @binding(4) var<storage, read_write> injected: array<atomic<i32>>;
// The maps' side, pairs, 1 if the set's direct change is injected (the probe's lights).
@group(0) @binding(5) var<uniform> rsm_size: vec4u;

fn splat(source: u32, p: vec3f, coefficients: array<vec4f, 3>) {
    if (params.info.w == SPLAT_CELL) {
        let c = vec3i(floor(cell_coords(p)));
        if (cell_inside(c)) { add_to_cell(source, cell_index(c), coefficients, params.scale.x); }
        return;
    }
    let x = cell_coords(p) - 0.5;
    let base = vec3i(floor(x));
    let f = x - floor(x);
    for (var corner = 0u; corner < 8u; corner++) {
        let o = vec3u(corner & 1u, (corner >> 1u) & 1u, corner >> 2u);
        let c = base + vec3i(o);
        if (!cell_inside(c)) { continue; }
        let w3 = select(1.0 - f, f, vec3<bool>(o == vec3u(1u)));
        let w = w3.x * w3.y * w3.z * params.scale.x;
        if (w <= 0.0) { continue; }
        add_to_cell(source, cell_index(c), coefficients, w);
    }
}

// Adds `coefficients` times `w` (fixed-point units) to `cell` of source `source`.
fn add_to_cell(source: u32, cell: u32, coefficients: array<vec4f, 3>, w: f32) {
    for (var ch = 0u; ch < 3u; ch++) {
        let at = ((source * 3u + ch) * cells() + cell) * 4u;
        let v = coefficients[ch] * w;
        for (var k = 0u; k < 4u; k++) {
            let q = i32(round(v[k]));
            if (q != 0) { atomicAdd(&injected[at + k], q); }
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

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3u) {
    let res = rsm_size.x;
    if (id.x >= res || id.y >= res || id.z >= rsm_size.y) { return; }
    let pair = pairs[id.z];
    let real = rsm[(pair.x * res + id.y) * res + id.x];
    let virt = rsm[(pair.y * res + id.y) * res + id.x];
    let light = lights[pair.z];
    let real_hit = real.position.w > 0.5;
    let virtual_hides = virtual_nearer(light, real, virt);
    if (light.direction_real.w < 0.5) {
        // A virtual light exists in the real+virtual solution only: R_μ is empty, and all
        // of R_ρ's bounce light is change.
        if (virtual_hides) {
            if (bounce_propagated()) { splat(SOURCE_INDIRECT, vpl_position(virt), vpl(virt)); }
        } else if (real_hit) {
            let r = vpl(real);
            if (rho_propagated()) { splat(SOURCE_RHO, vpl_position(real), r); }
            if (bounce_propagated()) { splat(SOURCE_INDIRECT, vpl_position(real), r); }
        }
        return;
    }
    // V_ρ's real VPLs are V_μ's but for those a virtual surface hides: V_ρ's slot holds only
    // that difference, and the seed adds V_μ to it (half the atomics of injecting every
    // texel twice; the same sum).
    if (real_hit && bounce_propagated()) {
        splat(SOURCE_MU, vpl_position(real), vpl(real));
    }
    if (!virtual_hides) { return; }
    if (bounce_propagated()) { splat(SOURCE_INDIRECT, vpl_position(virt), vpl(virt)); }
    if (!real_hit) { return; }
    let r = vpl(real);
    let hidden = array<vec4f, 3>(-r[0], -r[1], -r[2]);
    if (bounce_propagated()) { splat(SOURCE_INDIRECT, vpl_position(real), hidden); }
    if (rho_propagated()) { splat(SOURCE_RHO, vpl_position(real), hidden); }
    if (rsm_size.z == 1u) {
        // Lobe along the light (a direction, as SH of a delta), scaled so that the query on
        // this surface returns the irradiance taken away (the L1 projection of a delta
        // answers (1/4 + cos/2) of it).
        var d = light.direction_real.xyz;
        if (light.info.x != LIGHT_DIRECTIONAL) { d = normalize(real.position.xyz - light.position.xyz); }
        let cos_n = max(dot(-d, real.normal.xyz), 0.25);
        let lobe = sh4(d) / (0.25 + 0.5 * cos_n);
        // What the merge does not read from the maps (every light when it reads none).
        let broad = select(1.0, 1.0 - probe_light_sharpness(pair.w, params.scale.y), params.scale.y > 0.0);
        let lost = -real.power.rgb * broad;
        splat(SOURCE_DIRECT, real.position.xyz - 0.5 * cell_side() * d, array<vec4f, 3>(lobe * lost.r, lobe * lost.g, lobe * lost.b));
    }
}
