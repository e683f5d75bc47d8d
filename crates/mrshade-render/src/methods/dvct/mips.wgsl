// One level of a solution's anisotropic chains (Franke §2.13.2 step 3, with the anisotropic
// voxels of [CNS+11] §4). The thesis's hardware mipmaps (one mean) make a wall one voxel thick
// half as opaque at every level, so that a wide cone sees through it: the cornell walls let
// the probe in and a quarter of their bounce out, and a virtual block in front of a wall took
// probe light the wall had already stopped (its contact shadow three times too dark). Here
// the chain of axis a composites each parent's children front to back along a and averages
// the four columns: a surface crossing the parent stays opaque seen along its normal, half as
// opaque seen edge-on, and radiance keeps its ratio to opacity (premultiplied). The front child
// is the one nearer the volume's centre, where the virtual content and the cones that matter
// start: a wall two voxels thick shows its lit inner face to them (both orders averaged showed
// half its bounce: the dark outer face's voxel counted as much). The first level reads the
// voxels themselves for all three axes.

@group(0) @binding(0) var finer_x: texture_3d<f32>;
@group(0) @binding(1) var finer_y: texture_3d<f32>;
@group(0) @binding(2) var finer_z: texture_3d<f32>;
@group(0) @binding(3) var out_x: texture_storage_3d<rgba16float, write>;
@group(0) @binding(4) var out_y: texture_storage_3d<rgba16float, write>;
@group(0) @binding(5) var out_z: texture_storage_3d<rgba16float, write>;

// Front-to-back "over" of premultiplied samples.
fn over(front: vec4f, back: vec4f) -> vec4f { return front + (1.0 - front.a) * back; }

// The parent of `children` seen along `axis`, from the side of the volume's centre (the
// virtual content's): its front child is the one nearer the centre, `nearer_high` when that is
// the child with the higher coordinate. Child k sits at (k & 1, (k >> 1) & 1, k >> 2); along
// axis a, pairs differ in bit a.
fn parent(children: array<vec4f, 8>, axis: u32, nearer_high: bool) -> vec4f {
    let bit = 1u << axis;
    var sum = vec4f(0.0);
    for (var k = 0u; k < 8u; k++) {
        if ((k & bit) != 0u) { continue; }
        let low = children[k];
        let high = children[k | bit];
        sum += select(over(low, high), over(high, low), nearer_high);
    }
    return sum * 0.25;
}

fn children_of(finer: texture_3d<f32>, id: vec3u) -> array<vec4f, 8> {
    var c: array<vec4f, 8>;
    for (var k = 0u; k < 8u; k++) {
        c[k] = textureLoad(finer, id * 2u + vec3u(k & 1u, (k >> 1u) & 1u, k >> 2u), 0);
    }
    return c;
}

// Writes the parent at `id` of each chain from its children along that chain.
fn store_parents(id: vec3u, x: array<vec4f, 8>, y: array<vec4f, 8>, z: array<vec4f, 8>) {
    // Parents in the lower half of an axis have the centre on their high side.
    let nearer_high = 2u * id < textureDimensions(out_x);
    textureStore(out_x, id, parent(x, 0u, nearer_high.x));
    textureStore(out_y, id, parent(y, 1u, nearer_high.y));
    textureStore(out_z, id, parent(z, 2u, nearer_high.z));
}

@compute @workgroup_size(4, 4, 4)
fn cs_main(@builtin(global_invocation_id) id: vec3u) {
    if (any(id >= textureDimensions(out_x))) { return; }
    store_parents(id, children_of(finer_x, id), children_of(finer_y, id), children_of(finer_z, id));
}

// The first level, from the voxels (bound as all three finer levels): each voxel read once for
// the three chains (0.02 ms of 0.28 for a bounce's mipmaps of cornell's two volumes on an H200:
// most of their time is the small levels' dispatches, not their texels).
@compute @workgroup_size(4, 4, 4)
fn cs_base(@builtin(global_invocation_id) id: vec3u) {
    if (any(id >= textureDimensions(out_x))) { return; }
    let children = children_of(finer_x, id);
    store_parents(id, children, children, children);
}
