//! Regenerates `patch::gregory::tangents::OPTIMAL_SCALE`: the least-squares edge-tangent factor
//! per valence (module docs of `tessera::patch::gregory::tangents`), and
//! `patch::gregory::tangents_boundary::CREASE_SCALE`, the cross-boundary factor per crease sector
//! size, printed as the Rust arrays to paste, with the fitted RMS normal distance at the paper's
//! factor (1) and at the fitted one.
//!
//! ```sh
//! cargo run --release --example gregory_tangent_table
//! ```

use tessera::patch::gregory::tangent_fit::{
    band_fit_error, band_fit_terms, crease_fit_terms, fit_error, fit_scale, fit_terms,
    least_squares_scale,
};
use tessera::patch::gregory::tangents::MAX_FITTED_VALENCE;
use tessera::patch::gregory::tangents_boundary::MAX_FITTED_CREASE_SECTOR;
use tessera::patch::gregory::GregoryTangents;

fn main() -> tessera::Result<()> {
    let mut table = Vec::new();
    println!("valence  s*        RMS paper   RMS fitted");
    for n in 3..=MAX_FITTED_VALENCE {
        if n == 4 {
            table.push(1.0);
            println!("{n:>7}  1 (fixed: bicubic reproduction)");
            continue;
        }
        let t = fit_terms(n)?;
        let s = least_squares_scale(&t);
        println!(
            "{n:>7}  {s:.6}  {:.4e}  {:.4e}",
            fit_error(&t, 1.0).sqrt(),
            fit_error(&t, s).sqrt()
        );
        table.push(s);
    }
    println!("\nbeyond the table (the fallback GregoryTangents::scale uses):");
    for n in [96, 128, 256, 360] {
        let s = fit_scale(n)?;
        println!(
            "{n:>7}  fit {s:.6}  fallback {:.6}",
            GregoryTangents::Optimal.scale(n)
        );
    }
    let entries: Vec<String> = table.iter().map(|s| format!("{s:.6}")).collect();
    println!(
        "\npub const OPTIMAL_SCALE: [f64; MAX_FITTED_VALENCE - 2] = [\n    {},\n];",
        entries.join(", ")
    );
    println!("\ncrease sector faces  s*        RMS paper   RMS fitted");
    let mut crease = Vec::new();
    for k in 3..=MAX_FITTED_CREASE_SECTOR {
        let t = crease_fit_terms(k)?;
        let s = least_squares_scale(&t);
        println!(
            "{k:>19}  {s:.6}  {:.4e}  {:.4e}",
            fit_error(&t, 1.0).sqrt(),
            fit_error(&t, s).sqrt()
        );
        crease.push(format!("{s:.6}"));
    }
    println!(
        "\npub const CREASE_SCALE: [f64; MAX_FITTED_CREASE_SECTOR - 2] = [\n    {},\n];",
        crease.join(", ")
    );
    println!("\nband of k faces  s_c       s_2       RMS paper   RMS fitted");
    let (mut centre, mut two) = (Vec::new(), Vec::new());
    for k in 3..=MAX_FITTED_CREASE_SECTOR {
        let t = band_fit_terms(k)?;
        let [_, ab, ac, bb, bc, cc] = t;
        let det = bb * cc - bc * bc;
        let (sc, s2) = ((-ab * cc + ac * bc) / det, (-ac * bb + ab * bc) / det);
        println!(
            "{k:>15}  {sc:.6}  {s2:.6}  {:.4e}  {:.4e}",
            band_fit_error(&t, 1.0, 1.0).sqrt(),
            band_fit_error(&t, sc, s2).sqrt()
        );
        centre.push(format!("{sc:.6}"));
        two.push(format!("{s2:.6}"));
    }
    println!(
        "\npub const BAND_CENTRE_SCALE: [f64; MAX_FITTED_CREASE_SECTOR - 2] = [\n    {},\n];",
        centre.join(", ")
    );
    println!(
        "\npub const BAND_TWO_SCALE: [f64; MAX_FITTED_CREASE_SECTOR - 2] = [\n    {},\n];",
        two.join(", ")
    );
    Ok(())
}
