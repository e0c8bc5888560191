//! Writes a jittered copy of an OBJ control mesh: every vertex moved by a seeded pseudo-random
//! vector of length up to `AMOUNT` times its shortest incident edge (uniform in that ball), every
//! other line (faces, `t` tags) copied verbatim, so the tags and topology stay those of the
//! original. The meshes in `assets/jittered/` were made with the defaults (seed 1, amount 0.03):
//!
//! ```sh
//! cargo run --example jitter_mesh -- ../shared/meshes/osd/catmark_cube.obj assets/jittered/cube.obj
//! ```
//!
//! Usage: `jitter_mesh IN.obj OUT.obj [SEED] [AMOUNT]`. Deterministic: the same arguments give the
//! same bytes (splitmix64, no platform-dependent maths but `sqrt`).

use std::fmt::Write as _;

/// splitmix64 (Steele, Lea, Flood 2014): a small seeded generator with a fixed output.
struct SplitMix(u64);

impl SplitMix {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in [-1, 1).
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }

    /// Uniform in the unit ball (rejection sampling).
    fn ball(&mut self) -> [f64; 3] {
        loop {
            let p = [self.unit(), self.unit(), self.unit()];
            if p.iter().map(|x| x * x).sum::<f64>() <= 1.0 {
                return p;
            }
        }
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.len() < 2 {
        return Err("usage: jitter_mesh IN.obj OUT.obj [SEED] [AMOUNT]".into());
    }
    let seed: u64 = args.get(2).map_or(Ok(1), |s| s.parse())?;
    let amount: f64 = args.get(3).map_or(Ok(0.03), |s| s.parse())?;
    let text = std::fs::read_to_string(&args[0])?;
    let mut positions: Vec<[f64; 3]> = Vec::new();
    let mut faces: Vec<Vec<usize>> = Vec::new();
    for line in text.lines() {
        let mut t = line.split_whitespace();
        match t.next() {
            Some("v") => {
                let c: Vec<f64> = t.take(3).map(str::parse).collect::<Result<_, _>>()?;
                positions.push([c[0], c[1], c[2]]);
            }
            Some("f") => {
                let f: Vec<usize> = t
                    .map(|w| w.split('/').next().unwrap_or("").parse::<usize>())
                    .collect::<Result<_, _>>()?;
                faces.push(f.into_iter().map(|i| i - 1).collect());
            }
            _ => {}
        }
    }
    let dist = |a: usize, b: usize| {
        let (p, q) = (positions[a], positions[b]);
        ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt()
    };
    let mut shortest = vec![f64::INFINITY; positions.len()];
    for f in &faces {
        for (i, &a) in f.iter().enumerate() {
            let b = f[(i + 1) % f.len()];
            let d = dist(a, b);
            shortest[a] = shortest[a].min(d);
            shortest[b] = shortest[b].min(d);
        }
    }
    let mut rng = SplitMix(seed);
    let mut out = format!(
        "# {} jittered by `cargo run --example jitter_mesh` (seed {seed}, amount {amount}):\n\
         # each vertex moved by up to {amount} x its shortest incident edge\n",
        std::path::Path::new(&args[0])
            .file_name()
            .map_or(String::new(), |n| n.to_string_lossy().into_owned())
    );
    let mut v = 0;
    for line in text.lines() {
        if line.split_whitespace().next() == Some("v") {
            let d = rng.ball();
            let r = if shortest[v].is_finite() {
                amount * shortest[v]
            } else {
                0.0
            };
            let p = positions[v];
            writeln!(
                out,
                "v {:.9} {:.9} {:.9}",
                p[0] + r * d[0],
                p[1] + r * d[1],
                p[2] + r * d[2]
            )?;
            v += 1;
        } else {
            writeln!(out, "{line}")?;
        }
    }
    std::fs::write(&args[1], out)?;
    Ok(())
}
