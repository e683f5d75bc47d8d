// One level of a solution's anisotropic chains (Franke §2.13.2 step 3, with the anisotropic
// voxels of [CNS+11] §4). The thesis's hardware mipmaps (one mean) make a wall one voxel thick
// half as opaque at every level, so that a wide cone sees through it: the cornell walls let
// the probe in and a quarter of their bounce out, and a virtual block in front of a wall took
// probe light the wall had already stopped (its contact shadow three times too dark). Here
// each direction a cone can travel along an axis has its chain (six, as [CNS+11]; both ways
// of an axis side by side in one texture, towards + in the first half along x, Volume::chains):
// it composites each parent's children front to back as that cone meets them and averages the
// four columns. A surface crossing the parent stays opaque seen along its normal, half as
// opaque seen edge-on, radiance keeps its ratio to opacity (premultiplied), and a cone sees
// the face of a block that faces it. Three chains whose front child was the one nearer the
// volume's centre showed the cones that travel towards the centre (from the real surfaces
// around the virtual object, towards it) the far faces first: in front of a dim face of a
// block, the lit faces behind it. The first level reads the voxels themselves for all six.

@group(0) @binding(0) var finer_x: texture_3d<f32>;
@group(0) @binding(1) var finer_y: texture_3d<f32>;
@group(0) @binding(2) var finer_z: texture_3d<f32>;
@group(0) @binding(3) var out_x: texture_storage_3d<rgba16float, write>;
@group(0) @binding(4) var out_y: texture_storage_3d<rgba16float, write>;
@group(0) @binding(5) var out_z: texture_storage_3d<rgba16float, write>;
// The voxels' normals (VoxelNormals), for the first level.
@group(0) @binding(6) var normals: texture_3d<f32>;

// Front-to-back "over" of premultiplied samples.
fn over(front: vec4f, back: vec4f) -> vec4f { return front + (1.0 - front.a) * back; }

// The parent of the eight children of `finer` from `first` seen by a cone travelling along
// `axis`, towards + unless `towards_low` (its front child then the one with the higher
// coordinate): its four columns along the axis composited front to back, averaged. Child k
// sits at (k & 1, (k >> 1) & 1, k >> 2); along axis a, the columns' pairs differ in bit a.
// Written out, the eight reads first: with the children in an array filled and indexed in
// loops, the reads waited on one another.
fn parent(finer: texture_3d<f32>, first: vec3u, axis: u32, towards_low: bool) -> vec4f {
    let c = children(finer, first);
    let t = towards_low;
    var sum: vec4f;
    switch axis {
        case 0u: { sum = pair(c.c0, c.c1, t) + pair(c.c2, c.c3, t) + pair(c.c4, c.c5, t) + pair(c.c6, c.c7, t); }
        case 1u: { sum = pair(c.c0, c.c2, t) + pair(c.c1, c.c3, t) + pair(c.c4, c.c6, t) + pair(c.c5, c.c7, t); }
        default: { sum = pair(c.c0, c.c4, t) + pair(c.c1, c.c5, t) + pair(c.c2, c.c6, t) + pair(c.c3, c.c7, t); }
    }
    return sum * 0.25;
}

// A column of two children along the cone's axis, composited as the cone meets them.
fn pair(low: vec4f, high: vec4f, towards_low: bool) -> vec4f {
    return select(over(low, high), over(high, low), towards_low);
}

// The texel of child k of a parent, `first` the one with the lowest coordinates.
fn child(first: vec3u, k: u32) -> vec3u { return first + vec3u(k & 1u, (k >> 1u) & 1u, k >> 2u); }

// The eight children of a parent in `finer`, child k in ck, all read before any is used.
struct Children {
    c0: vec4f,
    c1: vec4f,
    c2: vec4f,
    c3: vec4f,
    c4: vec4f,
    c5: vec4f,
    c6: vec4f,
    c7: vec4f,
}

fn children(finer: texture_3d<f32>, first: vec3u) -> Children {
    return Children(
        textureLoad(finer, child(first, 0u), 0),
        textureLoad(finer, child(first, 1u), 0),
        textureLoad(finer, child(first, 2u), 0),
        textureLoad(finer, child(first, 3u), 0),
        textureLoad(finer, child(first, 4u), 0),
        textureLoad(finer, child(first, 5u), 0),
        textureLoad(finer, child(first, 6u), 0),
        textureLoad(finer, child(first, 7u), 0),
    );
}

// The parent an invocation writes: where it lies in the volume at its level, and the way its
// cones travel (texels in the second half along x: towards −).
struct Cell {
    id: vec3u,
    towards_low: bool,
}

fn cell(texel: vec3u) -> Cell {
    let side = textureDimensions(out_y).y;
    let towards_low = texel.x >= side;
    return Cell(vec3u(texel.x - select(0u, side, towards_low), texel.yz), towards_low);
}

@compute @workgroup_size(4, 4, 4)
fn cs_main(@builtin(global_invocation_id) texel: vec3u) {
    if (any(texel >= textureDimensions(out_x))) { return; }
    let c = cell(texel);
    // The finer level holds its two ways at the same offset: twice the side.
    let first = vec3u(2u * c.id.x + select(0u, 2u * textureDimensions(out_y).y, c.towards_low), 2u * c.id.yz);
    textureStore(out_x, texel, parent(finer_x, first, 0u, c.towards_low));
    textureStore(out_y, texel, parent(finer_y, first, 1u, c.towards_low));
    textureStore(out_z, texel, parent(finer_z, first, 2u, c.towards_low));
}

// How much of a surface's light a cone travelling along unit `e` sees, the surface sending it
// out on the side of `n` (`n_e` = n·e): all of it from that side and edge-on, none from
// behind (through the surface), between them a ramp. Isotropic voxels showed a cone from below the lit top
// of a block, and from in front of a dim face the lit faces behind it, at every coarse level
// where one voxel holds both: the floor in front of a block's unlit face took 2.5 times the
// light it sends there (a white cube beside a point light; cones of the base voxels alone
// agree within 10 %). An empty voxel (n = 0) keeps what it has (nothing).
fn facing(n_e: f32) -> f32 { return clamp(1.0 - 2.0 * n_e, 0.0, 1.0); }

// Of two voxels of a column along the cone's axis (premultiplied, with the component of
// their normals along the cone's way, n·e), the parent's share the cone sees: each voxel's
// light as seen from the cone's side, composited front to back.
fn column(low: vec4f, low_n: f32, high: vec4f, high_n: f32, towards_low: bool) -> vec4f {
    return pair(vec4f(low.rgb * facing(low_n), low.a), vec4f(high.rgb * facing(high_n), high.a), towards_low);
}

// The first level, from the voxels (bound as all three finer levels): each voxel and its
// normal read once for the three chains of a way. Written out without arrays: with the eight
// voxels, their normals and the three chains' copies as arrays (passed to functions, indexed
// in loops) this pass took 1.1 ms more than the three chains' means of one way had, at 128³
// on an H200, and 8 ms at 256³ (r21: most of the moving frame's 5.4 ms), where the voxels
// themselves are 16 reads per parent.
@compute @workgroup_size(4, 4, 4)
fn cs_base(@builtin(global_invocation_id) texel: vec3u) {
    if (any(texel >= textureDimensions(out_x))) { return; }
    let c = cell(texel);
    let first = 2u * c.id;
    let t = c.towards_low;
    // Each child, and its normal's components along the way.
    let v = children(finer_x, first);
    let m = children(normals, first);
    let way = select(1.0, -1.0, t);
    let n0 = way * m.c0.xyz;
    let n1 = way * m.c1.xyz;
    let n2 = way * m.c2.xyz;
    let n3 = way * m.c3.xyz;
    let n4 = way * m.c4.xyz;
    let n5 = way * m.c5.xyz;
    let n6 = way * m.c6.xyz;
    let n7 = way * m.c7.xyz;
    // The four columns along each axis, in the order `parent` sums them.
    let x = column(v.c0, n0.x, v.c1, n1.x, t) + column(v.c2, n2.x, v.c3, n3.x, t) + column(v.c4, n4.x, v.c5, n5.x, t)
        + column(v.c6, n6.x, v.c7, n7.x, t);
    let y = column(v.c0, n0.y, v.c2, n2.y, t) + column(v.c1, n1.y, v.c3, n3.y, t) + column(v.c4, n4.y, v.c6, n6.y, t)
        + column(v.c5, n5.y, v.c7, n7.y, t);
    let z = column(v.c0, n0.z, v.c4, n4.z, t) + column(v.c1, n1.z, v.c5, n5.z, t) + column(v.c2, n2.z, v.c6, n6.z, t)
        + column(v.c3, n3.z, v.c7, n7.z, t);
    textureStore(out_x, texel, x * 0.25);
    textureStore(out_y, texel, y * 0.25);
    textureStore(out_z, texel, z * 0.25);
}
