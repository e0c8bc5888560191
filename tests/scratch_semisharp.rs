mod common;

use common::meshes::osd;
use rayon::prelude::*;
use tessera::mesh::INFINITE_SHARPNESS;
use tessera::patch::adaptive::{AdaptiveSurface, PatchShape};
use tessera::patch::gregory::{gregory_patch_at_for, Coverage, GregoryTangents};
use tessera::subdiv::adaptive::AdaptiveRefinement;
use tessera::subdiv::eval::LimitEvaluator;
use tessera::subdiv::Level;

fn semi(s: f32) -> bool {
    s > 0.0 && s < INFINITE_SHARPNESS
}

#[test]
#[ignore]
fn measure() {
    let names = std::env::var("MESHES").unwrap();
    let isos: Vec<u32> = std::env::var("ISOS").unwrap_or("1,2,3,4".into()).split(',').map(|x| x.parse().unwrap()).collect();
    for name in names.split(',') {
        let m = osd(name);
        let ev = LimitEvaluator::new(&m).unwrap();
        let diag = m.bbox_diagonal();
        for &iso in &isos {
            let r = AdaptiveRefinement::new(&Level::from_mesh(&m).unwrap(), iso).unwrap();
            let base = AdaptiveSurface::new(&r, m.positions()).unwrap();
            // variants: name, threshold (None smooth)
            for (vname, thr) in [("smooth", None), ("sharp>0", Some(1e-6f32)), ("sharp>=0.5", Some(0.5)), ("sharp>=1", Some(1.0)), ("sharp>=2", Some(2.0))] {
                let mut s = base.clone();
                for p in s.patches.iter_mut() {
                    if !matches!(p.shape, PatchShape::Gregory(_)) { continue; }
                    let lev = &r.levels[p.level as usize];
                    let t0 = lev.topology();
                    let t = match thr {
                        None => t0.without_semi_sharpness().into_owned(),
                        Some(th) => t0.with_semi_sharpness_as_crease(th).into_owned(),
                    };
                    let first = lev.first_vertex as usize;
                    let local = &base.positions[first..first + lev.level.vertex_count()];
                    let g = gregory_patch_at_for(&t, local, p.face, GregoryTangents::default(), Coverage::EndCap).unwrap();
                    p.shape = PatchShape::Gregory(Box::new(g));
                }
                // samples
                let idx: Vec<usize> = s.patches.iter().enumerate().filter(|(_, p)| {
                    if !matches!(p.shape, PatchShape::Gregory(_)) { return false; }
                    let t = r.levels[p.level as usize].topology();
                    t.face_vertices(p.face).iter().any(|&v| semi(t.vertex_sharpness(v)) || t.vertex_edges(v).iter().any(|&e| semi(t.edge_sharpness(e))))
                }).map(|(i, _)| i).collect();
                let n = 8;
                let res: Vec<(f64, f64)> = idx.par_iter().flat_map_iter(|&i| {
                    let p = &s.patches[i];
                    let d = p.domain;
                    let mut out = Vec::new();
                    let mut uv = Vec::new();
                    let mut st = Vec::new();
                    for j in 0..=n { for k in 0..=n {
                        let (a, b) = (k as f64 / n as f64, j as f64 / n as f64);
                        let x = d.origin + a * d.u + b * d.v;
                        uv.push((x.x, x.y)); st.push((a, b));
                    }}
                    let ex = ev.eval_points(d.base_face as usize, d.sub_face.unwrap_or(0) as usize, &uv).unwrap();
                    for (&(a, b), x) in st.iter().zip(ex) {
                        let got = s.eval_patch(i, a, b);
                        let dist = got.position.distance(x.position) / diag;
                        let nn = got.du.cross(got.dv);
                        let ang = if nn.length() > 0.0 { nn.angle_between(x.normal) } else { f64::NAN };
                        out.push((dist, ang));
                    }
                    out
                }).collect();
                let rms = |f: &dyn Fn(&(f64, f64)) -> f64| {
                    let v: Vec<f64> = res.iter().map(f).filter(|x| x.is_finite()).collect();
                    ((v.iter().map(|x| x * x).sum::<f64>() / v.len().max(1) as f64).sqrt(), v.iter().cloned().fold(0.0, f64::max))
                };
                let (dr, dm) = rms(&|x| x.0);
                let (nr, nm) = rms(&|x| x.1);
                eprintln!("{name} L{iso} {vname:>20}: caps@semi {:5} dist {:.3e} / {:.3e}  normal {:.3e} / {:.3e}", idx.len(), dr, dm, nr, nm);
            }
        }
    }
}

