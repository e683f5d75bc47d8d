//! The "changed region" of a benchmark scene, defined as in the benchmark's CALIBRATION.md so
//! that region scores mean the same there and here: where the answer visibly differs from the
//! photo (mean absolute difference of 8-bit sRGB values, box-filtered over 7×7 pixels, above
//! 3/255), dilated by 2 pixels.

/// Half-width of the box filter (7×7).
const BOX_RADIUS: i64 = 3;
/// Threshold on the filtered mean absolute difference, in 8-bit steps.
const THRESHOLD: f64 = 3.0;
/// Dilation of the mask (pixels; a diamond: two steps of the 4-neighbourhood, as score.py).
const DILATE: i64 = 2;

/// The mask (row-major, `width × height`) where `answer` differs from `photo` (both RGB8).
pub fn changed_region(answer: &[u8], photo: &[u8], width: u32, height: u32) -> Vec<bool> {
    let (w, h) = (width as i64, height as i64);
    assert_eq!(answer.len(), (w * h * 3) as usize, "answer has another size");
    assert_eq!(photo.len(), answer.len(), "photo has another size");
    // Per-pixel mean over channels of |answer − photo|.
    let diff: Vec<f64> = answer
        .chunks_exact(3)
        .zip(photo.chunks_exact(3))
        .map(|(a, p)| a.iter().zip(p).map(|(x, y)| (*x as f64 - *y as f64).abs()).sum::<f64>() / 3.0)
        .collect();
    // Box filter with edge clamping (the filter window is always 7×7 samples).
    let at = |x: i64, y: i64| diff[(y.clamp(0, h - 1) * w + x.clamp(0, w - 1)) as usize];
    let area = ((2 * BOX_RADIUS + 1) * (2 * BOX_RADIUS + 1)) as f64;
    let mut changed = vec![false; diff.len()];
    for y in 0..h {
        for x in 0..w {
            let mut sum = 0.0;
            for dy in -BOX_RADIUS..=BOX_RADIUS {
                for dx in -BOX_RADIUS..=BOX_RADIUS {
                    sum += at(x + dx, y + dy);
                }
            }
            changed[(y * w + x) as usize] = sum / area > THRESHOLD;
        }
    }
    let mut dilated = vec![false; diff.len()];
    for y in 0..h {
        for x in 0..w {
            // score.py dilates twice by the 4-neighbourhood: a diamond, |dx| + |dy| ≤ 2.
            let hit = (-DILATE..=DILATE).any(|dy| {
                (-DILATE..=DILATE).any(|dx| {
                    let (qx, qy) = (x + dx, y + dy);
                    dx.abs() + dy.abs() <= DILATE
                        && (0..w).contains(&qx)
                        && (0..h).contains(&qy)
                        && changed[(qy * w + qx) as usize]
                })
            });
            dilated[(y * w + x) as usize] = hit;
        }
    }
    dilated
}

/// Mean of `values` where `mask` is set (0 where the mask is empty).
pub fn masked_mean(values: &[f32], mask: &[bool]) -> f32 {
    assert_eq!(values.len(), mask.len(), "mask has another size");
    let (sum, count) =
        values.iter().zip(mask).filter(|(_, m)| **m).fold((0.0f64, 0usize), |(s, c), (v, _)| (s + *v as f64, c + 1));
    if count == 0 { 0.0 } else { (sum / count as f64) as f32 }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_changed_square_gives_its_filtered_and_dilated_mask() {
        // 20×20 grey photo; the answer differs by 60 steps on a 3×3 square at (8..11, 8..11).
        let (w, h) = (20u32, 20u32);
        let photo = vec![100u8; (w * h * 3) as usize];
        let mut answer = photo.clone();
        for y in 8..11 {
            for x in 8..11 {
                let i = ((y * w + x) * 3) as usize;
                answer[i..i + 3].copy_from_slice(&[160, 160, 160]);
            }
        }
        let mask = changed_region(&answer, &photo, w, h);
        // The 7×7 mean is 60·n/49 with n changed pixels in the window: above 3 from n ≥ 3,
        // i.e. a window that overlaps the square by at least a 1×3 strip: centres within 3
        // pixels of it (x in 5..14), then 2 more by the dilation (x in 3..16).
        let at = |x: u32, y: u32| mask[(y * w + x) as usize];
        assert!(at(9, 9) && at(3, 9) && at(15, 9) && at(9, 3) && at(9, 15));
        assert!(!at(2, 9) && !at(16, 9) && !at(9, 2) && !at(9, 16));
        // Corners: a window overlapping the square by one pixel (n = 1) stays below, and the
        // dilation is a diamond: (6, 6) is changed (a 2×2 overlap), (5, 5) is 2 steps from
        // it, (4, 4) is 4 steps from every changed pixel.
        assert!(!at(2, 2) && at(5, 5) && !at(4, 4));
        assert_eq!(masked_mean(&[1.0, 2.0, 3.0], &[true, false, true]), 2.0);
        assert_eq!(masked_mean(&[1.0], &[false]), 0.0);
    }

    #[test]
    fn identical_images_have_an_empty_region() {
        let img = vec![7u8; 5 * 4 * 3];
        assert!(changed_region(&img, &img, 5, 4).iter().all(|m| !m));
    }
}
