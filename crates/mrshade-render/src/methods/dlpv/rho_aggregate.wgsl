// `aggregate` of V_ρ gathered from VPLs (rho_vpl.wgsl): one workgroup per block of a pair of
// maps.

@group(0) @binding(0) var<uniform> params: DlpvParams;
@group(0) @binding(1) var<storage, read> rsm: array<RsmTexel>;
@group(0) @binding(2) var<storage, read> pairs: array<vec4u>;
@group(0) @binding(3) var<storage, read> lights: array<Light>;
@group(0) @binding(4) var<storage, read_write> vpls: array<GatherVpl>;
// The maps' side, pairs, this set's first VPL, texels per block side.
@group(0) @binding(5) var<uniform> rho_info: vec4u;

const AGGREGATE_THREADS: u32 = 64u;
var<workgroup> partial_flux: array<vec4f, 64>;
var<workgroup> partial_position: array<vec4f, 64>;
var<workgroup> partial_normal: array<vec4f, 64>;

fn light_depth(light: Light, p: vec3f) -> f32 {
    if (light.info.x == LIGHT_DIRECTIONAL) { return dot(p, light.direction_real.xyz); }
    return distance(p, light.position.xyz);
}

@compute @workgroup_size(8, 8)
fn aggregate(@builtin(workgroup_id) block: vec3u, @builtin(local_invocation_id) local: vec3u,
             @builtin(local_invocation_index) thread: u32) {
    let res = rho_info.x;
    let side = rho_info.w;
    let pair = pairs[block.z];
    let light = lights[pair.z];
    var flux = vec4f(0.0);
    var position = vec4f(0.0);
    var normal = vec4f(0.0);
    let per_thread = side / 8u;
    for (var j = 0u; j < per_thread; j++) {
        for (var i = 0u; i < per_thread; i++) {
            let x = block.x * side + local.x + 8u * i;
            let y = block.y * side + local.y + 8u * j;
            let real = rsm[(pair.x * res + y) * res + x];
            let virt = rsm[(pair.y * res + y) * res + x];
            if (real.position.w < 0.5) { continue; }
            if (virt.position.w > 0.5 && light_depth(light, virt.position.xyz) < light_depth(light, real.position.xyz)) {
                continue;
            }
            let reflected = real.power.rgb * real.albedo.rgb * (1.0 - real.albedo.w);
            let w = dot(reflected, vec3f(0.2126, 0.7152, 0.0722)) + 1e-20;
            flux += vec4f(reflected, real.material.w);
            position += vec4f(real.position.xyz * w, w);
            normal += vec4f(real.normal.xyz * w, 0.0);
        }
    }
    partial_flux[thread] = flux;
    partial_position[thread] = position;
    partial_normal[thread] = normal;
    workgroupBarrier();
    for (var stride = AGGREGATE_THREADS / 2u; stride > 0u; stride = stride / 2u) {
        if (thread < stride) {
            partial_flux[thread] += partial_flux[thread + stride];
            partial_position[thread] += partial_position[thread + stride];
            partial_normal[thread] += partial_normal[thread + stride];
        }
        workgroupBarrier();
    }
    if (thread == 0u) {
        let blocks = res / side;
        let f = partial_flux[0];
        let p = partial_position[0];
        let n = partial_normal[0].xyz;
        var out: GatherVpl;
        out.position = vec4f(select(vec3f(0.0), p.xyz / p.w, p.w > 0.0), f.w);
        out.normal = vec4f(select(vec3f(0.0, 0.0, 1.0), normalize(n), dot(n, n) > 0.0), 0.0);
        out.flux = vec4f(f.rgb, 0.0);
        vpls[rho_info.z + (block.z * blocks + block.y) * blocks + block.x] = out;
    }
}
