//! Synthetic all-regular surfaces built directly as B-spline patches, and their independent
//! CPU evaluation.

use glam::DVec3;
use tessera::patch::RegularPatch;
use tessera::render::SurfaceData;

use super::reference::bspline_with_derivative;

/// Torus with `nu x nv` quads (every vertex valence 4): every face is a regular patch.
/// Vertex (i, j) = i + nu * j; faces counter-clockwise seen from outside.
pub fn torus(nu: u32, nv: u32, big_r: f64, small_r: f64) -> SurfaceData {
    let mut positions = Vec::new();
    for j in 0..nv {
        for i in 0..nu {
            let th = std::f64::consts::TAU * f64::from(i) / f64::from(nu);
            let ph = std::f64::consts::TAU * f64::from(j) / f64::from(nv);
            let rr = big_r + small_r * ph.cos();
            // Slight non-uniform wobble so patches are not all congruent.
            let wob = 1.0 + 0.08 * (3.0 * th).sin();
            positions.push(DVec3::new(
                rr * th.cos() * wob,
                small_r * ph.sin(),
                -rr * th.sin(),
            ));
        }
    }
    let vid = |i: i64, j: i64| -> u32 {
        let (nu, nv) = (i64::from(nu), i64::from(nv));
        (i.rem_euclid(nu) + nu * j.rem_euclid(nv)) as u32
    };
    SurfaceData::from_regular_patches(positions, grid_patches(nu, nv, vid, |_, _| 0))
}

/// Open, curved `nu x nv` quad grid: boundary vertices have valence 3 (corners 2), so every face
/// is a boundary-regular patch with mirrored phantoms. Vertex (i, j) = i + (nu + 1) * j.
pub fn open_grid(nu: u32, nv: u32) -> SurfaceData {
    let mut positions = Vec::new();
    for j in 0..=nv {
        for i in 0..=nu {
            let (x, z) = (
                f64::from(i) - f64::from(nu) * 0.5,
                f64::from(j) - f64::from(nv) * 0.5,
            );
            positions.push(DVec3::new(
                x,
                0.6 * (0.7 * x).sin() * (0.5 * z).cos() + 0.05 * x * z,
                -z,
            ));
        }
    }
    let w = i64::from(nu) + 1;
    let vid = |i: i64, j: i64| -> u32 {
        (i.clamp(0, i64::from(nu)) + w * j.clamp(0, i64::from(nv))) as u32
    };
    let mask = |i: i64, j: i64| {
        u8::from(j == 0)
            | u8::from(i == i64::from(nu) - 1) << 1
            | u8::from(j == i64::from(nv) - 1) << 2
            | u8::from(i == 0) << 3
    };
    SurfaceData::from_regular_patches(positions, grid_patches(nu, nv, vid, mask))
}

/// One patch per face `(i, j)` of an `nu x nv` grid, face id `i + nu * j`: the 4x4 control
/// vertices `vid(i - 1 + a, j - 1 + b)` and the boundary mask `mask(i, j)` (bit 0: v = 0 edge,
/// 1: u = 1, 2: v = 1, 3: u = 0).
fn grid_patches(
    nu: u32,
    nv: u32,
    vid: impl Fn(i64, i64) -> u32,
    mask: impl Fn(i64, i64) -> u8,
) -> Vec<RegularPatch> {
    let mut patches = Vec::new();
    for j in 0..i64::from(nv) {
        for i in 0..i64::from(nu) {
            let mut cvs = [0u32; 16];
            for b in 0..4 {
                for a in 0..4 {
                    cvs[(4 * b + a) as usize] = vid(i - 1 + a, j - 1 + b);
                }
            }
            patches.push(RegularPatch {
                face: (i + i64::from(nu) * j) as u32,
                cvs,
                boundary_mask: mask(i, j),
            });
        }
    }
    patches
}

/// Independent CPU reference: position and unit normal of a patch at (u, v), phantoms mirrored
/// as `RegularPatch::control_points` documents (columns first, then rows).
pub fn eval_patch(p: &RegularPatch, positions: &[DVec3], u: f64, v: f64) -> (DVec3, DVec3) {
    let mut c = [[DVec3::ZERO; 4]; 4];
    for j in 0..4 {
        for i in 0..4 {
            c[j][i] = positions[p.cvs[4 * j + i] as usize];
        }
    }
    let m = p.boundary_mask;
    for row in c.iter_mut() {
        if m & 8 != 0 {
            row[0] = 2.0 * row[1] - row[2];
        }
        if m & 2 != 0 {
            row[3] = 2.0 * row[2] - row[1];
        }
    }
    if m & 1 != 0 {
        c[0] = std::array::from_fn(|i| 2.0 * c[1][i] - c[2][i]);
    }
    if m & 4 != 0 {
        c[3] = std::array::from_fn(|i| 2.0 * c[2][i] - c[1][i]);
    }
    let (bu, dbu) = bspline_with_derivative(u);
    let (bv, dbv) = bspline_with_derivative(v);
    let (mut pos, mut du, mut dv) = (DVec3::ZERO, DVec3::ZERO, DVec3::ZERO);
    for j in 0..4 {
        for i in 0..4 {
            pos += bu[i] * bv[j] * c[j][i];
            du += dbu[i] * bv[j] * c[j][i];
            dv += bu[i] * dbv[j] * c[j][i];
        }
    }
    (pos, du.cross(dv).normalize())
}
