//! Golden images in `tests/golden/`: a render passes when at most 1% of its pixels differ from
//! the golden by more than 32/255 in a channel (rasterisation differences along silhouettes
//! between drivers). On a failure the actual and difference images are written to
//! `<target>/tmp/golden-failures/` and named in the panic. `TESSERA_UPDATE_GOLDEN=1` rewrites
//! the goldens instead of comparing (look at them before committing).

use std::path::PathBuf;

use image::RgbaImage;
use tessera::render::{compare_images, CompareThreshold};

const THRESHOLD: CompareThreshold = CompareThreshold {
    channel_tolerance: 32,
    max_differing_fraction: 0.01,
};

/// The golden image file of `name`.
pub fn golden_path(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("tests/golden/{name}.png"))
}

/// Whether the goldens are to be rewritten (`TESSERA_UPDATE_GOLDEN=1`).
pub fn update_requested() -> bool {
    std::env::var("TESSERA_UPDATE_GOLDEN").as_deref() == Ok("1")
}

/// Compares `actual` with `tests/golden/<name>.png`, or rewrites it when [`update_requested`].
pub fn check_golden(name: &str, actual: &RgbaImage) {
    let path = golden_path(name);
    if update_requested() {
        actual.save(&path).expect("write golden");
        eprintln!("updated {}", path.display());
        return;
    }
    let expected = image::open(&path)
        .unwrap_or_else(|e| {
            panic!(
                "golden {} unreadable ({e}); TESSERA_UPDATE_GOLDEN=1 creates it",
                path.display()
            )
        })
        .to_rgba8();
    let report = compare_images(&expected, actual, &THRESHOLD).unwrap();
    if !report.passes(&THRESHOLD) {
        let dir = super::out_dir("golden-failures");
        let a = dir.join(format!("{name}.actual.png"));
        let d = dir.join(format!("{name}.diff.png"));
        actual.save(&a).unwrap();
        report.diff_image.save(&d).unwrap();
        panic!(
            "golden {name}: {} of {} pixels ({:.3}%) differ by more than {} (max diff {}), allowed \
             {:.3}%\n  expected: {}\n  actual:   {}\n  diff:     {}",
            report.differing,
            report.total,
            100.0 * report.differing_fraction(),
            THRESHOLD.channel_tolerance,
            report.max_channel_diff,
            100.0 * THRESHOLD.max_differing_fraction,
            path.display(),
            a.display(),
            d.display()
        );
    }
}
