//! Where the volumes of the delta methods lie (Franke §2.12.7, §2.13.1): a cube centred on
//! the virtual content, a multiple of its largest edge, kept in step with it as it moves.

use glam::Vec3;

/// The cube (lower corner, side) of `extent` × the largest edge of `virtual_box`, centred on
/// it; without virtual content, the scene's box `scene_box` (nothing differs there).
pub fn place(virtual_box: Option<(Vec3, Vec3)>, scene_box: Option<(Vec3, Vec3)>, extent: f32) -> (Vec3, f32) {
    let (lo, hi, scale) = match (virtual_box, scene_box) {
        (Some((lo, hi)), _) => (lo, hi, extent),
        (None, Some((lo, hi))) => (lo, hi, 1.0),
        (None, None) => (Vec3::splat(-1.0), Vec3::splat(1.0), 1.0),
    };
    let side = ((hi - lo).max_element() * scale).max(1e-3);
    ((lo + hi) * 0.5 - Vec3::splat(side * 0.5), side)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_cube_is_twice_the_virtual_box_around_its_centre() {
        let (lo, side) = place(Some((Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 0.5, 0.25))), None, 2.0);
        assert_eq!(side, 2.0);
        assert_eq!(lo, Vec3::new(-0.5, -0.75, -0.875));
        let (lo, side) = place(None, Some((Vec3::ZERO, Vec3::splat(3.0))), 2.0);
        assert_eq!((lo, side), (Vec3::ZERO, 3.0));
    }
}
