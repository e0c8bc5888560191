//! The end caps' error against the exact limit per point class (docs/measured.md's *Where the fillet
//! cells' error sits*): a 9x9 grid of each end cap's own (s, t) (as `adaptive_grid endcaps:9`),
//! the drawn normal (`AdaptiveSurface::eval_with_normal`) and position against `LimitEvaluator`
//! at equal (u, v), summed per class of point relative to the promoted creases
//! (`patch::adaptive::promoted`): on a promoted edge (`promoted-edge-s` + the floor of its
//! residual sharpness), inside an end cap within the fillet of one (`band-s…`), on another edge
//! from a vertex on one (`edge-from-promoted`, with the vertex's valence, the number of promoted
//! edges there, whether two of them are opposite in the ring, and the grid step from the vertex),
//! farther along such an edge (`edge-far-promoted`), at such a vertex (`corner-promoted`),
//! elsewhere in an end cap with such a corner (`interior-promoted-cap`), and every other end-cap
//! point (`plain`). Per class: points, RMS / max distance (fraction of the bbox diagonal), share of the
//! summed squared normal error, RMS / max normal angle (rad).
//!
//! A second table splits the same points by region: `near-irregular` within the fillet width
//! `h = 2^-floor(s)` (own parameter, both directions) of an end-cap corner at a promoted vertex
//! whose crease is not regular (`vertex_fillet_sharpness` is `None`; `s` the mean residual
//! sharpness of its promoted edges, else its vertex sharpness), `elsewhere` the rest. Within `h`
//! of such a vertex the limit is the vertex's smoothed neighbourhood, a region of fixed size on
//! the surface (`h` doubles per level as the end caps halve), so its share of the grid points
//! grows with the isolation level. `elsewhere-only` is the RMS over all points with the region's
//! error set to zero.
//!
//! ```sh
//! cargo run --example endcap_error_classes -- MESH.obj ISOLATION [STEPS]
//! ```

use std::collections::BTreeMap;

use rayon::prelude::*;
use tessera::mesh::ObjOptions;
use tessera::patch::adaptive::promoted::{promoted_vertex, vertex_fillet_sharpness};
use tessera::patch::adaptive::{AdaptiveSurface, PatchShape};
use tessera::subdiv::adaptive::AdaptiveRefinement;
use tessera::subdiv::eval::LimitEvaluator;
use tessera::subdiv::Level;
use tessera::topology::Topology;
use tessera::ControlMesh;

/// Grid steps per end-cap side unless the third argument gives them (8: the 9x9 grid of
/// `adaptive_grid endcaps:9`, whose points are lattice points of `patch::adaptive::lattice_frames`;
/// 7: a grid between them).
const STEPS: usize = 8;

/// A sample: patch index, own (s, t), base (u, v), class, whether it is near an irregular
/// crease vertex.
type Sample = (usize, (f64, f64), (f64, f64), String, bool);

/// Per class: points, summed squared distance, max distance, summed squared angle, max angle.
type Sums = (usize, f64, f64, f64, f64);

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (Some(path), Some(iso)) = (args.first(), args.get(1)) else {
        return Err("usage: endcap_error_classes MESH.obj ISOLATION [STEPS]".into());
    };
    let iso: u32 = iso.parse()?;
    let steps: usize = args.get(2).map_or(Ok(STEPS), |s| s.parse())?;
    let mesh = ControlMesh::from_obj_file(path, &ObjOptions::default())?;
    let r = AdaptiveRefinement::new(&Level::from_mesh(&mesh)?, iso)?;
    let s = AdaptiveSurface::new(&r, mesh.positions())?;
    let ev = LimitEvaluator::new(&mesh)?;
    let diag = mesh.bbox_diagonal();
    let mut caps_by_level = BTreeMap::new();
    // Samples grouped by (base face, sub-face): one exact evaluation per group.
    let mut groups: BTreeMap<(u32, u32), Vec<Sample>> = BTreeMap::new();
    for (i, p) in s.patches.iter().enumerate() {
        if !matches!(p.shape, PatchShape::Gregory(_)) {
            continue;
        }
        let t = r.levels[p.level as usize].topology();
        let caps = caps_by_level
            .entry(p.level)
            .or_insert_with(|| r.end_cap_topology(p.level as usize));
        for j in 0..=steps {
            for k in 0..=steps {
                let st = (k as f64 / steps as f64, j as f64 / steps as f64);
                let d = p.domain;
                let uv = d.origin + st.0 * d.u + st.1 * d.v;
                groups
                    .entry((d.base_face, d.sub_face.unwrap_or(0)))
                    .or_default()
                    .push((
                        i,
                        st,
                        (uv.x, uv.y),
                        class(t, caps, p.face, st),
                        near_irregular(t, caps, p.face, st),
                    ));
            }
        }
    }
    let groups: Vec<_> = groups.into_iter().collect();
    let measured: Vec<(String, bool, f64, f64)> = groups
        .par_iter()
        .flat_map_iter(|((f, sub), samples)| {
            let uv: Vec<(f64, f64)> = samples.iter().map(|x| x.2).collect();
            let exact = ev.eval_points(*f as usize, *sub as usize, &uv).unwrap();
            samples
                .iter()
                .zip(exact)
                .map(|((i, st, _, class, near), x)| {
                    let (got, normal) = s.eval_with_normal(*i, st.0, st.1);
                    let angle = normal.angle_between(x.normal);
                    let angle = if angle.is_finite() { angle } else { 0.0 };
                    (
                        class.clone(),
                        *near,
                        got.position.distance(x.position) / diag,
                        angle,
                    )
                })
                .collect::<Vec<_>>()
        })
        .collect();
    let mut by_class: BTreeMap<String, Sums> = BTreeMap::new();
    let mut by_region: BTreeMap<String, Sums> = BTreeMap::new();
    let mut total: Sums = Default::default();
    for (class, near, dist, angle) in &measured {
        let region = if *near { "near-irregular" } else { "elsewhere" };
        for e in [
            by_class.entry(class.clone()).or_default(),
            by_region.entry(region.into()).or_default(),
            &mut total,
        ] {
            e.0 += 1;
            e.1 += dist * dist;
            e.2 = e.2.max(*dist);
            e.3 += angle * angle;
            e.4 = e.4.max(*angle);
        }
    }
    println!("class points dist_rms dist_max normal_share normal_rms normal_max");
    print_rows(&by_class, &total);
    println!("region points dist_rms dist_max normal_share normal_rms normal_max");
    print_rows(&by_region, &total);
    let rest = by_region.get("elsewhere").copied().unwrap_or_default();
    println!(
        "elsewhere-only normal_rms {:.3e} (all {} points, the near-irregular ones counted as exact)",
        (rest.3 / total.0.max(1) as f64).sqrt(),
        total.0
    );
    Ok(())
}

/// One line per entry of `rows`, then the `total` line.
fn print_rows(rows: &BTreeMap<String, Sums>, total: &Sums) {
    let total_row = ("TOTAL".to_string(), *total);
    for (class, e) in rows.iter().chain([(&total_row.0, &total_row.1)]) {
        println!(
            "{class:40} {:8} {:.3e} {:.3e} {:5.1}% {:.3e} {:.3}",
            e.0,
            (e.1 / e.0 as f64).sqrt(),
            e.2,
            100.0 * e.3 / total.3.max(f64::MIN_POSITIVE),
            (e.3 / e.0 as f64).sqrt(),
            e.4
        );
    }
}

/// Whether own `(s, t)` of end cap `face` lies within the fillet width `h` (both directions) of
/// a corner at a promoted vertex whose crease is not regular (module doc).
fn near_irregular(t: &Topology, caps: &Topology, face: u32, (s, u): (f64, f64)) -> bool {
    let fv = t.face_vertices(face);
    if fv.len() != 4 {
        return false;
    }
    let own = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)];
    fv.iter().zip(own).any(|(&v, (cs, ct))| {
        if !promoted_vertex(t, caps, v) || vertex_fillet_sharpness(t, caps, v).is_some() {
            return false;
        }
        let promoted: Vec<f32> = t
            .vertex_edges(v)
            .iter()
            .filter(|&&e| caps.is_promoted_edge(e))
            .map(|&e| t.edge_sharpness(e))
            .collect();
        let sharpness = if promoted.is_empty() {
            t.vertex_sharpness(v)
        } else {
            promoted.iter().sum::<f32>() / promoted.len() as f32
        };
        let h = f64::from(sharpness.floor()).exp2().recip();
        (s - cs).abs().max((u - ct).abs()) < h
    })
}

/// The class of own `(s, t)` of end cap `face` of level topology `t` (`caps` as its end caps
/// see it).
fn class(t: &Topology, caps: &Topology, face: u32, (s, u): (f64, f64)) -> String {
    let fv = t.face_vertices(face);
    let fe = t.face_edges(face);
    let any = fv.iter().any(|&v| promoted_vertex(t, caps, v));
    if fv.len() != 4 {
        return if any { "triangle-promoted" } else { "plain" }.into();
    }
    let corner = match (s, u) {
        (0.0, 0.0) => Some(0),
        (1.0, 0.0) => Some(1),
        (1.0, 1.0) => Some(2),
        (0.0, 1.0) => Some(3),
        _ => None,
    };
    if let Some(c) = corner {
        let v = fv[c];
        return match (promoted_vertex(t, caps, v), any) {
            (true, _) => format!("corner-promoted-val{}", t.valence(v)),
            (false, true) => "corner-other".into(),
            _ => "plain".into(),
        };
    }
    // Quad edge k at x from corner k.
    let edge = match (s, u) {
        (_, 0.0) => Some((0, s)),
        (1.0, _) => Some((1, u)),
        (_, 1.0) => Some((2, 1.0 - s)),
        (0.0, _) => Some((3, 1.0 - u)),
        _ => None,
    };
    if let Some((k, x)) = edge {
        let e = fe[k];
        if caps.is_promoted_edge(e) {
            return format!("promoted-edge-s{}", t.edge_sharpness(e).floor());
        }
        let (a, b) = (fv[k], fv[(k + 1) % 4]);
        let (near, far, step) = if x < 0.5 { (a, b, x) } else { (b, a, 1.0 - x) };
        if promoted_vertex(t, caps, near) {
            let ring = t.vertex_edges(near);
            let on: Vec<usize> = (0..ring.len())
                .filter(|&j| caps.is_promoted_edge(ring[j]))
                .collect();
            let opposite = on.len() == 2 && on[1] - on[0] == ring.len() / 2;
            return format!(
                "edge-from-promoted-val{}-p{}{}-x{}",
                ring.len(),
                on.len(),
                if opposite { "-opposite" } else { "" },
                // In eighths of the edge whatever the grid.
                (step * STEPS as f64).round()
            );
        }
        if promoted_vertex(t, caps, far) {
            return format!("edge-far-promoted-val{}", t.valence(far));
        }
        return if any { "edge-other" } else { "plain" }.into();
    }
    // Inside: the nearest promoted edge whose fillet (width 2^-floor(s)) holds the point.
    let band = (0..4)
        .filter(|&k| caps.is_promoted_edge(fe[k]))
        .map(|k| {
            let w = [u, 1.0 - s, 1.0 - u, s][k];
            (w, t.edge_sharpness(fe[k]))
        })
        .filter(|&(w, sharp)| w < (f64::from(sharp.floor())).exp2().recip())
        .min_by(|a, b| a.0.total_cmp(&b.0));
    match (band, fv.iter().find(|&&v| promoted_vertex(t, caps, v))) {
        (Some((_, sharp)), _) => format!("band-s{}", sharp.floor()),
        (None, Some(&v)) => format!("interior-promoted-cap-val{}", t.valence(v)),
        _ => "plain".into(),
    }
}
