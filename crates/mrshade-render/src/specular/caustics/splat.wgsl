// Caustic buffer by quad splatting (reflections spec §2.17.2): every photon that landed is a
// quad on its receiver's plane, of the half-size emit.wgsl's cs_size found (normal.w). Its power is spread
// by a tent kernel that integrates to one over the quad; neighbours one quad half-size apart
// sum to a partition of unity, so the buffer holds irradiance, W/m², and a caustic keeps its
// energy. Additive blending gathers the photons of L_rv in one target and those of L_r in
// the other (rgb: irradiance; a: photon count, for the thesis's k_c). A fragment counts only
// where the camera's surface lies on the quad (§2.17.4's depth test, as a fraction of the
// camera distance) and faces the same way.
// Two levels (Wyman's hierarchical caustic maps, in two levels): photons at most `splat_max`
// apart go to the fine buffer, those farther apart (a convex mirror's diverging reflection)
// to a coarse one of 1/COARSE_LEVEL_FACTOR its resolution per axis, where a quad of their own
// size costs few texels. Each level's draw runs over its list of landed photons only (the
// vertex stage, not blending, bound the splat on the H200 while it ran over every slot).

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<uniform> caustics: CausticParams;
@group(0) @binding(2) var<storage, read> photons: array<Photon>;
@group(0) @binding(3) var gbuffer_depth_motion: texture_2d<f32>;
@group(0) @binding(4) var gbuffer_normal_roughness: texture_2d<f32>;
// cs_size's lists of the landed photons per level, and the level this draw splats (x).
@group(0) @binding(5) var<storage, read> splat_list: array<u32>;
@group(0) @binding(6) var<uniform> level: vec4u;

struct Splat {
    @builtin(position) clip: vec4f,
    // the quad's corner, in half-sizes
    @location(0) local: vec2f,
    // the point of the quad (world), perspective-interpolated: exact on the plane
    @location(1) world: vec3f,
    // the photon's power over its quad's area: its irradiance where the tent is 1
    @location(2) @interpolate(flat) irradiance: vec3f,
    // the receiver's normal
    @location(3) @interpolate(flat) normal: vec3f,
    // caustic-buffer divisor of the level drawn
    @location(4) @interpolate(flat) divisor: u32,
    // 0, 1: a photon of L_rv; 2, 3: of L_r
    @location(5) @interpolate(flat) kind: u32,
}

// What is the same over a photon's quad is worked out once, in its six vertices, rather than
// in each of its fragments (the probe's 64 directions overlap hundreds of quads a texel).
@vertex
fn vs_main(@builtin(vertex_index) vertex: u32) -> Splat {
    var out: Splat;
    // Six vertices per photon (not instances of six: tiny instances starve the vertex stage).
    let index = splat_list[level.x * photon_slots() + vertex / 6u];
    let photon = photons[index];
    let h = photon.normal.w;
    // Two triangles: corners (−1,−1) (1,−1) (1,1), (−1,−1) (1,1) (−1,1).
    var corners = array<vec2f, 6>(
        vec2f(-1.0, -1.0), vec2f(1.0, -1.0), vec2f(1.0, 1.0),
        vec2f(-1.0, -1.0), vec2f(1.0, 1.0), vec2f(-1.0, 1.0),
    );
    let local = corners[vertex % 6u];
    let tb = tangent_frame(photon.normal.xyz);
    let world = photon.position.xyz + (tb[0] * local.x + tb[1] * local.y) * h;
    out.clip = frame.clip_from_world * vec4f(world, 1.0);
    out.local = local;
    out.world = world;
    out.kind = (index / (caustics.info.x * caustics.info.x)) % PHOTON_KINDS;
    out.irradiance = photon.power.rgb / (h * h);
    out.normal = photon.normal.xyz;
    out.divisor = caustics.info.w * select(1u, COARSE_LEVEL_FACTOR, level.x == 1u);
    return out;
}

struct Targets {
    @location(0) rv: vec4f,
    @location(1) r: vec4f,
}

@fragment
fn fs_main(in: Splat) -> Targets {
    // This caustic-buffer texel's centre on the full-size G-buffer.
    let at = in.clip.xy * f32(in.divisor);
    let pixel = min(vec2i(at), vec2i(frame.size.xy) - 1);
    let surface = world_from_pixel(frame, at, textureLoad(gbuffer_depth_motion, pixel, 0).x);
    let to_camera = distance(surface, frame.camera_position.xyz);
    let n = textureLoad(gbuffer_normal_roughness, pixel, 0).xyz;
    if (distance(in.world, surface) > caustics.splat.w * to_camera || dot(n, in.normal) < 0.5) {
        discard;
    }
    // quad_irradiance, its division done per photon.
    let e = vec4f(in.irradiance * quad_tent(in.local), 1.0);
    var out: Targets;
    if (in.kind < 2u) { out.rv = e; } else { out.r = e; }
    return out;
}
