//! The whole CPU preprocessing of the adaptive scheme (`AdaptiveTables::new`: the refinement with
//! its levels, census inputs and steps, the kernels' subdivision tables, and the draw tables —
//! slots, frame and end-cap rows with their f64 and f32 weights, records, patches, fans, coarse
//! edges) is bitwise what it was before the preprocessing was made faster (issue 8): each part's
//! `Debug` text (which prints every float in its shortest round-trip form, so equal text is
//! equal bits) hashed with FNV-1a, against the fingerprints the code before the speed-up
//! produced (computed by this test on that code: first commit 23a28a3; re-taken on main at
//! ceab382 after its end-cap sharpness change, which changes end caps' rows and the topology's
//! `Debug` text, was merged; the car's draw tables re-taken on main before the speed-up merge,
//! after the fitted crease-sector tangents changed its end caps' rows). The draw tables' were
//! re-taken when the end caps' rows became two-stage (issue 8, per-vertex row part): each smooth
//! end-cap corner's limit point and two tangent sums are vertex points computed once (rows
//! after the end caps'), the end-cap and frame rows read them instead of the vertex's ring, and
//! the smooth edge points are `p + cos q_c + sin q_s` of those sums (the paper's per-edge sums
//! regrouped). The refinement and kernels' fingerprints did not change; the CPU
//! `AdaptiveSurface` of these meshes (25 points per patch) moved by at most 4.3e-16 of the bbox
//! diagonal, unit normals by at most 1.3e-11 (rounding of the regrouped sums). They were
//! re-taken again for the normals on promoted creases (issue 8): end caps on an edge the end caps
//! keep infinitely sharp (residual sharpness >= 1) no longer flag it as a crease, and a frame at a
//! vertex on one takes the exact limit tangents; only the draw tables of the meshes with such
//! edges changed (car, cube_creases1, cubes_semisharp, single_crease). The draw tables' were
//! re-taken for the fillets of promoted creases (issue 8, session 10): `PatchRecord` has a new
//! field (`fillet`, word 11, once an unused 0: the residual sharpness of a promoted edge, or of
//! the crease at the ends of the other edges between end caps) and the end caps' draw flags bit
//! 28 + k marks promoted edges; the records' `Debug` text has the new field, so every case's
//! draw tables changed; the refinement and kernels' fingerprints did not. And again for
//! OpenSubdiv's face points under `optimal` at crease and corner vertices of quad rings (issue 10:
//! beside a sharp edge the other face point, alone in a corner sector the B-spline corner's):
//! only the draw tables of the meshes whose end caps touch such sectors (real or promoted
//! creases) changed. And again when the first stage was extended to darts and crease sectors
//! (issue 8: a dart's limit point and two tangent masks, the cross-boundary tangent of a crease
//! sector of three or more faces are vertex points; a dart's edge points `p + a t_1 + b t_2` of
//! them, the projection regrouped): only the car's draw tables changed (the other meshes' end
//! caps have no dart and no crease sector that large); its rows evaluated on the refined points
//! (f64 weights) moved by at most 3.2e-16 of the bbox diagonal (98-99 % of the points bitwise
//! equal), with the GPU's f32 weights by at most 5.0e-8 (the f32 rounding of the rows
//! themselves is 4.7e-8 there); the CPU `AdaptiveSurface` by at most 2.1e-16 of the diagonal,
//! unit normals 1.6e-12 (isolation 4). And again for the turned edges (issue 8, session 12): the
//! records of end caps with an edge from a crease vertex that is not regular (two promoted
//! creases, valence other than 4 or not opposite) carry that end's fillet code in `fillet` and
//! bit 8 + corner in `transition`; only the draw tables of the meshes with such vertices changed
//! (car, cube_creases1, cubes_semisharp), the refinement and kernels' did not.
//! And again when a build's dart masks were solved once per
//! valence (issue 8, `DartLimits`: the masks of sharp edge `d` are edge 0's rotated by `d`,
//! equal to the solve of edge `d` to 1e-12 relative, `rotated_dart_masks_are_the_solves`: the
//! same power iteration with its sums in another order): only the car's draw tables changed,
//! the rows of its darts whose sharp edge is not their ring's edge 0. And again when the
//! promoted corners' exact limit masks were shared between alike rings numbered by their shape
//! (issue 8, session 13, `SharedVertexMasks`: each distinct ring's mask is computed on an
//! extraction that starts at the face of interest, each face at the vertex, vertices numbered by
//! first appearance; equal to `vertex_mask` to 1e-12 relative, the local refinements' sums in
//! another order, `shared_vertex_masks_equal_vertex_mask`): only the draw tables of the meshes
//! with promoted creases changed (car, cube_creases1, cubes_semisharp, single_crease), their
//! promoted corners' frame rows; the refinement and kernels' did not.
//! And again for the end caps' own tangent and transversal factors (issue 8, session 13:
//! `patch::gregory::END_CAP_FACTORS` at smooth quad rings of valence 3, 5 and 6): only the draw
//! tables of the meshes with such end caps changed (car, hole_test1, nonquads, cubes_semisharp,
//! pole64), their rows' weights; the refinement and kernels' fingerprints did not (the car's and
//! cubes_semisharp's hashes re-taken again with both session-13 changes merged).
//! And again for the turns at irregular crease vertices (issue 8, h61): the records of end caps
//! with a corner where three or more promoted creases meet carry bit 12 + corner in
//! `transition`, those with a corner at an irregular crease vertex
//! (`promoted::irregular_crease_vertex`) bit 16 + corner; only the draw tables of the meshes
//! with such vertices changed (car, cube_creases1, cubes_semisharp), the refinement and
//! kernels' did not (re-taken once more with all of session 13's changes merged).
//! And again for one-sided face points at promoted creases (issue 8, session 14, h64: beside a
//! promoted edge only in two-face crease sectors, `VertexRing::one_sided_edge`): the refinement
//! fingerprints of every case moved with the `Debug` text of `Topology`, which has a new field
//! (`promoted`, empty on every level); of the draw tables only the car's changed (its end caps
//! beside promoted creases in wider crease sectors and corner sectors; cube_creases1,
//! cubes_semisharp and single_crease have none there); the kernels' did not.
//!
//! And again for the end caps' valence-3 transversal shape and factors (issue 8, h67,
//! `END_CAP_TRANSVERSAL_SHAPE`): the rows of end caps with a smooth all-quad valence-3 corner
//! moved, so the draw tables of the meshes with such vertices changed (car, hole_test1,
//! nonquads, cubes_semisharp, pole64); the refinement and kernels' did not. (Re-taken with both
//! h64 and h67 merged: the car's draw tables hold both changes, the other draw tables h67's, every
//! refinement fingerprint h64's.)
//! And again for the positional fillet (issue 8, session 15, h71): the records of end caps with a
//! corner the fillet reaches whole (`promoted::positional_fillet_end`) carry bit 20 + corner in
//! `transition`; of the cases only the car without single-crease patches has such end caps, so
//! only its draw tables changed (at 1 and 3 threads alike); the refinement and kernels' did not.
//!
//! And again for the decayed corners (issue 8, session 15, h73, `Topology::is_decayed_corner`):
//! the refinement fingerprints of every case moved with the `Debug` text of `Topology`, which has
//! a new field (`decayed_corner`, empty on every level: only the end caps' view of a level marks
//! them); the kernels' and draw tables' did not (no end cap of these cases has a decayed corner
//! of a valence `DECAYED_CORNER_SCALE` lists: 7 to 24). Checked at
//! `RAYON_NUM_THREADS=1` and `3`.
//!
//! And again for the exact corner offsets (issue 8, session 16, h78,
//! `patch::adaptive::exact_corners`): every case's draw tables moved, the patch records growing
//! from 28 to 36 words (`corner_exact`, `corner_fade`, padding), and with the exact-position
//! frames' rows where promoted corners the positional fillet does not reach whole have only quad
//! end caps around them (among the cases at least the car with single-crease patches at 2 and 4,
//! cube_creases1, cubes_semisharp, single_crease). The refinement and kernels' did not; checked at
//! `RAYON_NUM_THREADS=1` and `3`.
//!
//! And again for the fine fillet codes (issue 8, session 16, h81, `PatchRecord::fillet_fine`,
//! `promoted::fillet_fine_code`): every case's draw tables moved with the records' new field (the
//! three former padding words, now filled) and, where end caps meet at promoted creases, with
//! the 24-bit residual sharpness there in place of the `fillet` word's 16ths byte. The
//! refinement and kernels' did not; checked at `RAYON_NUM_THREADS=1` and `3`.
//!
//! The fingerprints change with any change of output, deliberate or not: a change that is meant
//! to alter the tables (new end-cap rules, another row order) re-derives them and says so.
//! And again when the end caps gained their lattice side table (issue 8, session 17,
//! `patch::adaptive::lattice_frames`: one word per end cap, a block per end cap with a corner at
//! an irregular crease vertex, and the lattice frames' rows after the exact-position frames):
//! every mesh's draw tables changed (the table's `NONE` word per end cap is part of them), the
//! refinement and kernels' did not; the same at `RAYON_NUM_THREADS=1` and `=3`. Then again
//! when regions narrower than a lattice cell were rounded up to one (not refined deeper): only
//! the car's at isolation 2 (fillet width `2^-4` there).
//!
//! And again for `--gregory-tangents fitted` (issue 10, session 18, h92,
//! `Topology::crease_factors`): the refinement fingerprints of every case moved with the `Debug`
//! text of `Topology`, which has a new field (`crease_factors`, empty on every level: only the
//! plan build under `fitted` sets it, on the base mesh); the kernels' and draw tables' did not.
//! Checked at `RAYON_NUM_THREADS=1` and `3`.
//!
//! And again for the end caps' valence-3 transversal factor `ρ` 0.8 → 0.785 (issue 8, session
//! 20, `patch::gregory::END_CAP_FACTORS`): the draw tables of the meshes with smooth all-quad
//! valence-3 end-cap corners changed (car, hole_test1, nonquads, cubes_semisharp, pole64), their
//! rows' weights; the refinement and kernels' did not. Checked at `RAYON_NUM_THREADS=1` and `3`.
//! And again for the lattice frames on sector grids (issue 8, session 21, h103: each region
//! vertex's refinement on its faces' grids, the pull-back's sums in grid order): only the draw
//! tables of the meshes with lattice regions changed (car, cube_creases1, cubes_semisharp,
//! single_crease), their lattice frames' rows; the refinement and kernels' did not. The CPU
//! surface with grid points on the lattice (`adaptive_grid` `endcaps:9`): positions bitwise,
//! normals by at most 1.2e-11 rad; the GPU capture (`tessera sample --tess 4`, which does not
//! see the lattice normals) bitwise.
//! And again for the adaptive step written in place (issue 8, session 21, h102: child points
//! numbered by kind and first appearance, edges by first appearance, rings from their parent's
//! start): every fingerprint of every case moved (the levels' numbering, the kernels' sums, the
//! rows' ids and order); GPU samples kept their keys, positions within 3.1e-7 of the bbox
//! diagonal, normals within 6.9e-4 rad (f32 refined points; bishop), the CPU surface within
//! 9.2e-16 (hashes re-taken by the lead with h103, h104 and h105 merged). Checked at
//! `RAYON_NUM_THREADS=1` and `3`.
//! And again when a closed ring of lattice sector grids started at its least rotation (issue 8,
//! session 22, h110: rotations of one sharp-spoke pattern share a grid shape, the pull-backs and
//! the last level's masks sum in the rotated order): only the draw tables of the meshes with
//! closed-ring lattice regions changed (car, cube_creases1, cubes_semisharp), their lattice
//! frames' rows; the refinement and kernels' did not. The CPU surface with grid points on the
//! lattice (`adaptive_grid` `endcaps:9`): positions bitwise, unit normals within 2.2e-13 (car
//! isolation 2), 1.8e-12 (car 4), 2.2e-11 (bishop 2); the GPU capture bitwise. Checked at
//! `RAYON_NUM_THREADS=1` and `3`.
//! And again for the end caps' classes (issue 8, session 26, h132 then h138): types equal up
//! to where their closed corners' rings start share one direct build, their rows turned (face
//! points to rounding; edge points written as the construction writes them, bitwise), and a
//! dart's edge-point coefficients projected on edge 0's masks (bits depending on the edge's
//! place after the sharp edge only): only the draw tables of the meshes with turned end caps
//! or darts changed (car, cube_creases1, cube_creases2, hole_test1, nonquads, cubes_semisharp,
//! tent_creases1, pole64); the refinement and kernels' did not. GPU capture and CPU surface
//! (iso 2: car, bishop, pole64, cube_creases1): positions bitwise, normals within 3.0e-8 rad.
//! Checked at `RAYON_NUM_THREADS=1` and `3`.

mod common;

use std::fmt::Write;
use std::sync::Arc;

use common::meshes::osd;
use tessera::render::schemes::adaptive::AdaptiveTables;
use tessera::render::{PlanOptions, SchemeLimits};
use tessera::topology::Topology;

/// FNV-1a over everything written to it.
struct Fnv(u64);

impl Write for Fnv {
    fn write_str(&mut self, s: &str) -> std::fmt::Result {
        for &b in s.as_bytes() {
            self.0 ^= u64::from(b);
            self.0 = self.0.wrapping_mul(0x100_0000_01b3);
        }
        Ok(())
    }
}

fn fingerprint(x: &impl std::fmt::Debug) -> u64 {
    let mut h = Fnv(0xcbf2_9ce4_8422_2325);
    write!(h, "{x:?}").unwrap();
    h.0
}

/// `[refinement, refinement tables, draw tables]` fingerprints of `name` at `isolation`.
fn tables(name: &str, isolation: u32, single_crease: bool) -> [u64; 3] {
    let topo = Arc::new(Topology::new(&osd(name)).unwrap());
    let faces: Vec<u32> = (0..topo.face_count() as u32).collect();
    let opts = PlanOptions::new(SchemeLimits::NO_DEVICE)
        .with_isolation(isolation)
        .with_single_crease(single_crease);
    let t = AdaptiveTables::new(&topo, &faces, &opts).unwrap();
    [
        fingerprint(&t.adaptive),
        fingerprint(&t.refinement),
        fingerprint(&t.draw),
    ]
}

#[test]
fn adaptive_tables_are_bitwise_unchanged() {
    let cases: &[(&str, u32, bool, [u64; 3])] = &[
        (
            "catmark_car",
            2,
            true,
            [0x8c504596b1ebd11f, 0x4ae1883627f7beff, 0x6d142961f2ae458d],
        ),
        (
            "catmark_car",
            4,
            true,
            [0xaa577697d5befba0, 0xbd17ec91610ada85, 0x21a06076ccfe5ead],
        ),
        (
            "catmark_car",
            2,
            false,
            [0xe0ec567d74e3f901, 0x8a56b105c260f68d, 0x25144b3d7e034d1f],
        ),
        (
            "catmark_cube_creases1",
            3,
            true,
            [0xef8f4e56ce77aa4e, 0xe6807a11d0320937, 0xc39c7d8f615548d0],
        ),
        (
            "catmark_cube_creases2",
            4,
            false,
            [0x347e5b01a05cf7c5, 0x70fd7c1eeef76b9d, 0x1f559e05ee0fe34d],
        ),
        (
            "catmark_dart_edgecorner",
            3,
            true,
            [0x2da913123bf59149, 0x27e01097bcf7dbdd, 0xf37b09ff0959b873],
        ),
        (
            "catmark_hole_test1",
            2,
            true,
            [0x63544b3a0620b64a, 0x2420c892eb45313f, 0x8731f9a0eb175f53],
        ),
        (
            "catmark_nonquads",
            3,
            true,
            [0x5274a1f8afebd9a, 0xede011b3a57fb4ae, 0xf48b122f00c654f9],
        ),
        (
            "catmark_cubes_semisharp",
            3,
            true,
            [0xced62465517e1628, 0xfb51a83c5fcf28f8, 0x1dff2233258b6dc7],
        ),
        (
            "catmark_tent_creases1",
            2,
            true,
            [0xe4f0a4ed8c2a6997, 0x9e9345e533289444, 0xb32d4458a3d63ee8],
        ),
        (
            "catmark_single_crease",
            4,
            true,
            [0xafef070e0fab9b7c, 0x58645cb72fa051fd, 0xdff8ed4919a80d49],
        ),
        (
            "catmark_pole64",
            2,
            true,
            [0x91f6c068d302ea6, 0xcd51389183c2423d, 0x68732c45c26db8c3],
        ),
    ];
    let mut wrong = Vec::new();
    for &(name, iso, sc, want) in cases {
        let got = tables(name, iso, sc);
        if got != want {
            wrong.push(format!(
                "(\"{name}\", {iso}, {sc}, [{:#x}, {:#x}, {:#x}]),",
                got[0], got[1], got[2]
            ));
        }
    }
    assert!(wrong.is_empty(), "changed:\n{}", wrong.join("\n"));
}
