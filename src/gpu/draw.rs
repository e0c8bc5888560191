//! Draw-size rules for patch lists.
//!
//! Measured on Mesa 22.3.6 lavapipe (tests/gpu_core.rs, `chunked_patch_draws_are_correct`
//! and the scan recorded in src/gpu/README.md): within one draw of a `PATCH_LIST`, only the
//! first `floor(1024 / P)` patches of an indexed draw, or `floor(4096 / P)` patches of a
//! non-indexed draw, reach the TCS with their own control points (P = control points per
//! patch); every later patch is evaluated from wrong control points (deterministically); and
//! past [`MAX_DOMAIN_POINTS_PER_DRAW`] tessellated points in one draw the triangles join wrong
//! vertices. Splitting draws at these sizes is valid on every device and costs a few extra draw
//! calls, so it is applied always (no driver detection). [`patch_draw_chunks`] applies both
//! rules; every patch pass draws through it (`render::pass::record_patch_draws`).

/// Largest number of `points_per_patch`-point patches to put in one indexed draw.
pub const MAX_INDICES_PER_PATCH_DRAW: u32 = 1024;
/// Largest number of vertices to put in one non-indexed patch draw.
pub const MAX_VERTICES_PER_PATCH_DRAW: u32 = 4096;

/// Largest number of tessellated domain points (TES invocations) one patch draw may produce.
/// Measured on Mesa 22.3.6 lavapipe with the one-point QAS patches of `catmark_car` (1575
/// quads): at uniform level 8 (81 points per quad) draws of 800 patches are correct and of 832
/// are not; at level 16 (289 points) 226 are and 240 are not, i.e. the wrong patches start past
/// 2^16 domain points in one draw. [`patch_draw_chunks`] keeps every draw below it by the
/// largest level of the draw's patches ([`patches_per_draw_at_level`]).
pub const MAX_DOMAIN_POINTS_PER_DRAW: u32 = 1 << 16;

/// An upper bound of the domain points of a quad patch whose levels are at most `level`, for
/// any spacing (fractional levels round up to at most `ceil(level) + 1` segments).
pub fn quad_domain_points(level: f32) -> u32 {
    let side = level.max(1.0).ceil() as u32 + 2;
    side * side
}

/// How many patches whose levels are at most `level` one draw may hold so that it stays below
/// [`MAX_DOMAIN_POINTS_PER_DRAW`] (at least 1).
pub fn patches_per_draw_at_level(level: f32) -> u32 {
    (MAX_DOMAIN_POINTS_PER_DRAW / quad_domain_points(level)).max(1)
}

/// How many patches of `points_per_patch` control points one draw may hold (at least 1).
pub fn max_patches_per_draw(points_per_patch: u32, indexed: bool) -> u32 {
    let limit = if indexed {
        MAX_INDICES_PER_PATCH_DRAW
    } else {
        MAX_VERTICES_PER_PATCH_DRAW
    };
    (limit / points_per_patch.max(1)).max(1)
}

/// How many patches of `points_per_patch` control points, tessellated at levels at most
/// `max_level`, one draw may hold: the smaller of [`max_patches_per_draw`] (control points) and
/// [`patches_per_draw_at_level`] (domain points), at least 1.
pub fn patches_per_draw(points_per_patch: u32, indexed: bool, max_level: f32) -> u32 {
    max_patches_per_draw(points_per_patch, indexed).min(patches_per_draw_at_level(max_level))
}

/// Splits `patch_count` patches of `points_per_patch` control points, tessellated at levels at
/// most `max_level`, into `(first_patch, count)` draws of at most [`patches_per_draw`] patches.
/// `gl_PrimitiveID` restarts at 0 in every draw, so shaders need `first_patch` (e.g. as a push
/// constant) to index per-patch data.
pub fn patch_draw_chunks(
    patch_count: u32,
    points_per_patch: u32,
    indexed: bool,
    max_level: f32,
) -> impl Iterator<Item = (u32, u32)> {
    let step = patches_per_draw(points_per_patch, indexed, max_level);
    (0..patch_count)
        .step_by(step as usize)
        .map(move |first| (first, step.min(patch_count - first)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chunk_sizes() {
        assert_eq!(max_patches_per_draw(16, true), 64);
        assert_eq!(max_patches_per_draw(20, true), 51);
        assert_eq!(max_patches_per_draw(4, false), 1024);
        assert_eq!(max_patches_per_draw(20, false), 204);
        assert_eq!(max_patches_per_draw(2000, true), 1);
        let c: Vec<_> = patch_draw_chunks(130, 16, true, 16.0).collect();
        assert_eq!(c, vec![(0, 64), (64, 64), (128, 2)]);
        assert_eq!(patch_draw_chunks(0, 16, true, 16.0).count(), 0);
        // Level 64 (66 x 66 points per quad): 15 patches per draw, below the 64 of the index rule.
        let c: Vec<_> = patch_draw_chunks(40, 16, true, 64.0).collect();
        assert_eq!(c, vec![(0, 15), (15, 15), (30, 10)]);
        // One-point patches at level 8: the domain points (655), not the indices (1,024), bind.
        assert_eq!(patches_per_draw(1, true, 8.0), 655);
        assert_eq!(patches_per_draw(4, true, 14.0), 256);
        // Level 8: at most 10 x 10 points per quad; level 16: 18 x 18 (the measured 226 fit).
        assert_eq!(patches_per_draw_at_level(8.0), 655);
        assert_eq!(patches_per_draw_at_level(16.0), 202);
        assert_eq!(patches_per_draw_at_level(64.0), 15);
    }
}
