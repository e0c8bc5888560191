//! The flat per-vertex tables of the two-stage variant (§4.1-4.2): a shader-style
//! re-implementation that reads ONLY `GregoryVertexTable`'s arrays and the positions (as the
//! vertex shader and TCS will) reproduces the library's patches. It doubles as the porting
//! template for the GLSL helper.

mod common;

use common::meshes::mesh as load;
use glam::DVec3;
use std::f64::consts::PI;
use tessera::patch::gregory::table::{
    GregoryVertexTable, KIND_CORNER, KIND_CREASE, KIND_NONE, KIND_SMOOTH,
};
use tessera::patch::gregory::{gregory_patch_at_with, GregoryPatch, GregoryTangents};
use tessera::topology::Topology;

/// What the vertex shader outputs for one vertex.
struct VertexOut {
    p: DVec3,
    e: Vec<DVec3>,
    r_plus: Vec<DVec3>,
    r_minus: Vec<DVec3>,
    cos: Vec<f64>,
    /// Per face: bit 0 / bit 1 its first / second edge is sharp, when the vertex's face points
    /// beside sharp edges are one-sided (the flag word); empty otherwise.
    sides: Vec<u8>,
    corner: bool,
}

/// The vertex stage, from the flat arrays only.
fn vertex_stage(t: &GregoryVertexTable, pos: &[DVec3], v: usize) -> Option<VertexOut> {
    let [off, ne, nf, kind] = [0, 1, 2, 3].map(|k| t.vertices[4 * v + k] as usize);
    if kind == KIND_NONE as usize {
        return None;
    }
    let x = pos[v];
    let w = &t.ring[off..off + ne];
    let sector = &t.ring[off + ne..off + ne + nf];
    let m: Vec<DVec3> = w.iter().map(|&u| 0.5 * (x + pos[u as usize])).collect();
    let mut c = Vec::with_capacity(nf);
    let mut at = off + ne + nf;
    for i in 0..nf {
        let size = t.ring[at] as usize;
        let mut s = x + pos[w[i] as usize] + pos[w[(i + 1) % ne] as usize];
        for k in 0..size - 3 {
            s += pos[t.ring[at + 1 + k] as usize];
        }
        c.push(s / size as f64);
        at += size - 2;
    }
    if kind == KIND_SMOOTH as usize {
        // The two words after the face records: the f32 bits of the edge-tangent factor and of
        // the transversal factor.
        let scale = f32::from_bits(t.ring[at]) as f64;
        let rho = f32::from_bits(t.ring[at + 1]) as f64;
        return Some(smooth(x, &m, &c, scale, rho));
    }
    // Sectors and sharp edges from the sector words.
    let mut sharp = vec![false; ne];
    for &s in sector {
        let (start, k) = ((s & 0xffff) as usize, (s >> 16) as usize);
        sharp[start] = true;
        sharp[(start + k) % ne] = true;
    }
    let sharp_ids: Vec<usize> = (0..ne).filter(|&j| sharp[j]).collect();
    let p = if kind == KIND_CREASE as usize {
        (x + m[sharp_ids[0]] + m[sharp_ids[1]]) / 3.0
    } else {
        x
    };
    let mut e = vec![DVec3::ZERO; ne];
    for &j in &sharp_ids {
        e[j] = (x + 2.0 * m[j]) / 3.0;
    }
    let mut r_plus = vec![DVec3::ZERO; nf];
    let mut r_minus = vec![DVec3::ZERO; nf];
    let mut cos = vec![0.0; nf];
    for (i, &word) in sector.iter().enumerate() {
        let (s, k) = ((word & 0xffff) as usize, (word >> 16) as usize);
        if s != i {
            continue; // handle each sector once, from its first face
        }
        let tt = (s + k) % ne;
        let alpha = if kind == KIND_CORNER as usize {
            PI / (2.0 * k as f64)
        } else {
            PI / k as f64
        };
        let second = if kind == KIND_CORNER as usize {
            e[tt] - p
        } else if k >= 2 {
            // The sector's cross-boundary factor: word `s` after the face records.
            let factor = f32::from_bits(t.ring[at + s]) as f64;
            factor * crease_tangent(x, &m, &c, s, k, ne) / 3.0
        } else {
            DVec3::ZERO
        };
        for l in 1..k {
            let a = l as f64 * alpha;
            e[(s + l) % ne] = p + a.cos() * (e[s] - p) + a.sin() * second;
        }
        for l in 0..k {
            cos[(s + l) % ne] = alpha.cos();
        }
        for l in 1..k {
            let (j, jp, jn) = ((s + l) % ne, (s + l - 1) % ne, (s + l + 1) % ne);
            let r = (m[jn] - m[jp]) / 3.0 + 2.0 / 3.0 * (c[j] - c[jp]);
            r_plus[j] = r;
            r_minus[jp] = -r;
        }
        r_plus[s] = 2.0 / 3.0 * (m[(s + 1) % ne] - x) + 4.0 / 3.0 * (c[s] - m[s]);
        let last = (s + k - 1) % ne;
        r_minus[last] = 2.0 / 3.0 * (m[last] - x) + 4.0 / 3.0 * (c[last] - m[tt]);
    }
    // The one-sided flag: after the crease words (one per face) or the face records (corners).
    let flag = t.ring[if kind == KIND_CREASE as usize {
        at + nf
    } else {
        at
    }];
    let sides = if flag != 0 {
        (0..nf)
            .map(|j| u8::from(sharp[j]) | (u8::from(sharp[(j + 1) % ne]) << 1))
            .collect()
    } else {
        Vec::new()
    };
    Some(VertexOut {
        p,
        e,
        r_plus,
        r_minus,
        cos,
        sides,
        corner: kind == KIND_CORNER as usize,
    })
}

/// Paper §3.2-3.4 for a closed smooth ring.
fn smooth(x: DVec3, m: &[DVec3], c: &[DVec3], scale: f64, rho: f64) -> VertexOut {
    let n = m.len();
    let nf = n as f64;
    let sum: DVec3 = (0..n).map(|i| m[i] + c[i]).sum();
    let p = (nf - 3.0) / (nf + 5.0) * x + 4.0 / (nf * (nf + 5.0)) * sum;
    let cpn = (PI / nf).cos();
    let sigma = 1.0 / (4.0 + cpn * cpn).sqrt();
    let c2 = (2.0 * PI / nf).cos();
    let lambda = (5.0 + c2 + cpn * (18.0 + 2.0 * c2).sqrt()) / 16.0;
    let e = (0..n)
        .map(|j| {
            let mut q = DVec3::ZERO;
            for i in 0..n {
                let a = 2.0 * PI * ((i + n - j) % n) as f64 / nf;
                q +=
                    (1.0 - sigma * cpn) * a.cos() * m[i] + 2.0 * sigma * (a + PI / nf).cos() * c[i];
            }
            p + 2.0 / 3.0 * (scale * lambda) * (2.0 / nf) * q
        })
        .collect();
    let r: Vec<DVec3> = (0..n)
        .map(|j| {
            rho * ((m[(j + 1) % n] - m[(j + n - 1) % n]) / 3.0
                + 2.0 / 3.0 * (c[j] - c[(j + n - 1) % n]))
        })
        .collect();
    VertexOut {
        p,
        e,
        r_minus: (0..n).map(|j| -r[(j + 1) % n]).collect(),
        r_plus: r,
        cos: vec![c2; n],
        sides: Vec::new(),
        corner: false,
    }
}

/// Cross-boundary tangent of a crease sector (sine mode of the sector's subdivision matrix),
/// written over edge neighbours `w = 2m - v` and face "diagonals" `f = 4c - v - w_i - w_{i+1}`.
fn crease_tangent(x: DVec3, m: &[DVec3], c: &[DVec3], s: usize, k: usize, ne: usize) -> DVec3 {
    let th = PI / k as f64;
    let ct = th.cos();
    let xx = (4.0 * (1.0 + ct) + (16.0 * (1.0 + ct).powi(2) + 128.0 * (1.0 + ct)).sqrt()) / 64.0;
    let b = 1.0 / (16.0 * xx);
    let gamma = (th.sin() * (1.0 / 16.0 + b / 4.0) - (1.0 + 2.0 * b) / (th / 2.0).tan() / 8.0) / xx;
    let w = |i: usize| 2.0 * m[(s + i) % ne] - x;
    let f = |i: usize| 4.0 * c[(s + i) % ne] - x - w(i) - w(i + 1);
    let mut t = gamma * (w(0) - x) + gamma * (w(k) - x);
    for i in 1..k {
        t += (i as f64 * th).sin() * (w(i) - x);
    }
    for i in 0..k {
        t += b * ((i as f64 * th).sin() + ((i + 1) as f64 * th).sin()) * (f(i) - x);
    }
    8.0 * (0.25 + xx) / (3.0 * k as f64) * t
}

/// The TCS stage: control points of patch `k` in the stencil row order (p, e+, e-, f+, f-
/// per corner).
fn tcs_stage(
    t: &GregoryVertexTable,
    outs: &[Option<VertexOut>],
    topo_face: &[u32],
    k: usize,
) -> Vec<DVec3> {
    let n = topo_face.len();
    let d = if n == 4 { 3.0 } else { 4.0 };
    let corner = |i: usize| {
        let o = outs[topo_face[i] as usize].as_ref().unwrap();
        let j = t.patch_offsets[4 * k + i] as usize;
        (o, j)
    };
    let mut rows = Vec::new();
    for i in 0..n {
        let (o, j) = corner(i);
        let (on, jn) = corner((i + 1) % n);
        let (op, jp) = corner((i + n - 1) % n);
        let ep = o.e[j];
        let em = o.e[(j + 1) % o.e.len()];
        let e_next_minus = on.e[(jn + 1) % on.e.len()];
        let e_prev_plus = op.e[jp];
        let (ca, mut cn, mut cp) = (o.cos[j], on.cos[jn], op.cos[jp]);
        let sides = o.sides.get(j).copied().unwrap_or(0);
        if sides == 3 && o.corner {
            // Alone in its corner sector: the B-spline corner's face points.
            (cn, cp) = (0.0, 0.0);
        }
        let fp = (cn * o.p + (d - 2.0 * ca - cn) * ep + 2.0 * ca * e_next_minus + o.r_plus[j]) / d;
        let fm = (cp * o.p + (d - 2.0 * ca - cp) * em + 2.0 * ca * e_prev_plus + o.r_minus[j]) / d;
        // Beside one sharp edge, the corner's other face point.
        let (fp, fm) = match sides {
            1 => (fm, fm),
            2 => (fp, fp),
            _ => (fp, fm),
        };
        rows.extend([o.p, ep, em, fp, fm]);
    }
    rows
}

#[test]
fn flat_tables_reproduce_the_patches() {
    let mut checked = 0;
    for name in [
        "catmark_cube",
        "catmark_nonquads",
        "catmark_smoothtris0",
        "catmark_gregory_test1",
        "catmark_gregory_test6",
        "catmark_gregory_test3",
        "catmark_xord_boundary",
        "catmark_inf_crease0",
        "catmark_inf_crease1",
        "catmark_cubes_infsharp",
        "catmark_pawn",
        "embedded:mixed",
        "embedded:open",
        "embedded:creased",
    ] {
        let mesh = load(name);
        let topo = Topology::new(&mesh).unwrap();
        // `Scaled` also scales the two-face band sectors (`tangents_boundary::sector_band`:
        // gregory_test3, xord_boundary), whose factor words the table keys on the 2-ring.
        for tangents in [
            GregoryTangents::Paper,
            GregoryTangents::Optimal,
            GregoryTangents::Scaled(0.7),
            GregoryTangents::Bands,
        ] {
            let table =
                GregoryVertexTable::with_tangents(&topo, 0..topo.face_count() as u32, tangents);
            let pos = mesh.positions();
            let outs: Vec<Option<VertexOut>> = (0..topo.vertex_count())
                .map(|v| vertex_stage(&table, pos, v))
                .collect();
            for (k, &f) in table.faces.iter().enumerate() {
                let rows = tcs_stage(&table, &outs, topo.face_vertices(f), k);
                let expected: Vec<DVec3> =
                    match gregory_patch_at_with(&topo, pos, f, tangents).unwrap() {
                        GregoryPatch::Quad(q) => (0..4)
                            .flat_map(|i| {
                                [q.p[i], q.e_plus[i], q.e_minus[i], q.f_plus[i], q.f_minus[i]]
                            })
                            .collect(),
                        GregoryPatch::Triangle(q) => (0..3)
                            .flat_map(|i| {
                                [q.p[i], q.e_plus[i], q.e_minus[i], q.f_plus[i], q.f_minus[i]]
                            })
                            .collect(),
                    };
                assert_eq!(rows.len(), expected.len());
                for (r, (a, b)) in rows.iter().zip(&expected).enumerate() {
                    assert!(
                        (*a - *b).length() < 1e-12 * mesh.bbox_diagonal().max(1.0),
                        "{name} face {f} row {r}: {a} vs {b}"
                    );
                }
                checked += 1;
            }
            // Every patch corner has vertex data and a valid offset.
            for (k, &f) in table.faces.iter().enumerate() {
                for (i, &v) in topo.face_vertices(f).iter().enumerate() {
                    assert_ne!(table.vertices[4 * v as usize + 3], KIND_NONE);
                    assert!((table.patch_offsets[4 * k + i] as usize) < topo.vertex_faces(v).len());
                }
            }
        }
    }
    assert!(checked > 1000, "{checked}");
}
