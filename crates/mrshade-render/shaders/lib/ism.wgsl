// Imperfect shadow maps (Knecht §2.9, Ritschel et al. 2008): one small depth map per VPL in an
// atlas, splatted from a sparse point cloud. Surface VPLs use the hemispherical (Nusselt,
// "cosine") mapping around their normal, directional VPLs an orthographic map of the bounding
// sphere of the atlas's own points (real or virtual), so that small virtual objects get the
// whole map's resolution. Texels store (0xffffffff − distance bits) so that `atomicMax` keeps the
// nearest point and a cleared (zero) texel means "nothing in this direction".
// Mirrors `IsmParams` and `GpuPoint` in src/passes/ism/mod.rs.

struct Point {
    position: vec3f,
    instance: u32,
    normal: vec3f,
    material: u32,
}

struct IsmParams {
    // tile resolution, tiles per atlas row, VPL count, points per VPL
    tile: vec4u,
    // bounding sphere of the real points (the scene): centre, radius
    scene: vec4f,
    // bounding sphere of the virtual points
    scene_virtual: vec4f,
    // splat half-size of real and virtual points (m), relative depth bias, receiver offset
    // along its normal in splat half-sizes
    splat: vec4f,
}

struct IsmCoord {
    uv: vec2f,
    depth: f32,
    valid: bool,
}

fn ism_sphere(params: IsmParams, virtual_atlas: bool) -> vec4f {
    return select(params.scene, params.scene_virtual, virtual_atlas);
}

// Where world point `p` falls in VPL `v`'s map of the real or the virtual atlas. Directional
// maps are not `valid` outside their sphere (nothing of that atlas can shadow there).
fn ism_project(v: Vpl, p: vec3f, params: IsmParams, virtual_atlas: bool) -> IsmCoord {
    var c: IsmCoord;
    if (vpl_kind(v) == VPL_DIRECTIONAL) {
        let sphere = ism_sphere(params, virtual_atlas);
        let d = v.position.xyz;
        let tb = tangent_frame(d);
        let q = p - sphere.xyz;
        let r = sphere.w;
        c.uv = 0.5 + 0.5 * vec2f(dot(q, tb[0]), dot(q, tb[1])) / r;
        c.depth = max(dot(q, d) + r, 0.0);
        c.valid = all(c.uv >= vec2f(0.0)) && all(c.uv < vec2f(1.0));
        return c;
    }
    let to = p - v.position.xyz;
    c.depth = length(to);
    let l = to / max(c.depth, 1e-9);
    let tb = tangent_frame(v.normal.xyz);
    c.uv = 0.5 + 0.5 * vec2f(dot(l, tb[0]), dot(l, tb[1]));
    c.valid = dot(l, v.normal.xyz) > 0.0;
    return c;
}

fn ism_texel_index(vpl: u32, uv: vec2f, params: IsmParams) -> u32 {
    let res = params.tile.x;
    let t = clamp(vec2u(uv * f32(res)), vec2u(0u), vec2u(res - 1u));
    let tile = vec2u(vpl % params.tile.y, vpl / params.tile.y);
    let atlas_width = params.tile.y * res;
    return (tile.y * res + t.y) * atlas_width + tile.x * res + t.x;
}

fn ism_encode(depth: f32) -> u32 { return 0xffffffffu - bitcast<u32>(depth); }

// The low bits of a texel name the nearest caster's material (its index + 1; 0: none known,
// i.e. opaque), so that a transmissive caster lets light through its shadow
// (`caster_transmittance`). They cost the depth 8 of its 23 mantissa bits: 3·10⁻⁵ relative.
const ISM_CASTER_BITS: u32 = 0xffu;
fn ism_encode_caster(depth: f32, material: u32) -> u32 {
    let code = select(0u, material + 1u, material < ISM_CASTER_BITS);
    return (ism_encode(depth) & ~ISM_CASTER_BITS) | code;
}
fn ism_caster_material(stored: u32) -> u32 { return (stored & ISM_CASTER_BITS) - 1u; }
fn ism_caster_known(stored: u32) -> bool { return (stored & ISM_CASTER_BITS) != 0u; }
fn ism_decode(stored: u32) -> f32 {
    if (stored == 0u) { return 3.0e38; }
    return bitcast<f32>(0xffffffffu - stored);
}

// World-space extent of one texel of a VPL's map at `depth` (for biasing lookups).
fn ism_texel_extent(v: Vpl, depth: f32, params: IsmParams, virtual_atlas: bool) -> f32 {
    if (vpl_kind(v) == VPL_DIRECTIONAL) { return 2.0 * ism_sphere(params, virtual_atlas).w / f32(params.tile.x); }
    return 2.0 * depth / f32(params.tile.x);
}
