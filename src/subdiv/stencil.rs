//! Stencil tables: refined vertices as sparse weighted sums of the base (control) vertices, the
//! composition of the per-level refinement matrices (OpenSubdiv's `Far::StencilTable` idea).
//! Topology is fixed, positions change every frame: `apply` is all that runs per frame.
//! (The Gregory patch stencils over one face's one-ring are `patch::gregory::stencil` and
//! `patch::gregory::stencil_table`.)

use super::level::Level;
use super::sparse::SparseMatrix;
use crate::mesh::ControlMesh;
use crate::Result;
use glam::DVec3;

/// Rows of weights over `base_count()` base vertices (CSR, `f64`, sorted columns, no zeros).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct StencilTable {
    pub(crate) matrix: SparseMatrix,
}

impl StencilTable {
    /// All vertices of uniform level `level` (ordered as [`Level::refine`] orders them) in terms
    /// of the mesh's vertices; `level = 0` is the identity.
    pub fn refined(mesh: &ControlMesh, level: u32) -> Result<StencilTable> {
        Ok(Self::from_level(&Level::from_mesh(mesh)?, level))
    }

    /// All vertices `depth` uniform steps below `base`, in terms of `base`'s vertices.
    pub fn from_level(base: &Level, depth: u32) -> StencilTable {
        let n = base.vertex_count();
        if depth == 0 {
            let mut m = SparseMatrix::new(n);
            m.indices = (0..n as u32).collect();
            m.weights = vec![1.0; n];
            m.offsets = (0..=n).collect();
            return StencilTable { matrix: m };
        }
        let mut table = base.refine_matrix();
        let mut current = (depth > 1).then(|| base.refine_topology());
        for d in 2..=depth {
            let Some(level) = current.take() else { break };
            if d < depth {
                let (child, m) = rayon::join(
                    || level.refine_topology(),
                    || level.compose_refinement(&table),
                );
                table = m;
                current = Some(child);
            } else {
                table = level.compose_refinement(&table);
            }
        }
        StencilTable { matrix: table }
    }

    /// Wraps a matrix whose columns are base vertices.
    pub fn from_matrix(matrix: SparseMatrix) -> StencilTable {
        StencilTable { matrix }
    }

    /// Number of stencils (rows).
    pub fn len(&self) -> usize {
        self.matrix.rows()
    }

    /// Whether the table has no stencils.
    pub fn is_empty(&self) -> bool {
        self.matrix.rows() == 0
    }

    /// Number of base vertices the stencils refer to.
    pub fn base_count(&self) -> usize {
        self.matrix.cols()
    }

    /// The underlying matrix.
    pub fn matrix(&self) -> &SparseMatrix {
        &self.matrix
    }

    /// Stencil `r` as `(base vertices, weights)`.
    pub fn stencil(&self, r: usize) -> (&[u32], &[f64]) {
        self.matrix.row(r)
    }

    /// Appends one stencil (e.g. a limit stencil).
    pub fn push(&mut self, entries: &[(u32, f64)]) {
        self.matrix.push_row(entries);
    }

    /// Appends all rows of `rows` (columns are base vertices).
    pub fn append(&mut self, rows: &SparseMatrix) {
        self.matrix.append(rows);
    }

    /// Appends stencils given over the vertices this table produces (e.g. limit masks over a
    /// refined level): each is composed with this table first.
    pub fn append_composed(&mut self, rows_over_table: &SparseMatrix) {
        let composed = rows_over_table.compose(&self.matrix);
        self.matrix.append(&composed);
    }

    /// `dst[r] = sum of stencil r applied to src` (parallel when large).
    pub fn apply(&self, src: &[DVec3], dst: &mut [DVec3]) {
        self.matrix.apply(src, dst);
    }

    /// Applies to `src` and returns one point per stencil.
    pub fn apply_vec(&self, src: &[DVec3]) -> Vec<DVec3> {
        self.matrix.apply_vec(src)
    }
}
