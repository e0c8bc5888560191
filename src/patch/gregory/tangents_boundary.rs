//! Cross-boundary tangent lengths of crease sectors (boundary and infinitely sharp crease
//! vertices, §4.6), fitted to the exact limit as [`super::tangents`] fits smooth vertices.
//!
//! # The free parameter
//!
//! A crease sector of `k` faces between the sharp edges `s` and `t` has the edge points
//! `e_s`, `e_t` of the crease curve (the cubic B-spline's, exact) and inner edge points
//! `e_i = p + cos(iπ/k) (e_s − p) + sin(iπ/k) s(k) T/3` (`GregoryVertex::sectored`), with `T`
//! the cross-boundary tangent ([`super::crease_tangent_weights`], the sine mode of the sector's
//! subdivision matrix scaled like the paper's `λ q`). Any `s(k) > 0` keeps the limit position,
//! the crease curve's tangent, the tangent plane and condition (1) (the inner points stay the
//! affine half `2k`-gon of `cos(π/k)`); only the length of `T` changes. `s(2) = 1` is exact (the
//! boundary bicubic B-spline) and a sector of one face has no inner edge, so the table covers
//! `k = 3..=`[`MAX_FITTED_CREASE_SECTOR`]. The two sectors of a crease vertex refine
//! independently (the crease rules read only the crease curve and the sector's own faces), so a
//! crease vertex with sectors of `k₁` and `k₂` faces uses `s(k₁)` and `s(k₂)`, and a boundary
//! vertex of `k` faces `s(k)`, whatever the boundary interpolation (the modes differ only at a
//! boundary vertex of one face: a corner, or a one-face crease sector, neither with an inner
//! edge).
//!
//! No length is exact at `k ≥ 3`: the cross-boundary mode's eigenvalue `μ` (0.580 at `k = 3`,
//! 0.635 at 6) exceeds the crease curve's 1/2, so the exact inner edge curves leave the vertex
//! along `T` like `t^(−log₂ μ)` with an infinite derivative, and the best cubic length depends
//! on the ring's mix of the two modes: on meshes the fitted factors help some vertices and hurt
//! others (README, issue 10).
//!
//! # The fit ([`GregoryTangents::Optimal`])
//!
//! As for smooth vertices, with the half-ring [`super::tangent_fit::crease_fit_mesh`]: vertex 0 on
//! the mesh boundary with `k` sectors of `4 × 4` quads spanning a half plane (sector `i` between
//! the directions at `πi/k` and `π(i+1)/k`, the crease curve along the x axis), lifted to the
//! three quadratic heights of [`super::tangents`]; the mean squared normal distance of the `k`
//! faces at vertex 0 to the exact limit is a parabola in `s` with its minimum at
//! `s* = −Σ ab / Σ b²` ([`super::tangent_fit::crease_fit_scale`]), tabulated in
//! [`CREASE_SCALE`] by `cargo run --example gregory_tangent_table`. Beyond the table the last
//! entry is used. Like the smooth factors, `Optimal` applies them on rings of quads only.
//!
//! # Bands (the 2-ring key; fitted, taken by `Bands`, not by `Optimal`)
//!
//! Where a sector's inner edges end on crease vertices the half-ring above is far from the
//! mesh: on `xord_boundary` (fans one face deep) and `gregory_test3` the best lengths differ
//! from [`CREASE_SCALE`] and the exact `s(2) = 1` (README, issue 10). [`sector_band`] keys a
//! sector on its 2-ring (`VertexRing::far_sector`: per inner edge, the far end's crease sector):
//! a two-face sector whose inner edge ends inside a crease sector of `k' >= 3` faces has band
//! `k'` (never a face of a regular boundary B-spline patch: both faces hold the far end, which
//! is irregular, so no crack), a sector of `k >= 3` faces whose inner edges all end on crease
//! vertices has band 1. The fit: [`super::tangent_fit::band_fit_mesh`], the half-ring one face
//! deep (the centre's band 1, every two-face vertex's band `k`); the patches are affine in the
//! centre's factor `s_c` and the two-face vertices' `s_2`, so the mean squared normal distance
//! is a quadratic in both, minimised in closed form
//! ([`super::tangent_fit::band_fit_scales`]): [`BAND_CENTRE_SCALE`], [`BAND_TWO_SCALE`]
//! (`s_c(3) = 0.616`, `s_2(3) = 0.945`; `s_c(6) = 0.358`, `s_2(6) = 1.418`). The key is carried
//! through the construction (the rings), the stencils, the `gregory-vs` factor words and the
//! end caps' shared-row keys, and `Scaled(s)` applies `s` on bands, so the fits and
//! experiments run on it. `Optimal` does not read the band tables: with them `gregory_test3`
//! and `xord_boundary` come closer to OpenSubdiv but stay above it, and `xord_boundary`'s RMS
//! normal and `inf_crease0/1`'s RMS distance grow slightly (README). `Bands`
//! (`--gregory-tangents bands`) is `Optimal` with the band tables, for meshes with bands.
//!
//! # One-sided face points (`Optimal`, issue 10)
//!
//! Compared point by point with OpenSubdiv's Gregory basis (README), two of its rules at
//! boundary and crease vertices keep the exact corner plane and are taken by `Optimal`:
//! - beside a sharp edge the face point is the corner's other face point in the same face
//!   (`GregoryVertex::one_sided`, applied in the patch assembly), not eq. 6 with the reflected
//!   ring;
//! - at a vertex alone in its corner sector both face points are eq. 6 with the far corner's
//!   cosine 0 (`e + r/3`, the B-spline corner's `(4v + 2a + 2b + d)/9`).
//!
//! Its third, Biermann et al.'s cross-boundary tangent, is not in the exact tangent plane (an
//! eigenvector of Biermann's modified rules): it gains accuracy by tilting the corner normal
//! (up to 0.14 rad on the corpus), which the exact corner normals tessera keeps rule out.
//!
//! # Corners
//!
//! Corner sectors have no free length: in a sector of two faces the inner edge point is
//! `p + (e_s − p + e_t − p)/√2`, fixed by condition (1) with the sector's `cos(π/4)` and the
//! exact sharp-edge points; one face has no inner edge; wider corner sectors (end caps only)
//! follow the refined chords (`GregoryVertex::sectored`).

use super::tangents::GregoryTangents;
use crate::topology::Topology;

/// The largest crease sector (faces) with a fitted entry in [`CREASE_SCALE`].
pub const MAX_FITTED_CREASE_SECTOR: usize = 16;

/// `s(k)` for crease sectors of `k = 3..=MAX_FITTED_CREASE_SECTOR` faces (index `k − 3`), fitted
/// as the module docs describe by `cargo run --example gregory_tangent_table`.
pub const CREASE_SCALE: [f64; MAX_FITTED_CREASE_SECTOR - 2] = [
    0.831433, 0.685052, 0.595432, 0.536264, 0.494867, 0.466251, 0.445894, 0.430687, 0.419084,
    0.410119, 0.403074, 0.397448, 0.392902, 0.389194,
];

/// `s(k)` of the centre of a band ([`sector_band`] 1): a crease sector of `k =
/// 3..=MAX_FITTED_CREASE_SECTOR` faces (index `k − 3`) with an inner edge ending on a crease
/// vertex, fitted jointly with [`BAND_TWO_SCALE`] on [`super::tangent_fit::band_fit_mesh`] by
/// `cargo run --example gregory_tangent_table`.
pub const BAND_CENTRE_SCALE: [f64; MAX_FITTED_CREASE_SECTOR - 2] = [
    0.615910, 0.471059, 0.409273, 0.358313, 0.312443, 0.279614, 0.255671, 0.237111, 0.222943,
    0.212397, 0.204574, 0.198816, 0.194684, 0.191847,
];

/// `s(2)` of a two-face crease sector whose inner edge ends on the centre of a band, a crease
/// vertex whose sector there has `k = 3..=MAX_FITTED_CREASE_SECTOR` faces (index `k − 3`),
/// fitted with [`BAND_CENTRE_SCALE`].
pub const BAND_TWO_SCALE: [f64; MAX_FITTED_CREASE_SECTOR - 2] = [
    0.945250, 1.126182, 1.302256, 1.417673, 1.460030, 1.469143, 1.460534, 1.443194, 1.423105,
    1.403309, 1.384827, 1.368046, 1.353068, 1.339818,
];

impl GregoryTangents {
    /// Whether face points beside sharp edges are one-sided at a vertex whose faces are all
    /// quads (`quads`) (`GregoryVertex::one_sided`): `Optimal` on quad rings only, where
    /// OpenSubdiv's rules were measured (at boundary vertices with triangles they lose to the
    /// reflected ring, README); the paper's construction and `Scaled`, on which the fit of
    /// [`CREASE_SCALE`] runs, reflect the ring.
    pub fn one_sided_face_points(self, quads: bool) -> bool {
        self.without_bands() == GregoryTangents::Optimal && quads
    }

    /// The factor `s(k)` on the cross-boundary tangent of a crease sector of `k` faces with
    /// 2-ring key `band` ([`sector_band`]) at a vertex whose faces are all quads (`quads`),
    /// rounded to `f32` as [`Self::scale`]: 1 for the paper's construction, for sectors of one
    /// face and for two-face sectors off a band (the boundary bicubic's, exact); `Scaled(s)`
    /// gives `s` to every other sector, two-face sectors on a band included (the fits);
    /// `Optimal` gives [`CREASE_SCALE`] to sectors of three or more faces of quad rings, 1
    /// elsewhere, whatever the band; `Bands` takes [`BAND_TWO_SCALE`] and [`BAND_CENTRE_SCALE`]
    /// on a band of quad rings and `Optimal`'s factors elsewhere ("Bands" in the module docs).
    pub fn crease_scale(self, k: usize, band: usize, quads: bool) -> f64 {
        // The end caps' own factors are at smooth rings only: `EndCaps` is `Optimal` here, and
        // `Fitted` too where a sector has no fitted factor (`Self::sector_scale`).
        let s = match self {
            GregoryTangents::Paper => 1.0,
            _ if k <= 1 || (k == 2 && band == 0) => 1.0,
            GregoryTangents::Scaled(s) => s,
            GregoryTangents::Bands if quads && k == 2 => {
                BAND_TWO_SCALE[band.min(MAX_FITTED_CREASE_SECTOR) - 3]
            }
            GregoryTangents::Bands if quads && band == 1 => {
                BAND_CENTRE_SCALE[k.min(MAX_FITTED_CREASE_SECTOR) - 3]
            }
            GregoryTangents::Optimal
            | GregoryTangents::Bands
            | GregoryTangents::EndCaps
            | GregoryTangents::Fitted
                if !quads || k == 2 =>
            {
                1.0
            }
            GregoryTangents::Optimal
            | GregoryTangents::Bands
            | GregoryTangents::EndCaps
            | GregoryTangents::Fitted => CREASE_SCALE[k.min(MAX_FITTED_CREASE_SECTOR) - 3],
        };
        s as f32 as f64
    }

    /// The factor on the cross-boundary tangent of crease sector number `sector` (in
    /// `super::sectors` order) as [`Self::crease_scale`], but under [`GregoryTangents::Fitted`]
    /// the sector's frozen factor where its vertex's pair `fitted` has one
    /// (`Topology::crease_factors` at `crease_factor_slot`, 0 for none;
    /// [`super::vertex_fit`]). Already an `f32`.
    pub fn sector_scale(
        self,
        k: usize,
        band: usize,
        quads: bool,
        fitted: Option<[f32; 2]>,
        sector: usize,
    ) -> f64 {
        match fitted.map(|f| f[crease_factor_slot(sector)]) {
            Some(s) if self == GregoryTangents::Fitted && s > 0.0 => f64::from(s),
            _ => self.crease_scale(k, band, quads),
        }
    }
}

/// The 2-ring key of a crease sector of `k` faces whose inner edges' far ends have the crease
/// sectors `far` (`VertexRing::far_sector` of the inner edges: 0 where the far end is no crease
/// vertex): for `k = 2`, the far end's sector size when that is 3 or more (0 otherwise: a far
/// sector of two faces makes both faces regular boundary B-spline patches, whose edge curve
/// the inner edge point must stay); for `k >= 3`, 1 when every inner edge ends on a crease
/// vertex (the centre of a band one face wide), else 0.
pub fn sector_band(k: usize, far: impl IntoIterator<Item = usize>) -> usize {
    let mut far = far.into_iter();
    match k {
        0 | 1 => 0,
        2 => far.next().filter(|&f| f >= 3).unwrap_or(0),
        _ => usize::from(far.all(|f| f >= 2)),
    }
}

/// The entry of a vertex's frozen crease-sector pair (`Topology::crease_factors`) that crease
/// sector number `sector` (in `super::sectors` order) reads and [`super::vertex_fit`] writes: a
/// crease vertex has two sectors.
pub(super) fn crease_factor_slot(sector: usize) -> usize {
    sector.min(1)
}

/// The words of vertex `v`'s frozen crease-sector factors ([`Topology::crease_factors`], read
/// under [`GregoryTangents::Fitted`]; 0 where none) in the end caps' shared-row and ring-type
/// keys (`super::shared_rows`, `super::corner_types`): two rings of one connectivity with
/// different factors must not share rows.
pub(super) fn crease_factor_words(topo: &Topology, v: u32) -> [u32; 2] {
    topo.crease_factors(v).unwrap_or_default().map(f32::to_bits)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paper_and_regular_sectors_keep_one() {
        for k in 1..40 {
            for band in [0, 1, 3, 7] {
                assert_eq!(GregoryTangents::Paper.crease_scale(k, band, true), 1.0);
                assert_eq!(GregoryTangents::Optimal.crease_scale(k, band, false), 1.0);
            }
        }
        for t in [GregoryTangents::Optimal, GregoryTangents::Scaled(0.5)] {
            assert_eq!(t.crease_scale(1, 0, true), 1.0);
            assert_eq!(t.crease_scale(2, 0, true), 1.0);
        }
        assert_eq!(GregoryTangents::Scaled(0.5).crease_scale(3, 0, true), 0.5);
        assert_eq!(GregoryTangents::Scaled(0.5).crease_scale(2, 3, true), 0.5);
        // `Optimal` does not take the band tables (module docs).
        assert_eq!(GregoryTangents::Optimal.crease_scale(2, 3, true), 1.0);
        assert_eq!(
            GregoryTangents::Optimal.crease_scale(3, 1, true),
            CREASE_SCALE[0] as f32 as f64
        );
        assert_eq!(
            GregoryTangents::Optimal.crease_scale(99, 0, true),
            CREASE_SCALE[MAX_FITTED_CREASE_SECTOR - 3] as f32 as f64
        );
    }

    #[test]
    fn only_fitted_reads_a_sectors_frozen_factor() {
        let fitted = GregoryTangents::Fitted;
        for (k, band, quads) in [(2, 0, true), (2, 3, true), (3, 0, true), (5, 1, false)] {
            let optimal = GregoryTangents::Optimal.crease_scale(k, band, quads);
            assert_eq!(fitted.crease_scale(k, band, quads), optimal);
            assert_eq!(fitted.sector_scale(k, band, quads, None, 0), optimal);
            assert_eq!(
                fitted.sector_scale(k, band, quads, Some([0.0, 1.5]), 0),
                optimal
            );
            assert_eq!(
                fitted.sector_scale(k, band, quads, Some([1.25, 0.0]), 0),
                1.25
            );
            assert_eq!(
                fitted.sector_scale(k, band, quads, Some([0.0, 1.5]), 1),
                1.5
            );
            for t in [GregoryTangents::Optimal, GregoryTangents::EndCaps] {
                assert_eq!(
                    t.sector_scale(k, band, quads, Some([1.25, 1.25]), 0),
                    optimal
                );
            }
        }
        assert_eq!(fitted.for_end_caps(), GregoryTangents::EndCaps);
        assert!(fitted.one_sided_face_points(true));
    }

    #[test]
    fn bands_take_the_band_tables_on_bands_of_quad_rings_only() {
        let bands = GregoryTangents::Bands;
        let f = |x: f64| x as f32 as f64;
        assert_eq!(bands.crease_scale(2, 3, true), f(BAND_TWO_SCALE[0]));
        assert_eq!(bands.crease_scale(2, 6, true), f(BAND_TWO_SCALE[3]));
        assert_eq!(bands.crease_scale(3, 1, true), f(BAND_CENTRE_SCALE[0]));
        assert_eq!(bands.crease_scale(40, 1, true), f(BAND_CENTRE_SCALE[13]));
        // Off a band, and on rings with other faces, `Optimal`'s factors.
        for (k, band, quads) in [(2, 0, true), (3, 0, true), (5, 0, true), (2, 3, false)] {
            assert_eq!(
                bands.crease_scale(k, band, quads),
                GregoryTangents::Optimal.crease_scale(k, band, quads),
                "k {k} band {band} quads {quads}"
            );
        }
        assert_eq!(bands.crease_scale(3, 1, false), 1.0);
        assert!(bands.one_sided_face_points(true) && !bands.one_sided_face_points(false));
        for n in 3..80 {
            assert_eq!(bands.scale(n), GregoryTangents::Optimal.scale(n));
        }
        assert_eq!("bands".parse::<GregoryTangents>(), Ok(bands));
        assert_eq!(bands.to_string(), "bands");
    }
}
