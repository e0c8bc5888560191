//! Facet classes (paper §3) and the patches of a whole mesh.

use super::construct::{bicubic, pm_facet, polar};
use super::corner::{facet_corner, FacetCorner};
use super::error::NotPm;
use super::vertex::{check_vertex, pm_vertex, PmOptions, PmVertex};
use crate::patch::gregory::{GregoryPoint, Weights};
use crate::topology::Topology;
use glam::DVec3;

/// What a facet becomes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FacetClass {
    /// A quad whose corners have valence 4 and whose corners' faces are all quads: bicubic.
    Ordinary,
    /// A triangle of a polar fan (its corner `pole` is the centre): singular bicubic.
    Polar {
        /// The pole's corner index in the facet.
        pole: usize,
    },
    /// Any other facet of `m = 3, 4, 5` sides: Pm-patch.
    Pm {
        /// Number of sides.
        m: usize,
    },
}

/// One facet's patch, control points in the layouts of [`super::construct`].
#[derive(Debug, Clone, PartialEq)]
pub enum PmPatch<P = DVec3> {
    /// 16 bicubic Bézier points `b[i + 4 j]`.
    Bicubic(Box<[P; 16]>),
    /// 13 points of a singular bicubic; `pole` is the pole's corner in the facet (corner
    /// `pole + 1` is the patch's `(0, 0)`, corner `pole + 2` its `(1, 0)`).
    Polar {
        /// Control points.
        h: Box<[P; 13]>,
        /// The pole's corner in the facet.
        pole: usize,
    },
    /// `6 m + 1` points: per sector `v, b_210, b_120, b_211, b_121, b_112`, then `b_004`.
    Pm(Vec<P>),
}

impl<P> PmPatch<P> {
    /// Control points of this patch (16, 13 or `6 m + 1`).
    pub fn points(&self) -> &[P] {
        match self {
            PmPatch::Bicubic(b) => &b[..],
            PmPatch::Polar { h, .. } => &h[..],
            PmPatch::Pm(p) => p,
        }
    }
}

/// An interior vertex all of whose faces are triangles and all of whose neighbours are interior
/// of valence 4: the centre of a polar configuration.
pub fn is_pole(topo: &Topology, v: u32) -> bool {
    !topo.is_boundary_vertex(v)
        && topo.valence(v) >= 3
        && topo.vertex_faces(v).iter().all(|&f| topo.face_size(f) == 3)
        && topo.vertex_edges(v).iter().all(|&e| {
            let w = topo.other_vertex(e, v);
            !topo.is_boundary_vertex(w) && topo.valence(w) == 4
        })
}

fn is_ordinary(topo: &Topology, face: u32) -> bool {
    topo.face_size(face) == 4
        && topo.face_vertices(face).iter().all(|&v| {
            topo.valence(v) == 4 && topo.vertex_faces(v).iter().all(|&g| topo.face_size(g) == 4)
        })
}

/// The class of `face`, or why it gets no patch.
pub fn classify(topo: &Topology, face: u32) -> Result<FacetClass, NotPm> {
    let size = topo.face_size(face);
    if !(3..=5).contains(&size) {
        return Err(NotPm::Polygon { face, size });
    }
    if topo.is_hole(face) {
        return Err(NotPm::Hole { face });
    }
    for &v in topo.face_vertices(face) {
        check_vertex(topo, face, v)?;
    }
    if is_ordinary(topo, face) {
        return Ok(FacetClass::Ordinary);
    }
    if size == 3 {
        let poles: Vec<usize> = (0..3)
            .filter(|&k| is_pole(topo, topo.face_vertices(face)[k]))
            .collect();
        if let [pole] = poles[..] {
            return Ok(FacetClass::Polar { pole });
        }
    }
    Ok(FacetClass::Pm { m: size })
}

/// The vertex stage over every vertex that can carry patches (`None` for the others).
pub fn pm_vertices<P: GregoryPoint>(
    topo: &Topology,
    point: &impl Fn(u32) -> P,
    options: &PmOptions,
) -> Vec<Option<PmVertex<P>>> {
    (0..topo.vertex_count() as u32)
        .map(|v| {
            let n = topo.valence(v);
            let ok = !topo.is_boundary_vertex(v) && n >= 3 && topo.vertex_faces(v).len() == n;
            ok.then(|| pm_vertex(topo, v, point, options))
        })
        .collect()
}

/// The patch of `face` from the vertex stage `verts` ([`pm_vertices`]).
pub fn pm_patch<P: GregoryPoint>(
    topo: &Topology,
    face: u32,
    verts: &[Option<PmVertex<P>>],
    options: &PmOptions,
) -> Result<PmPatch<P>, NotPm> {
    let class = classify(topo, face)?;
    let fv = topo.face_vertices(face);
    let corners: Vec<FacetCorner<P>> = (0..fv.len())
        .map(|k| {
            let vert = verts[fv[k] as usize].as_ref().ok_or(NotPm::Boundary {
                face,
                vertex: fv[k],
            })?;
            Ok(facet_corner(topo, face, k, vert))
        })
        .collect::<Result<_, NotPm>>()?;
    Ok(match class {
        FacetClass::Ordinary => PmPatch::Bicubic(Box::new(bicubic(&corners))),
        FacetClass::Polar { pole } => {
            let (a, b) = ((pole + 1) % 3, (pole + 2) % 3);
            let crease = |k: usize| options.edge_crease(topo.face_edges(face)[k]);
            // Edge `pole` joins the pole and corner a; edge `b` joins corner b and the pole.
            let h = polar(
                &corners[a],
                &corners[b],
                &corners[pole],
                [crease(pole), crease(b)],
            );
            PmPatch::Polar {
                h: Box::new(h),
                pole,
            }
        }
        FacetClass::Pm { .. } => PmPatch::Pm(pm_facet(&corners)),
    })
}

/// Every facet's patch over vertex positions, or its refusal.
pub fn pm_facets(
    topo: &Topology,
    positions: &[DVec3],
    options: &PmOptions,
) -> Vec<Result<PmPatch, NotPm>> {
    let verts = pm_vertices(topo, &|v| positions[v as usize], options);
    (0..topo.face_count() as u32)
        .map(|f| pm_patch(topo, f, &verts, options))
        .collect()
}

/// The patches of a whole mesh; the first facet the construction cannot take is the error.
pub fn pm_patches(
    topo: &Topology,
    positions: &[DVec3],
    options: &PmOptions,
) -> Result<Vec<PmPatch>, NotPm> {
    pm_facets(topo, positions, options).into_iter().collect()
}

/// The stencil form: every control point of every facet as weights over control vertices
/// (the same construction run on unit weight vectors).
pub fn pm_facets_weights(
    topo: &Topology,
    options: &PmOptions,
) -> Vec<Result<PmPatch<Weights>, NotPm>> {
    let verts = pm_vertices(topo, &Weights::unit, options);
    (0..topo.face_count() as u32)
        .map(|f| pm_patch(topo, f, &verts, options))
        .collect()
}
