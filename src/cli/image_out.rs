//! Image files written by the CLI: the format is the one the `--out` extension names (`.png`, or
//! `.jpg` / `.jpeg`), any other extension is refused before rendering, and a failed write says
//! it could not write (naming the file and the reason, e.g. a missing directory).

use std::path::Path;

use image::{ImageFormat, RgbaImage};
use tessera::{Error, Result};

/// The format of `path` from its extension (case-insensitive), or the error naming it.
pub fn format_of(path: &Path) -> Result<ImageFormat> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("png") => Ok(ImageFormat::Png),
        Some("jpg" | "jpeg") => Ok(ImageFormat::Jpeg),
        Some(other) => Err(Error::Invalid(format!(
            "--out {}: unsupported image format `.{other}` (use .png, .jpg or .jpeg)",
            path.display()
        ))),
        None => Err(Error::Invalid(format!(
            "--out {}: no file extension (use .png, .jpg or .jpeg)",
            path.display()
        ))),
    }
}

/// Checks, before any work, that `path` names a supported format in an existing directory.
pub fn check_out(path: &Path) -> Result<ImageFormat> {
    let format = format_of(path)?;
    let dir = path.parent().filter(|d| !d.as_os_str().is_empty());
    if let Some(dir) = dir {
        if !dir.is_dir() {
            return Err(Error::Write {
                path: path.display().to_string(),
                message: format!("the directory {} does not exist", dir.display()),
            });
        }
    }
    Ok(format)
}

/// Writes `img` to `path` in the format its extension names (JPEG without alpha).
pub fn save(img: &RgbaImage, path: &Path) -> Result<()> {
    let format = format_of(path)?;
    let err = |e: image::ImageError| Error::Write {
        path: path.display().to_string(),
        message: match e {
            image::ImageError::IoError(io) => io.to_string(),
            e => e.to_string(),
        },
    };
    match format {
        ImageFormat::Jpeg => image::DynamicImage::ImageRgba8(img.clone())
            .to_rgb8()
            .save_with_format(path, ImageFormat::Jpeg)
            .map_err(err),
        f => img.save_with_format(path, f).map_err(err),
    }
}
