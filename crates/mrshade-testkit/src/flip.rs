//! FLIP between 8-bit sRGB images (LDR FLIP, default viewing conditions), as the mean FLIP
//! error. (The benchmark's score.py averages FLIP's magma heat map instead: see
//! `mrshade_eval::metrics`.)

/// Mean FLIP error of `test` against `reference` (both RGB8, `width × height`).
pub fn mean(reference: &[u8], test: &[u8], width: u32, height: u32) -> f32 {
    assert_eq!(reference.len(), test.len(), "image sizes differ");
    let r = nv_flip::FlipImageRgb8::with_data(width, height, reference);
    let t = nv_flip::FlipImageRgb8::with_data(width, height, test);
    let err = nv_flip::flip(r, t, nv_flip::DEFAULT_PIXELS_PER_DEGREE);
    let pool = nv_flip::FlipPool::from_image(&err);
    pool.mean()
}

/// The FLIP error of every pixel (row-major).
pub fn per_pixel(reference: &[u8], test: &[u8], width: u32, height: u32) -> Vec<f32> {
    assert_eq!(reference.len(), test.len(), "image sizes differ");
    let r = nv_flip::FlipImageRgb8::with_data(width, height, reference);
    let t = nv_flip::FlipImageRgb8::with_data(width, height, test);
    nv_flip::flip(r, t, nv_flip::DEFAULT_PIXELS_PER_DEGREE).to_vec()
}

/// The FLIP error map as a magma heat map (RGB8), for failure reports.
pub fn heatmap(reference: &[u8], test: &[u8], width: u32, height: u32) -> Vec<u8> {
    let r = nv_flip::FlipImageRgb8::with_data(width, height, reference);
    let t = nv_flip::FlipImageRgb8::with_data(width, height, test);
    nv_flip::flip(r, t, nv_flip::DEFAULT_PIXELS_PER_DEGREE).apply_color_lut(&nv_flip::magma_lut()).to_vec()
}
