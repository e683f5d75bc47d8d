//! The memory budget of a scene being loaded (`limits.scene_mib`): every loader says what it
//! is about to allocate, and for what, *before* allocating it.

use anyhow::{Result, bail};
use mrshade_core::settings::Limits;

/// Bytes allowed and bytes promised so far.
#[derive(Clone, Debug)]
pub struct Budget {
    limit: u64,
    used: u64,
    /// Largest decoded image, in pixels (`limits.image_pixels`).
    pub image_pixels: u64,
    /// The setting that raises `image_pixels`, for messages.
    image_setting: &'static str,
}

impl Budget {
    /// The budget of `limits`.
    pub fn new(limits: &Limits) -> Self {
        Self {
            limit: limits.scene_bytes(),
            used: 0,
            image_pixels: limits.image_pixels,
            image_setting: "`limits.image_pixels` (raise it with --set limits.image_pixels=N)",
        }
    }

    /// A budget for images of at most `max_pixels`, raised by `setting` (named in messages).
    pub fn images(max_pixels: u64, setting: &'static str) -> Self {
        Self { image_pixels: max_pixels, image_setting: setting, ..Self::default() }
    }

    /// Promises `count × bytes_each` more bytes for `what`, or says which input asked for too
    /// much and how to allow it. Products that overflow are refused too.
    pub fn charge(&mut self, what: impl std::fmt::Display, count: u64, bytes_each: u64) -> Result<()> {
        let total = count.checked_mul(bytes_each).and_then(|b| b.checked_add(self.used));
        match total {
            Some(total) if total <= self.limit => {
                self.used = total;
                Ok(())
            }
            _ => bail!(
                "{what} needs {} ({count} × {bytes_each} bytes), which takes the scene past \
                 `limits.scene_mib` = {} (raise it with --set limits.scene_mib=N)",
                human_bytes(count.saturating_mul(bytes_each)),
                self.limit >> 20
            ),
        }
    }

    /// Refuses an image of `width × height` pixels above `limits.image_pixels`, from its
    /// header, before it is decoded.
    pub fn check_image(&self, width: u32, height: u32) -> Result<()> {
        let pixels = width as u64 * height as u64;
        if pixels > self.image_pixels {
            bail!(
                "the image is {width}×{height} ({pixels} pixels), more than the {} pixels of {}",
                self.image_pixels,
                self.image_setting
            );
        }
        Ok(())
    }
}

/// `123 bytes`, `4.0 MiB`, `24.0 GiB`.
fn human_bytes(bytes: u64) -> String {
    match bytes {
        b if b < 1 << 20 => format!("{b} bytes"),
        b if b < 1 << 30 => format!("{:.1} MiB", b as f64 / (1u64 << 20) as f64),
        b => format!("{:.1} GiB", b as f64 / (1u64 << 30) as f64),
    }
}

impl Default for Budget {
    fn default() -> Self {
        Self::new(&Limits::default())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn charges_add_up_and_overflow_is_refused() {
        let mut b = Budget::new(&Limits { scene_mib: 1, ..Default::default() });
        b.charge("a", 1024, 512).unwrap();
        b.charge("b", 1024, 512).unwrap();
        let err = b.charge("accessor 3 (POSITION)", 1, 1).unwrap_err().to_string();
        assert!(err.contains("accessor 3 (POSITION)") && err.contains("`limits.scene_mib` = 1"), "{err}");
        assert_eq!(human_bytes(25769803776), "24.0 GiB");
        assert!(Budget::default().charge("x", u64::MAX, 12).is_err());
        assert!(Budget::default().check_image(26000, 19500).unwrap_err().to_string().contains("26000×19500"));
    }
}
