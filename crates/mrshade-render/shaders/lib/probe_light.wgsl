// How sharp a shadow a light split from the probe casts (ibl/lights.rs gives its angular
// radius, its pair's w as f32 bits): 1 up to an angular radius of `sharp_below`, 0 from twice
// that; 1 for every light with `sharp_below` = 0 (every light read from the maps, as virtual
// pixels do; `dlpv.sharp_probe_shadows_deg = 0` means the opposite, and its passes test for it
// before calling this). The passes that shadow such lights through their maps and those that
// leave the rest to a volume weigh them by this and its complement.
fn probe_light_sharpness(radius_bits: u32, sharp_below: f32) -> f32 {
    if (sharp_below <= 0.0) { return 1.0; }
    return saturate(2.0 - bitcast<f32>(radius_bits) / sharp_below);
}
