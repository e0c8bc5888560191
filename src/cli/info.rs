//! `tessera info`: counts and classification of a control mesh.

use std::collections::BTreeMap;
use std::fmt::Write;

use clap::Args;
use tessera::mesh::{ControlMesh, ObjOptions, INFINITE_SHARPNESS};
use tessera::subdiv::adaptive::{AdaptiveOptions, AdaptiveRefinement, PatchCensus, PatchType};
use tessera::subdiv::tables::RefinementTables;
use tessera::subdiv::Level;
use tessera::topology::{FaceClass, Topology};

/// Arguments of `tessera info`.
#[derive(Args)]
pub struct InfoArgs {
    /// Control mesh: an OBJ file with OpenSubdiv tags, or `embedded:NAME`
    /// (mixed, open, creased).
    pub mesh: String,
    /// The file's faces are wound clockwise seen from outside: reverse them.
    #[arg(long)]
    pub left_handed: bool,
    /// Also refine feature-adaptively to this isolation level (0-8) and print the patch
    /// census: counts by type and level, `patches total=N`, the refined vertex count and the
    /// size of the GPU subdivision tables.
    #[arg(long, value_parser = clap::value_parser!(u32).range(0..=8))]
    pub isolation: Option<u32>,
    /// With --isolation: stop refining at single-crease patches (a regular quad whose only
    /// feature is one semi-sharp crease line along one of its edges; Niessner, Loop, Greiner
    /// 2012), and count them per level as `single-crease=N`. This is how OpenSubdiv counts with
    /// `useSingleCreasePatch`.
    #[arg(long, requires = "isolation")]
    pub single_crease: bool,
    /// Set every crease tag of sharpness > 0 (semi-sharp or infinitely sharp) to S before
    /// anything else; tags of sharpness 0, boundary edges and corner tags are unchanged.
    #[arg(long, value_name = "S")]
    pub crease_sharpness: Option<f32>,
}

/// Runs the subcommand: prints the report, or returns the typed error of a bad mesh.
pub fn run(args: InfoArgs) -> tessera::Result<()> {
    let options = ObjOptions {
        left_handed: args.left_handed,
        ..ObjOptions::default()
    };
    let mut mesh = tessera::assets::load_mesh(&args.mesh, &options)?;
    if let Some(s) = args.crease_sharpness {
        mesh.set_crease_sharpness(s)?;
    }
    let topo = Topology::new(&mesh)?;
    print!("{}", report(&args.mesh, &mesh, &topo));
    if let Some(isolation) = args.isolation {
        let base = Level::from_topology(topo);
        let refinement = AdaptiveRefinement::with_options(
            &base,
            AdaptiveOptions {
                single_crease: args.single_crease,
                ..AdaptiveOptions::new(isolation)
            },
        )?;
        let tables = RefinementTables::adaptive(&refinement)?;
        print!(
            "{}",
            census_report(&refinement, &PatchCensus::new(&refinement))
        );
        println!("refined vertices={}", tables.total_vertices);
        println!("table bytes={}", tables.gpu_tables().bytes());
    }
    Ok(())
}

/// The census part of the report: one line per level with counts by type (`single-crease`
/// only when the refinement uses single-crease patches), totals by type, and
/// the script-readable `patches total=N` (every drawn patch, end caps and transition patches
/// included).
fn census_report(refinement: &AdaptiveRefinement, census: &PatchCensus) -> String {
    let mut out = String::new();
    let w = &mut out;
    let _ = writeln!(
        w,
        "adaptive isolation {}: {} levels, {} refined vertices",
        refinement.isolation,
        refinement.levels.len(),
        refinement.vertex_count()
    );
    let counts = |by_type: &[usize], transition: usize| {
        let mut parts: Vec<String> = PatchType::ALL
            .iter()
            .filter(|&&k| k != PatchType::SingleCrease || refinement.single_crease)
            .map(|&k| format!("{}={}", k.name(), by_type[k as usize]))
            .collect();
        parts.push(format!("transition={transition}"));
        parts.join(" ")
    };
    for (l, c) in census.levels.iter().enumerate() {
        let _ = writeln!(
            w,
            "patches level {l}: total={} {}",
            c.total(),
            counts(&c.by_type, c.transition)
        );
    }
    let by_type = PatchType::ALL.map(|k| census.count(k));
    let transition = census.levels.iter().map(|c| c.transition).sum();
    let _ = writeln!(w, "patches by type: {}", counts(&by_type, transition));
    let _ = writeln!(w, "patches total={}", census.total());
    out
}

/// `k: n, k: n, ...` of a histogram (or `none`).
fn histogram<K: std::fmt::Display>(h: &BTreeMap<K, usize>) -> String {
    if h.is_empty() {
        return "none".into();
    }
    h.iter()
        .map(|(k, n)| format!("{k}: {n}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// A sharpness as a grouping key: its text, `inf` at or above [`INFINITE_SHARPNESS`].
fn sharpness_key(s: f32) -> String {
    if s >= INFINITE_SHARPNESS {
        "inf".into()
    } else {
        format!("{s}")
    }
}

/// Sharpness histogram, ordered by value with `inf` last.
fn sharpness_histogram(values: impl Iterator<Item = f32>) -> String {
    let mut v: Vec<f32> = values.map(|s| s.min(INFINITE_SHARPNESS)).collect();
    if v.is_empty() {
        return "none".into();
    }
    v.sort_by(f32::total_cmp);
    let mut parts: Vec<(String, usize)> = Vec::new();
    for s in v {
        let key = sharpness_key(s);
        match parts.last_mut() {
            Some((k, n)) if *k == key => *n += 1,
            _ => parts.push((key, 1)),
        }
    }
    parts
        .iter()
        .map(|(k, n)| format!("{k}: {n}"))
        .collect::<Vec<_>>()
        .join(", ")
}

fn class_name(c: FaceClass) -> &'static str {
    match c {
        FaceClass::Hole => "hole",
        FaceClass::Boundary => "boundary",
        FaceClass::Creased => "creased",
        FaceClass::Triangle => "triangle",
        FaceClass::Polygon => "polygon",
        FaceClass::IrregularQuad => "irregular quad",
        FaceClass::RegularQuad => "regular quad",
    }
}

/// The text `tessera info` prints.
///
/// Interior extraordinary vertices have valence (edge count) != 4; boundary extraordinary
/// vertices have valence >= 4 (valence 2 is a boundary corner, 3 a regular boundary vertex).
/// Creases and corners are counted as tagged, grouped by sharpness (`inf` >= 10).
fn report(name: &str, mesh: &ControlMesh, topo: &Topology) -> String {
    let mut out = String::new();
    let w = &mut out;
    let nv = mesh.vertex_count();
    let nf = mesh.face_count();
    let mut sizes = BTreeMap::new();
    for f in 0..nf {
        *sizes.entry(mesh.face_size(f)).or_insert(0usize) += 1;
    }
    let (mut interior_ev, mut boundary_ev) = (BTreeMap::new(), BTreeMap::new());
    let (mut n_interior, mut n_boundary, mut unreferenced) = (0, 0, 0);
    for v in 0..nv as u32 {
        let valence = topo.valence(v);
        if topo.vertex_faces(v).is_empty() {
            unreferenced += 1;
        } else if topo.is_boundary_vertex(v) {
            n_boundary += 1;
            if valence >= 4 {
                *boundary_ev.entry(valence).or_insert(0usize) += 1;
            }
        } else {
            n_interior += 1;
            if valence != 4 {
                *interior_ev.entry(valence).or_insert(0usize) += 1;
            }
        }
    }
    let boundary_edges = (0..topo.edge_count() as u32)
        .filter(|&e| topo.is_boundary_edge(e))
        .count();
    let mut classes = BTreeMap::new();
    for f in 0..nf as u32 {
        let c = topo.face_class(f);
        classes.entry(class_rank(c)).or_insert((c, 0usize)).1 += 1;
    }
    let class_text = classes
        .values()
        .map(|&(c, n)| format!("{}: {n}", class_name(c)))
        .collect::<Vec<_>>()
        .join(", ");
    let ev_total = |h: &BTreeMap<usize, usize>| h.values().sum::<usize>();
    let opts = mesh.options();
    let _ = writeln!(w, "mesh: {name}");
    let _ = writeln!(
        w,
        "vertices: {nv} (interior {n_interior}, boundary {n_boundary}, unreferenced {unreferenced})"
    );
    let _ = writeln!(w, "faces: {nf} (by size: {})", histogram(&sizes));
    let _ = writeln!(
        w,
        "edges: {} (boundary {boundary_edges})",
        topo.edge_count()
    );
    let _ = writeln!(
        w,
        "extraordinary vertices, interior: {} (by valence: {})",
        ev_total(&interior_ev),
        histogram(&interior_ev)
    );
    let _ = writeln!(
        w,
        "extraordinary vertices, boundary: {} (by valence: {})",
        ev_total(&boundary_ev),
        histogram(&boundary_ev)
    );
    let _ = writeln!(
        w,
        "creases: {} (by sharpness: {})",
        mesh.creases().len(),
        sharpness_histogram(mesh.creases().iter().map(|c| c.sharpness))
    );
    let _ = writeln!(
        w,
        "corners: {} (by sharpness: {})",
        mesh.corners().len(),
        sharpness_histogram(mesh.corners().iter().map(|c| c.sharpness))
    );
    let holes = (0..nf).filter(|&f| mesh.is_hole(f)).count();
    let _ = writeln!(w, "holes: {holes}");
    let _ = writeln!(
        w,
        "scheme: boundary {:?}, crease method {:?}",
        opts.boundary, opts.crease_method
    );
    let _ = writeln!(w, "faces by class: {class_text}");
    let _ = writeln!(w, "warnings: {}", mesh.warnings().len());
    for warning in mesh.warnings() {
        let _ = writeln!(w, "  {warning}");
    }
    out
}

/// Sort key listing classes in the order they are checked.
fn class_rank(c: FaceClass) -> u8 {
    match c {
        FaceClass::Hole => 0,
        FaceClass::Boundary => 1,
        FaceClass::Creased => 2,
        FaceClass::Triangle => 3,
        FaceClass::Polygon => 4,
        FaceClass::IrregularQuad => 5,
        FaceClass::RegularQuad => 6,
    }
}
