//! Displacement along the normal on the CPU: the two displacement functions the evaluation
//! stages apply (`glsl/common/displace.glsl`), for tests and for users reproducing displaced
//! points without a GPU.
//!
//! * Procedural (`--displacement procedural`): `d(p) = (sin(5x + 1) + sin(5y + 2) + sin(5z +
//!   3)) / 3` lies in [-1, 1] and is smooth, and it depends on the position alone (not on a
//!   face's parameterisation), so it is continuous across faces; the displaced point is `p +
//!   scale * d(p) * n` with the unit limit normal `n`.
//! * Map (`--displacement FILE.png`, [`DisplacementMap`]): a scalar image sampled at the
//!   surface's face-varying texture coordinate `(s, t)` (OBJ `vt`, [`crate::mesh::uv`]):
//!   `d = value - 0.5` with `value` the first channel normalised to [0, 1] (8 or 16 bit), so
//!   mid-grey leaves the surface where it is and `d` lies in [-0.5, 0.5]. Sampled as the GPU
//!   samples a combined image sampler with linear filtering and repeat addressing at level 0:
//!   texel `(i, j)` is centred at `((i + 0.5) / w, (j + 0.5) / h)`, row 0 of the image at `t`
//!   near 0 (the PNG's top row), bilinear between the four nearest centres, wrapping at the
//!   borders ([`DisplacementMap::sample`]). The displaced point is `p + scale * d(s, t) * n`.
//!   Positions are watertight where the faces share their `vt`: the coordinates are bitwise
//!   equal there (texcoord.glsl), so the sampled values and the displaced points are too.
//!   The shading normal is `n` tilted by the surface gradient of `d`,
//!   `normalize(n - scale grad_surf d)` ([`DisplacementMap::shading_normal`]): the exact normal
//!   of `p + scale d n` without the surface's own curvature term `scale d dn` (first order).
//!   `grad_surf d` comes from the map's `(s, t)`-gradient (the analytic derivative of the
//!   bilinear filter, [`DisplacementMap::sample`]) by the chain rule through the texture
//!   coordinates' Jacobian `d(s, t)/d(u, v)` and the surface's partials `dP/du`, `dP/dv`
//!   ([`surface_gradient`]). The shading normal does not move the point: positions stay
//!   watertight; normals agree across edges only to a tolerance (each side's partials and
//!   texture-coordinate Jacobian are its own).

use std::path::Path;

use glam::{DVec2, DVec3};

use crate::{Error, Result};

/// Offsets of the three sine waves.
const PHASE: DVec3 = DVec3::new(1.0, 2.0, 3.0);
/// Angular frequency of the waves (radians per world unit).
const FREQUENCY: f64 = 5.0;

/// `d(p)` and its gradient.
pub fn procedural(p: DVec3) -> (f64, DVec3) {
    let a = FREQUENCY * p + PHASE;
    let d = (a.x.sin() + a.y.sin() + a.z.sin()) / 3.0;
    let grad = DVec3::new(a.x.cos(), a.y.cos(), a.z.cos()) * (FREQUENCY / 3.0);
    (d, grad)
}

/// The displaced point `p + scale d(p) n` and its shading normal: `n` tilted by the tangential
/// part of `scale grad d` (first order; the surface's curvature term is left out), as the
/// shaders compute it.
pub fn displaced(p: DVec3, n: DVec3, scale: f64) -> (DVec3, DVec3) {
    let (d, g) = procedural(p);
    let tangential = g - g.dot(n) * n;
    (p + scale * d * n, (n - scale * tangential).normalize())
}

/// The surface gradient of a scalar at a point with unit normal `n` and partials `ta = dP/da`,
/// `tb = dP/db`, from its derivatives `dd = (dd/da, dd/db)`: the vector `g` perpendicular to
/// `n` with `g . ta = dd/da`, `g . tb = dd/db`. Zero where the partials degenerate
/// (`|n . ta x tb| <= 1e-6 |ta| |tb|`), as `glsl/common/displace.glsl` computes it.
pub fn surface_gradient(n: DVec3, ta: DVec3, tb: DVec3, dd: DVec2) -> DVec3 {
    let det = n.dot(ta.cross(tb));
    if det.abs() <= 1e-6 * ta.length() * tb.length() || !det.is_finite() {
        return DVec3::ZERO;
    }
    (tb.cross(n) * dd.x + n.cross(ta) * dd.y) / det
}

/// Texels of a [`DisplacementMap`]: the first channel, row-major from the image's top row.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Texels {
    /// 8-bit values (`value = texel / 255`).
    U8(Vec<u8>),
    /// 16-bit values (`value = texel / 65535`).
    U16(Vec<u16>),
}

/// A scalar displacement map (module docs for the convention): decoded texels an engine can
/// pass directly ([`Self::from_u8`], [`Self::from_u16`]) or a PNG read by [`Self::load`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DisplacementMap {
    width: u32,
    height: u32,
    texels: Texels,
    /// Where the texels came from (file path or "texels"), for error messages.
    source: String,
}

impl DisplacementMap {
    fn new(width: u32, height: u32, texels: Texels, len: usize) -> Result<DisplacementMap> {
        if width == 0 || height == 0 || len as u64 != u64::from(width) * u64::from(height) {
            return Err(Error::SizeMismatch {
                what: "displacement map texels (width x height, at least 1 x 1)",
                expected: u64::from(width) * u64::from(height),
                found: len as u64,
            });
        }
        Ok(DisplacementMap {
            width,
            height,
            texels,
            source: "texels".into(),
        })
    }

    /// A map of `width x height` 8-bit texels, row-major (row 0 at `t` near 0).
    pub fn from_u8(width: u32, height: u32, texels: Vec<u8>) -> Result<DisplacementMap> {
        let len = texels.len();
        Self::new(width, height, Texels::U8(texels), len)
    }

    /// A map of `width x height` 16-bit texels, row-major (row 0 at `t` near 0).
    pub fn from_u16(width: u32, height: u32, texels: Vec<u16>) -> Result<DisplacementMap> {
        let len = texels.len();
        Self::new(width, height, Texels::U16(texels), len)
    }

    /// Reads an image file (PNG; JPEG also decodes): its first channel (grey, or red), 16-bit
    /// images as 16 bit, everything else as 8 bit. A missing, unreadable or non-image file is
    /// an error naming the path.
    pub fn load(path: &Path) -> Result<DisplacementMap> {
        let shown = path.display().to_string();
        let img = image::ImageReader::open(path)
            .map_err(|e| Error::Io {
                path: shown.clone(),
                message: e.to_string(),
            })?
            .with_guessed_format()
            .map_err(|e| Error::Io {
                path: shown.clone(),
                message: e.to_string(),
            })?
            .decode()
            .map_err(|e| Error::Image {
                path: shown.clone(),
                message: e.to_string(),
            })?;
        let (w, h) = (img.width(), img.height());
        let sixteen = matches!(
            img.color(),
            image::ColorType::L16
                | image::ColorType::La16
                | image::ColorType::Rgb16
                | image::ColorType::Rgba16
        );
        let mut map = if sixteen {
            Self::from_u16(w, h, first_of_four(img.to_rgba16().into_raw()))?
        } else if img.color().channel_count() <= 2 {
            Self::from_u8(w, h, img.to_luma8().into_raw())?
        } else {
            Self::from_u8(w, h, first_of_four(img.to_rgba8().into_raw()))?
        };
        map.source = shown;
        Ok(map)
    }

    /// Width and height in texels.
    pub fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// The texels.
    pub fn texels(&self) -> &Texels {
        &self.texels
    }

    /// Where the map came from: its path, or `"texels"`.
    pub fn source(&self) -> &str {
        &self.source
    }

    /// Texel `(i, j)` (column, row) normalised to [0, 1].
    pub fn value(&self, i: u32, j: u32) -> f64 {
        let k = (j * self.width + i) as usize;
        match &self.texels {
            Texels::U8(t) => f64::from(t[k]) / 255.0,
            Texels::U16(t) => f64::from(t[k]) / 65535.0,
        }
    }

    /// The largest difference between two texels that are neighbours (with wrap-around): the
    /// most a filtered value can change over one texel.
    pub fn largest_step(&self) -> f64 {
        let (w, h) = (self.width, self.height);
        let mut step = 0.0f64;
        for j in 0..h {
            for i in 0..w {
                let v = self.value(i, j);
                step = step
                    .max((v - self.value((i + 1) % w, j)).abs())
                    .max((v - self.value(i, (j + 1) % h)).abs());
            }
        }
        step
    }

    /// The filtered value at `(s, t)` as a linear-filtered, repeat-addressed sampler reads
    /// level 0 (module docs), and its derivatives by `s` and `t` (of the bilinear piece
    /// containing the point).
    pub fn sample(&self, st: DVec2) -> (f64, DVec2) {
        let (w, h) = (f64::from(self.width), f64::from(self.height));
        let x = st.x * w - 0.5;
        let y = st.y * h - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (a, b) = (x - x0, y - y0);
        let wrap = |k: f64, n: u32| k.rem_euclid(f64::from(n)) as u32;
        let (i0, i1) = (wrap(x0, self.width), wrap(x0 + 1.0, self.width));
        let (j0, j1) = (wrap(y0, self.height), wrap(y0 + 1.0, self.height));
        let (v00, v10) = (self.value(i0, j0), self.value(i1, j0));
        let (v01, v11) = (self.value(i0, j1), self.value(i1, j1));
        let value = (1.0 - b) * ((1.0 - a) * v00 + a * v10) + b * ((1.0 - a) * v01 + a * v11);
        let ds = ((1.0 - b) * (v10 - v00) + b * (v11 - v01)) * w;
        let dt = ((1.0 - a) * (v01 - v00) + a * (v11 - v10)) * h;
        (value, DVec2::new(ds, dt))
    }

    /// The displacement `d = value - 0.5` at `(s, t)`.
    pub fn displacement(&self, st: DVec2) -> f64 {
        self.sample(st).0 - 0.5
    }

    /// The displaced point `p + scale d(s, t) n`.
    pub fn displaced(&self, p: DVec3, n: DVec3, st: DVec2, scale: f64) -> DVec3 {
        p + scale * self.displacement(st) * n
    }

    /// The shading normal of the displaced surface at a point with unit normal `n`, partials
    /// `du = dP/du`, `dv = dP/dv` and texture coordinate `st` whose Jacobian is
    /// `st_jac = [d(s, t)/du, d(s, t)/dv]`: `normalize(n - scale grad_surf d)` (module docs;
    /// `n` itself where the partials degenerate).
    pub fn shading_normal(
        &self,
        n: DVec3,
        [du, dv]: [DVec3; 2],
        st: DVec2,
        st_jac: [DVec2; 2],
        scale: f64,
    ) -> DVec3 {
        let g = self.sample(st).1;
        let dd = DVec2::new(g.dot(st_jac[0]), g.dot(st_jac[1]));
        (n - scale * surface_gradient(n, du, dv, dd)).normalize()
    }
}

/// The first of every four values (the red channel of RGBA texels).
fn first_of_four<T: Copy>(values: Vec<T>) -> Vec<T> {
    values.into_iter().step_by(4).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gradient_matches_finite_differences() {
        let p = DVec3::new(0.3, -0.7, 1.1);
        let (_, g) = procedural(p);
        let h = 1e-6;
        for (k, e) in [DVec3::X, DVec3::Y, DVec3::Z].into_iter().enumerate() {
            let fd = (procedural(p + h * e).0 - procedural(p - h * e).0) / (2.0 * h);
            assert!((fd - g[k]).abs() < 1e-8, "axis {k}: {fd} vs {}", g[k]);
        }
    }

    #[test]
    fn displaces_along_the_normal_within_bounds() {
        let (p, n) = (DVec3::new(0.1, 0.2, 0.3), DVec3::Z);
        let (q, m) = displaced(p, n, 0.5);
        assert!((q - p).cross(n).length() < 1e-15, "moved along n only");
        assert!((q - p).length() <= 0.5 + 1e-15);
        assert!((m.length() - 1.0).abs() < 1e-12);
        assert_eq!(displaced(p, n, 0.0), (p, n));
    }

    fn map() -> DisplacementMap {
        // 3 x 2 texels, row 0 first.
        DisplacementMap::from_u8(3, 2, vec![0, 51, 102, 153, 204, 255]).unwrap()
    }

    #[test]
    fn map_samples_texel_centres_and_wraps() {
        let m = map();
        for j in 0..2 {
            for i in 0..3 {
                let st = DVec2::new((f64::from(i) + 0.5) / 3.0, (f64::from(j) + 0.5) / 2.0);
                assert!((m.sample(st).0 - m.value(i, j)).abs() < 1e-12);
            }
        }
        // (0, 0) lies between the four corner texels (repeat addressing).
        let corners = (m.value(0, 0) + m.value(2, 0) + m.value(0, 1) + m.value(2, 1)) / 4.0;
        assert!((m.sample(DVec2::ZERO).0 - corners).abs() < 1e-12);
        assert!((m.sample(DVec2::new(1.0, -1.0)).0 - corners).abs() < 1e-12);
        assert_eq!(m.value(2, 1), 1.0);
        assert!((m.displacement(DVec2::new(2.5 / 3.0, 0.75)) - 0.5).abs() < 1e-12);
        assert!((m.largest_step() - 153.0 / 255.0).abs() < 1e-12);
        let wide = DisplacementMap::from_u16(1, 1, vec![65535]).unwrap();
        assert_eq!(wide.sample(DVec2::new(0.3, 0.9)).0, 1.0);
    }

    #[test]
    fn map_derivatives_match_finite_differences() {
        let m = map();
        let h = 1e-7;
        for st in [
            DVec2::new(0.4, 0.6),
            DVec2::new(0.05, 0.1),
            DVec2::new(0.9, 0.95),
        ] {
            let (_, g) = m.sample(st);
            let fd_s = (m.sample(st + DVec2::X * h).0 - m.sample(st - DVec2::X * h).0) / (2.0 * h);
            let fd_t = (m.sample(st + DVec2::Y * h).0 - m.sample(st - DVec2::Y * h).0) / (2.0 * h);
            assert!(
                (g.x - fd_s).abs() < 1e-5 && (g.y - fd_t).abs() < 1e-5,
                "{st}: {g} vs ({fd_s}, {fd_t})"
            );
        }
    }

    #[test]
    fn surface_gradient_reproduces_the_directional_derivatives() {
        // A sheared, non-orthogonal frame: g is tangent and its projections are the inputs.
        let n = DVec3::new(0.2, -0.3, 1.0).normalize();
        let ta = DVec3::new(1.0, 0.1, 0.2);
        let ta = ta - ta.dot(n) * n;
        let tb = DVec3::new(0.4, 1.3, 0.0);
        let tb = tb - tb.dot(n) * n;
        let dd = DVec2::new(0.7, -1.9);
        let g = surface_gradient(n, ta, tb, dd);
        assert!(g.dot(n).abs() < 1e-12);
        assert!((g.dot(ta) - dd.x).abs() < 1e-12 && (g.dot(tb) - dd.y).abs() < 1e-12);
        // Flipping the normal keeps the gradient; parallel partials give none.
        assert!((surface_gradient(-n, ta, tb, dd) - g).length() < 1e-12);
        assert_eq!(surface_gradient(n, ta, 2.0 * ta, dd), DVec3::ZERO);
        // The plane z = 0 with st = (x, y) and a ramp of 1/3 per texel (d/ds = 4/3 between the
        // first and last texel centres): the tilted plane z = 0.3 d(x).
        let ramp = DisplacementMap::from_u8(4, 1, vec![0, 85, 170, 255]).unwrap();
        let frame = [DVec3::X, DVec3::Y];
        let (st, jac) = (DVec2::new(0.4, 0.7), [DVec2::X, DVec2::Y]);
        let tilted = ramp.shading_normal(DVec3::Z, frame, st, jac, 0.3);
        let want = DVec3::new(-0.3 * 4.0 / 3.0, 0.0, 1.0).normalize();
        assert!((tilted - want).length() < 1e-12, "{tilted} vs {want}");
        let flat = DisplacementMap::from_u8(4, 1, vec![9; 4]).unwrap();
        assert_eq!(flat.shading_normal(DVec3::Z, frame, st, jac, 0.3), DVec3::Z);
    }

    #[test]
    fn map_texels_must_fill_the_size() {
        assert!(DisplacementMap::from_u8(2, 2, vec![0; 3]).is_err());
        assert!(DisplacementMap::from_u16(0, 0, vec![]).is_err());
    }
}
