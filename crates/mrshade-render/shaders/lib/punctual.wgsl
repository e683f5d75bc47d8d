// Differential direct light of the punctual lights at one surface (Knecht §2.7, Eq. 5.1–5.3):
//   L_rv += L_o · min(V_r, V_v),   L_r += L_o · r(pl) · r(p) · V_r.
// Needs lights.wgsl, shadow.wgsl, brdf.wgsl and the bindings `lights`, `frame`.

struct Radiance {
    rv: vec3f,
    r: vec3f,
}

fn punctual_radiance(s: Surface, r_p: f32) -> Radiance {
    var out = Radiance(vec3f(0.0), vec3f(0.0));
    for (var i = 0u; i < frame.counts.x; i++) {
        let light = lights[i];
        let incident = light_incident(light, s.position);
        let l_o = brdf_cos(s, incident.l) * incident.radiance;
        if (all(l_o == vec3f(0.0))) { continue; }
        let v_r = shadow_visibility(light, light.info.y, s.position, s.normal);
        let v_v = shadow_visibility(light, light.info.w, s.position, s.normal);
        out.rv += l_o * min(v_r, v_v);
        out.r += l_o * light.direction_real.w * r_p * v_r;
    }
    return out;
}
