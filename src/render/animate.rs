//! Animation helpers for `tessera render --animate`: a simple deformation of the control
//! positions (the topology and every table built from it stay; the renderer only receives new
//! positions, [`super::SurfaceRenderer::update_positions`]) and a contact sheet of the frames.

use glam::DVec3;
use image::RgbaImage;

/// Twist about the `up` axis through the centre of the bounding box: a point at height `h`
/// (fraction of the box's extent along `up`, from -0.5 to 0.5) turns by
/// `amplitude * h * sin(2 pi phase)` radians. `phase` runs over [0, 1) for one period.
pub fn twist(positions: &[DVec3], up: DVec3, amplitude: f64, phase: f64) -> Vec<DVec3> {
    let up = up.normalize_or(DVec3::Z);
    let (lo, hi) = positions.iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(a, b), p| (a.min(*p), b.max(*p)),
    );
    if positions.is_empty() {
        return Vec::new();
    }
    let centre = 0.5 * (lo + hi);
    let extent = (hi - lo).dot(up).abs().max(1e-12);
    let swing = amplitude * (std::f64::consts::TAU * phase).sin();
    positions
        .iter()
        .map(|&p| {
            let d = p - centre;
            let h = d.dot(up) / extent;
            let angle = swing * h;
            // Rodrigues rotation of d about `up`.
            let (s, c) = angle.sin_cos();
            centre + d * c + up.cross(d) * s + up * up.dot(d) * (1.0 - c)
        })
        .collect()
}

/// Tiles `frames` (all the same size) row by row into a sheet `cols` frames wide.
pub fn contact_sheet(frames: &[RgbaImage], cols: u32) -> RgbaImage {
    let Some(first) = frames.first() else {
        return RgbaImage::new(1, 1);
    };
    let (w, h) = first.dimensions();
    let cols = cols.clamp(1, frames.len() as u32);
    let rows = (frames.len() as u32).div_ceil(cols);
    let mut sheet = RgbaImage::new(w * cols, h * rows);
    for (k, f) in frames.iter().enumerate() {
        let (x0, y0) = ((k as u32 % cols) * w, (k as u32 / cols) * h);
        for (x, y, px) in f.enumerate_pixels() {
            if x < w && y < h {
                sheet.put_pixel(x0 + x, y0 + y, *px);
            }
        }
    }
    sheet
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn twist_keeps_the_axis_and_heights_and_turns_by_height() {
        let pts = vec![
            DVec3::new(0.0, 0.0, -1.0),
            DVec3::new(1.0, 0.0, 1.0),
            DVec3::new(1.0, 0.0, 0.0),
        ];
        // Box centre (0.5, 0, 0), extent 2 along z; phase 0.25: full swing.
        let out = twist(&pts, DVec3::Z, 1.0, 0.25);
        for (a, b) in pts.iter().zip(&out) {
            assert!((a.z - b.z).abs() < 1e-12, "heights are kept");
        }
        // The point at height +0.5 turns by +0.5 rad about the axis x = 0.5, y = 0.
        let d = out[1] - DVec3::new(0.5, 0.0, 1.0);
        assert!((d.y.atan2(d.x) - 0.5).abs() < 1e-12);
        // The point at mid height does not move; phase 0 leaves everything in place.
        assert!((out[2] - pts[2]).length() < 1e-12);
        let still = twist(&pts, DVec3::Z, 1.0, 0.0);
        assert!(still
            .iter()
            .zip(&pts)
            .all(|(a, b)| (*a - *b).length() < 1e-12));
    }

    #[test]
    fn sheet_layout() {
        let a = RgbaImage::from_pixel(2, 1, image::Rgba([1, 0, 0, 255]));
        let b = RgbaImage::from_pixel(2, 1, image::Rgba([2, 0, 0, 255]));
        let c = RgbaImage::from_pixel(2, 1, image::Rgba([3, 0, 0, 255]));
        let s = contact_sheet(&[a, b, c], 2);
        assert_eq!(s.dimensions(), (4, 2));
        assert_eq!(s.get_pixel(2, 0)[0], 2);
        assert_eq!(s.get_pixel(0, 1)[0], 3);
        assert_eq!(s.get_pixel(3, 1)[0], 0);
    }
}
