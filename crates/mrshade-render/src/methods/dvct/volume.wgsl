// The volumes of delta voxel cone tracing (Franke §2.13): a cube of `res`³ voxels around the
// virtual content. Mirrors `VolumeParams` in volume.rs.

struct VolumeParams {
    // xyz: world position of the volume's lower corner; w: voxel side (m)
    origin: vec4f,
    // voxels per side, mip levels, triangles, VOLUME_* bits
    info: vec4u,
    // diffuse cone aperture (diameter / length), pixels per side of a trace texel (texel.wgsl),
    // the pixels' and the second bounce's cone sample spacing (cones.wgsl)
    cone: vec4f,
}

// Bits of VolumeParams.info.w: the first bounce is the last and takes the probe's light; the
// real voxels the camera sees take the photo's light (photo.wgsl); the scene holds a virtual
// light, whose change reaches beyond this volume (cones.wgsl trace_cone).
const VOLUME_SINGLE_BOUNCE: u32 = 1u;
const VOLUME_PHOTO: u32 = 2u;
const VOLUME_VIRTUAL_LIGHTS: u32 = 4u;

fn voxel_side() -> f32 { return params.origin.w; }
fn volume_side() -> f32 { return params.origin.w * f32(params.info.x); }
fn voxel_index(v: vec3u) -> u32 { return (v.z * params.info.x + v.y) * params.info.x + v.x; }
fn voxel_centre(v: vec3u) -> vec3f { return params.origin.xyz + (vec3f(v) + 0.5) * voxel_side(); }
// From `p` toward the volume's centre, where the virtual content is: the side of a real surface
// that matters faces it (voxelize.wgsl keeps that face, bounce.wgsl gathers on that side).
fn toward_centre(p: vec3f) -> vec3f { return params.origin.xyz + 0.5 * volume_side() - p; }

// A voxel's word in the voxels buffer (voxelize.wgsl): 0 when it holds no surface of its
// kind, else the kept triangle + 1 with VOXEL_FACES_CENTRE set when that triangle faces the
// volume's centre.
const VOXEL_FACES_CENTRE: u32 = 0x80000000u;
fn voxel_triangle(word: u32) -> u32 { return (word & ~VOXEL_FACES_CENTRE) - 1u; }
