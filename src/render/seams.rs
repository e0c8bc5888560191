//! Seams between patches read from a measured TES capture: where two captured points lie within
//! a tolerance of each other (a shared edge or corner emitted by both sides, or by two
//! sub-patches), are they the same bits (watertight), and where the exact surface is smooth
//! there, how far apart are the two sides' normals (tangent-plane continuity of the scheme).

use std::collections::HashMap;

use glam::DVec3;

use super::accuracy::MeasuredPoint;
use crate::patch::gregory::accuracy::normal_angle;

/// Exact normals of two sides closer than this (radians) mark a smooth place of the limit
/// surface; farther apart, a crease or a corner the scheme may reproduce as one.
pub const SMOOTH_ANGLE: f64 = 1e-4;

/// What [`SeamReport::new`] found.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct SeamReport {
    /// Pairs of distinct captured points closer than the tolerance.
    pub pairs: usize,
    /// Of which the positions differ in at least one bit (a crack or a T-junction gap).
    pub cracked: usize,
    /// Largest distance between the points of a cracked pair (model units).
    pub max_gap: f64,
    /// Pairs where the exact surface is smooth ([`SMOOTH_ANGLE`]).
    pub smooth_pairs: usize,
    /// Largest angle between the captured normals of a smooth pair (radians): 0 for a scheme
    /// whose sides share normals bitwise, the scheme's G1 defect otherwise.
    pub max_normal_jump: f64,
}

impl SeamReport {
    /// Pairs up `points` closer than `tolerance` (model units; e.g. 1e-6 of the bbox diagonal),
    /// records equal in every field counting once.
    pub fn new(points: &[MeasuredPoint], tolerance: f64) -> SeamReport {
        let cell = |p: DVec3| (p / tolerance.max(f64::MIN_POSITIVE)).floor().as_ivec3();
        let position = |m: &MeasuredPoint| DVec3::from(m.record.position.map(f64::from));
        let mut grid: HashMap<glam::IVec3, Vec<usize>> = HashMap::new();
        for (i, m) in points.iter().enumerate() {
            grid.entry(cell(position(m))).or_default().push(i);
        }
        let mut report = SeamReport::default();
        for (i, a) in points.iter().enumerate() {
            let (pa, c) = (position(a), cell(position(a)));
            for d in neighbour_offsets() {
                for &j in grid.get(&(c + d)).into_iter().flatten() {
                    let b = &points[j];
                    if j <= i || a.record == b.record || (position(b) - pa).length() > tolerance {
                        continue;
                    }
                    report.add(a, b);
                }
            }
        }
        report
    }

    /// Whether no pair cracked.
    pub fn watertight(&self) -> bool {
        self.cracked == 0
    }

    fn add(&mut self, a: &MeasuredPoint, b: &MeasuredPoint) {
        self.pairs += 1;
        let bits = |m: &MeasuredPoint| m.record.position.map(f32::to_bits);
        if bits(a) != bits(b) {
            self.cracked += 1;
            let gap = DVec3::from(a.record.position.map(f64::from))
                .distance(DVec3::from(b.record.position.map(f64::from)));
            self.max_gap = self.max_gap.max(gap);
        }
        if normal_angle(a.exact_normal, b.exact_normal) < SMOOTH_ANGLE {
            self.smooth_pairs += 1;
            let n = |m: &MeasuredPoint| DVec3::from(m.record.normal.map(f64::from));
            self.max_normal_jump = self.max_normal_jump.max(normal_angle(n(a), n(b)));
        }
    }
}

/// The 27 cells around and including a cell.
fn neighbour_offsets() -> impl Iterator<Item = glam::IVec3> {
    (-1..=1)
        .flat_map(|z| (-1..=1).flat_map(move |y| (-1..=1).map(move |x| glam::IVec3::new(x, y, z))))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::CaptureRecord;

    fn point(face: u32, u: f32, position: [f32; 3], normal: [f32; 3]) -> MeasuredPoint {
        MeasuredPoint {
            record: CaptureRecord {
                face,
                u,
                v: 0.0,
                position,
                normal,
                sub_face: None,
                patch: None,
                texcoord: [0.0; 2],
            },
            distance: 0.0,
            uv_error: None,
            normal_angle: 0.0,
            exact_normal: DVec3::Z,
        }
    }

    #[test]
    fn equal_bits_are_watertight_and_near_misses_crack() {
        let up = [0.0, 0.0, 1.0];
        let tilted = [0.0, 0.6, 0.8];
        let x = 1.0f32;
        let next = f32::from_bits(x.to_bits() + 1);
        let points = [
            point(0, 1.0, [x, 0.0, 0.0], up),
            point(1, 0.0, [x, 0.0, 0.0], tilted),
            point(2, 0.0, [next, 0.0, 0.0], up),
            point(3, 0.5, [5.0, 0.0, 0.0], up),
        ];
        let r = SeamReport::new(&points, 1e-3);
        // 0-1 equal bits, 0-2 and 1-2 one ulp apart; 3 alone.
        assert_eq!((r.pairs, r.cracked), (3, 2));
        assert!(!r.watertight());
        assert_eq!(r.max_gap, f64::from(next - x));
        assert_eq!(r.smooth_pairs, 3);
        assert!((r.max_normal_jump - 0.6f64.asin()).abs() < 1e-6);
        let r = SeamReport::new(&points[..2], 1e-3);
        assert!(r.watertight() && r.pairs == 1);
    }
}
