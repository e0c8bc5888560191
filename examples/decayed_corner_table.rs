//! Regenerates `patch::gregory::tangents::DECAYED_CORNER_SCALE`: the least-squares edge-tangent
//! factor of the adaptive end caps at a decayed corner of each valence
//! (`tessera::patch::adaptive::decayed_fit`), printed beside the smooth end caps' factor with
//! the root sum of squared normal distances at both, then as the Rust array to paste.
//!
//! ```sh
//! cargo run --release --example decayed_corner_table [FIRST LAST]
//! ```

use tessera::patch::adaptive::decayed_fit::decayed_fit_terms;
use tessera::patch::gregory::tangent_fit::{fit_error, least_squares_scale};
use tessera::patch::gregory::GregoryTangents;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<usize> = std::env::args()
        .skip(1)
        .map(|a| a.parse())
        .collect::<Result<_, _>>()?;
    let (first, last) = match args[..] {
        [] => (7, 24),
        [a, b] if 3 <= a && a <= b => (a, b),
        _ => return Err("usage: decayed_corner_table [FIRST LAST] (3 <= FIRST <= LAST)".into()),
    };
    let mut table = Vec::new();
    println!("valence  s*      rss at s*   smooth s  rss at smooth s");
    for n in (first..=last).filter(|&n| n != 4) {
        let t = decayed_fit_terms(n)?;
        let s = least_squares_scale(&t);
        let smooth = GregoryTangents::EndCaps.ring_factors(&vec![4; n]).tangent;
        let rss = |s: f64| fit_error(&t, s).max(0.0).sqrt();
        println!(
            "{n:>7}  {s:.4}  {:.4e}  {smooth:.4}    {:.4e}",
            rss(s),
            rss(smooth)
        );
        table.push((n, s));
    }
    println!(
        "\npub const DECAYED_CORNER_SCALE: [(usize, f64); {}] = [",
        table.len()
    );
    for (n, s) in table {
        println!("    ({n}, {s:.4}),");
    }
    println!("];");
    Ok(())
}
