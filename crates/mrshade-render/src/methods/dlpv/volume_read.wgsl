// Reading the accumulated volumes at a surface point: the merge's (gather.wgsl) and the
// virtual surfaces' light that the gathered bounce sends on (vpl_aggregate.wgsl `cell_vpls`).
// The including shader binds `volumes` (array<vec4f>: V_ρ, V_Δ, V_μ, each channel-major) and
// `rho_band2` (volume.wgsl); needs shaders/lib/sh.wgsl and volume.wgsl before it.

const VOLUME_RHO: u32 = 0u;
const VOLUME_DELTA: u32 = 1u;
const VOLUME_MU: u32 = 2u;

fn cell_light(volume: u32, i: u32, lobe: vec4f) -> vec3f {
    let first = volume * 3u * cells() + i;
    return vec3f(
        dot(volumes[first], lobe),
        dot(volumes[first + cells()], lobe),
        dot(volumes[first + 2u * cells()], lobe),
    );
}

// Band 2 of cell `i` of V_ρ against the clamped cosine's band 2 (`lobe`: coefficients 4–7,
// `lobe8`: 8).
fn rho_band2_light(i: u32, lobe: vec4f, lobe8: f32) -> vec3f {
    let at = i * 4u;
    return vec3f(dot(rho_band2[at], lobe), dot(rho_band2[at + 1u], lobe), dot(rho_band2[at + 2u], lobe))
        + rho_band2[at + 3u].rgb * lobe8;
}

// Irradiance from `volume` at `p` on a surface of normal `n`; zero outside the volume. V_ρ
// gathered from VPLs adds its band 2 (Â_2 = π/4; even, so the same for n and −n).
fn volume_irradiance(volume: u32, p: vec3f, n: vec3f) -> vec3f {
    let x = cell_coords(p + 0.5 * cell_side() * n) - 0.5;
    let base = vec3i(floor(x));
    let f = x - floor(x);
    let lobe = sh4_clamped_cosine(-n);
    let band2 = volume == VOLUME_RHO && !rho_propagated();
    let lobe2 = PI / 4.0 * sh9_band2(n);
    let lobe8 = PI / 4.0 * sh9_y8(n);
    var e = vec3f(0.0);
    for (var corner = 0u; corner < 8u; corner++) {
        let o = vec3u(corner & 1u, (corner >> 1u) & 1u, corner >> 2u);
        let c = base + vec3i(o);
        if (!cell_inside(c)) { continue; }
        let w3 = select(1.0 - f, f, vec3<bool>(o == vec3u(1u)));
        let w = w3.x * w3.y * w3.z;
        var light = cell_light(volume, cell_index(c), lobe);
        if (band2) { light += rho_band2_light(cell_index(c), lobe2, lobe8); }
        e += w * light;
    }
    return e / (cell_side() * cell_side());
}
