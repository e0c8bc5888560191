//! Image comparison for golden-image tests: a per-pixel tolerance plus a maximum fraction of
//! pixels allowed to exceed it, with a difference image for inspection.

use image::{Rgba, RgbaImage};

use crate::{Error, Result};

/// Pass/fail thresholds of [`compare_images`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CompareThreshold {
    /// A pixel differs when any channel (R, G, B, A, 8-bit) differs by more than this.
    pub channel_tolerance: u8,
    /// The images match when at most this fraction of pixels differ.
    pub max_differing_fraction: f64,
}

impl Default for CompareThreshold {
    fn default() -> Self {
        CompareThreshold {
            channel_tolerance: 24,
            max_differing_fraction: 0.002,
        }
    }
}

/// Result of a comparison.
#[derive(Debug, Clone)]
pub struct CompareReport {
    /// Pixels whose largest channel difference exceeds the tolerance.
    pub differing: usize,
    /// Pixels compared.
    pub total: usize,
    /// Largest channel difference anywhere.
    pub max_channel_diff: u8,
    /// Differing pixels in red over a faded copy of the expected image.
    pub diff_image: RgbaImage,
}

impl CompareReport {
    /// Fraction of differing pixels.
    pub fn differing_fraction(&self) -> f64 {
        self.differing as f64 / self.total.max(1) as f64
    }

    /// Whether the comparison passes `threshold`.
    pub fn passes(&self, threshold: &CompareThreshold) -> bool {
        self.differing_fraction() <= threshold.max_differing_fraction
    }
}

/// Compares `actual` against `expected` pixel by pixel. Errors if the sizes differ.
pub fn compare_images(
    expected: &RgbaImage,
    actual: &RgbaImage,
    threshold: &CompareThreshold,
) -> Result<CompareReport> {
    if expected.dimensions() != actual.dimensions() {
        return Err(Error::Invalid(format!(
            "image sizes differ: expected {:?}, actual {:?}",
            expected.dimensions(),
            actual.dimensions()
        )));
    }
    let (w, h) = expected.dimensions();
    let mut diff_image = RgbaImage::new(w, h);
    let mut differing = 0usize;
    let mut max_channel_diff = 0u8;
    for ((e, a), d) in expected
        .pixels()
        .zip(actual.pixels())
        .zip(diff_image.pixels_mut())
    {
        let m =
            e.0.iter()
                .zip(a.0.iter())
                .map(|(x, y)| x.abs_diff(*y))
                .max()
                .unwrap_or(0);
        max_channel_diff = max_channel_diff.max(m);
        if m > threshold.channel_tolerance {
            differing += 1;
            *d = Rgba([255, 0, 0, 255]);
        } else {
            let grey = ((u32::from(e.0[0]) + u32::from(e.0[1]) + u32::from(e.0[2])) / 12) as u8;
            *d = Rgba([grey, grey, grey, 255]);
        }
    }
    Ok(CompareReport {
        differing,
        total: (w as usize) * (h as usize),
        max_channel_diff,
        diff_image,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_pixels_beyond_tolerance() {
        let a = RgbaImage::from_pixel(10, 10, Rgba([100, 100, 100, 255]));
        let mut b = a.clone();
        b.put_pixel(1, 1, Rgba([100, 140, 100, 255])); // 40 > 24: differs
        b.put_pixel(2, 2, Rgba([110, 100, 100, 255])); // 10: within tolerance
        let th = CompareThreshold::default();
        let r = compare_images(&a, &b, &th).unwrap();
        assert_eq!(r.differing, 1);
        assert_eq!(r.max_channel_diff, 40);
        assert_eq!(r.diff_image.get_pixel(1, 1), &Rgba([255, 0, 0, 255]));
        // 1 of 100 pixels = 1% > 0.2%.
        assert!(!r.passes(&th));
        assert!(r.passes(&CompareThreshold {
            channel_tolerance: 24,
            max_differing_fraction: 0.01
        }));
        assert!(compare_images(&a, &RgbaImage::new(3, 3), &th).is_err());
    }
}
