// The camera G-buffer's surface at internal pixel `pixel`: its world position from the stored
// depth, seen from the camera, with its material texels (gbuffer_surface). Bindings are
// declared by the including pass: frame, gbuffer_depth_motion, gbuffer_albedo_metallic,
// gbuffer_normal_roughness, gbuffer_specular.

fn pixel_surface(pixel: vec2i) -> Surface {
    let p = world_from_pixel(frame, vec2f(pixel) + 0.5, textureLoad(gbuffer_depth_motion, pixel, 0).x);
    return gbuffer_surface(
        p,
        frame.camera_position.xyz,
        textureLoad(gbuffer_albedo_metallic, pixel, 0),
        textureLoad(gbuffer_normal_roughness, pixel, 0),
        textureLoad(gbuffer_specular, pixel, 0),
    );
}
