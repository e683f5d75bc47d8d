// Caustic buffer by quad splatting (reflections spec §2.17.2): every photon that landed is a
// quad on its receiver's plane, sized from where its neighbours in the photon map landed
// (Wyman's hierarchical caustic maps; the nearer one along each axis), clamped to [splat_min, splat_max]. Its power is spread
// by a tent kernel that integrates to one over the quad; neighbours one quad half-size apart
// sum to a partition of unity, so the buffer holds irradiance, W/m², and a caustic keeps its
// energy. Additive blending gathers the photons of L_rv in one target and those of L_r in
// the other (rgb: irradiance; a: photon count, for the thesis's k_c). A fragment counts only
// where the camera's surface lies on the quad (§2.17.4's depth test, as a fraction of the
// camera distance) and faces the same way.

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<uniform> caustics: CausticParams;
@group(0) @binding(2) var<storage, read> photons: array<Photon>;
@group(0) @binding(3) var gbuffer_depth_motion: texture_2d<f32>;
@group(0) @binding(4) var gbuffer_normal_roughness: texture_2d<f32>;

struct Splat {
    @builtin(position) clip: vec4f,
    // the quad's corner, in half-sizes
    @location(0) local: vec2f,
    @location(1) @interpolate(flat) photon: u32,
    @location(2) @interpolate(flat) half_size: f32,
}

// World distance to the photon's landed neighbour `dx`, `dy` texels away (0 if none).
fn neighbour_distance(index: u32, texel: vec2u, p: vec3f, dx: i32, dy: i32) -> f32 {
    let res = i32(caustics.info.x);
    let q = vec2i(texel) + vec2i(dx, dy);
    if (any(q < vec2i(0)) || any(q >= vec2i(res))) { return 0.0; }
    let other = photons[u32(i32(index) + dy * res + dx)];
    if (other.position.w == 0.0) { return 0.0; }
    return distance(other.position.xyz, p);
}

// The smaller of two neighbour distances that exist (0: none).
fn nearer(a: f32, b: f32) -> f32 {
    if (a == 0.0) { return b; }
    if (b == 0.0) { return a; }
    return min(a, b);
}

@vertex
fn vs_main(@builtin(vertex_index) vertex: u32, @builtin(instance_index) index: u32) -> Splat {
    var out: Splat;
    out.photon = index;
    let photon = photons[index];
    if (photon.position.w == 0.0) {
        out.clip = vec4f(2.0, 2.0, 2.0, 1.0);
        return out;
    }
    let res = caustics.info.x;
    let texel = vec2u(index % res, (index / res) % res);
    let p = photon.position.xyz;
    // The photon spacing along each axis of the map: the nearer neighbour's distance, so that
    // one neighbour across a discontinuity (another surface, the caster's silhouette) does not
    // blow the quad up (and the frame time with it); the wider axis sizes the quad.
    let spacing = max(
        nearer(neighbour_distance(index, texel, p, -1, 0), neighbour_distance(index, texel, p, 1, 0)),
        nearer(neighbour_distance(index, texel, p, 0, -1), neighbour_distance(index, texel, p, 0, 1)),
    );
    let h = clamp(spacing, caustics.splat.x, caustics.splat.y);
    // Two triangles: corners (−1,−1) (1,−1) (1,1), (−1,−1) (1,1) (−1,1).
    var corners = array<vec2f, 6>(
        vec2f(-1.0, -1.0), vec2f(1.0, -1.0), vec2f(1.0, 1.0),
        vec2f(-1.0, -1.0), vec2f(1.0, 1.0), vec2f(-1.0, 1.0),
    );
    let local = corners[vertex];
    let tb = tangent_frame(photon.normal.xyz);
    let world = p + (tb[0] * local.x + tb[1] * local.y) * h;
    out.clip = frame.clip_from_world * vec4f(world, 1.0);
    out.local = local;
    out.half_size = h;
    return out;
}

struct Targets {
    @location(0) rv: vec4f,
    @location(1) r: vec4f,
}

@fragment
fn fs_main(in: Splat) -> Targets {
    let photon = photons[in.photon];
    let pixel = vec2i(in.clip.xy);
    let tb = tangent_frame(photon.normal.xyz);
    let world = photon.position.xyz + (tb[0] * in.local.x + tb[1] * in.local.y) * in.half_size;
    let surface = world_from_pixel(frame, in.clip.xy, textureLoad(gbuffer_depth_motion, pixel, 0).x);
    let to_camera = distance(surface, frame.camera_position.xyz);
    let n = textureLoad(gbuffer_normal_roughness, pixel, 0).xyz;
    if (distance(world, surface) > caustics.splat.z * to_camera || dot(n, photon.normal.xyz) < 0.5) {
        discard;
    }
    let tent = (1.0 - abs(in.local.x)) * (1.0 - abs(in.local.y));
    let e = vec4f(photon.power.rgb * tent / (in.half_size * in.half_size), 1.0);
    let kind = (in.photon / (caustics.info.x * caustics.info.x)) % PHOTON_KINDS;
    var out: Targets;
    if (kind < 2u) { out.rv = e; } else { out.r = e; }
    return out;
}
