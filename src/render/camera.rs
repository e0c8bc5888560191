//! Camera: an orbit around the model's bounding-box centre, perspective projection into Vulkan
//! clip space (x right, y down, depth 0..1).

use glam::{DMat4, DVec3, Mat4};

use crate::{Error, Result};

/// How the camera is placed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CameraSpec {
    /// Frames the bounding box from a fixed three-quarter view (azimuth 35°, elevation 25°).
    Auto,
    /// Orbit around the bounding-box centre: angles in degrees, distance in model units.
    Orbit {
        /// Rotation about +y, 0 looks from +z towards -z.
        azimuth_deg: f64,
        /// Angle above the xz plane.
        elevation_deg: f64,
        /// Distance from the bounding-box centre.
        distance: f64,
    },
}

impl CameraSpec {
    /// Parses `auto` or `az,el,dist` (degrees, degrees, model units).
    pub fn parse(text: &str) -> Result<CameraSpec> {
        let t = text.trim();
        if t.eq_ignore_ascii_case("auto") {
            return Ok(CameraSpec::Auto);
        }
        let parts: Vec<&str> = t.split(',').map(str::trim).collect();
        let bad = || Error::Invalid(format!("camera `{text}`: expected `auto` or `az,el,dist`"));
        if parts.len() != 3 {
            return Err(bad());
        }
        let mut v = [0.0f64; 3];
        for (slot, p) in v.iter_mut().zip(&parts) {
            *slot = p.parse::<f64>().map_err(|_| bad())?;
            if !slot.is_finite() {
                return Err(bad());
            }
        }
        if v[2] <= 0.0 {
            return Err(Error::Invalid(format!(
                "camera `{text}`: distance must be positive"
            )));
        }
        Ok(CameraSpec::Orbit {
            azimuth_deg: v[0],
            elevation_deg: v[1],
            distance: v[2],
        })
    }
}

/// Which world axis points up on screen.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum UpAxis {
    /// +y is up (the orbit's azimuth 0 looks from +z).
    Y,
    /// +z is up, as in the OpenSubdiv regression shapes and the embedded meshes (azimuth 0 looks
    /// from -y).
    #[default]
    Z,
}

impl UpAxis {
    /// The up vector.
    pub fn vector(self) -> DVec3 {
        match self {
            UpAxis::Y => DVec3::Y,
            UpAxis::Z => DVec3::Z,
        }
    }

    /// Direction from the target to the eye for an orbit (radians).
    fn orbit_direction(self, az: f64, el: f64) -> DVec3 {
        match self {
            UpAxis::Y => DVec3::new(el.cos() * az.sin(), el.sin(), el.cos() * az.cos()),
            UpAxis::Z => DVec3::new(el.cos() * az.sin(), -el.cos() * az.cos(), el.sin()),
        }
    }

    /// Parses `y` or `z`.
    pub fn parse(text: &str) -> Result<UpAxis> {
        match text.trim() {
            "y" | "Y" => Ok(UpAxis::Y),
            "z" | "Z" => Ok(UpAxis::Z),
            _ => Err(Error::Invalid(format!(
                "up axis `{text}`: expected `y` or `z`"
            ))),
        }
    }
}

/// Vertical field of view of every camera, in degrees.
pub const FOV_Y_DEG: f64 = 35.0;

/// A placed perspective camera.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    /// Eye position (world).
    pub eye: DVec3,
    /// Point looked at (world).
    pub target: DVec3,
    /// Vertical field of view, radians.
    pub fov_y: f64,
    /// Width / height of the image.
    pub aspect: f64,
    /// Near plane distance.
    pub near: f64,
    /// Far plane distance.
    pub far: f64,
    /// World up direction.
    pub up: DVec3,
}

impl Camera {
    /// Places the camera for the bounding box `(lo, hi)` of the model and an image aspect ratio
    /// (+y up; see [`Camera::frame_oriented`]).
    pub fn frame(spec: CameraSpec, lo: DVec3, hi: DVec3, aspect: f64) -> Camera {
        Self::frame_points(spec, lo, hi, &[], aspect)
    }

    /// As [`Camera::frame_points`] with +y up.
    pub fn frame_points(
        spec: CameraSpec,
        lo: DVec3,
        hi: DVec3,
        points: &[DVec3],
        aspect: f64,
    ) -> Camera {
        Self::frame_oriented(spec, UpAxis::Y, lo, hi, points, aspect)
    }

    /// Places the camera for the bounding box `(lo, hi)` with `up` pointing up on screen; `Auto`
    /// fits `points` (samples of the surface inside the box) to the frame instead of the box
    /// corners when any are given.
    pub fn frame_oriented(
        spec: CameraSpec,
        up: UpAxis,
        lo: DVec3,
        hi: DVec3,
        points: &[DVec3],
        aspect: f64,
    ) -> Camera {
        let centre = (lo + hi) * 0.5;
        let radius = ((hi - lo).length() * 0.5).max(1e-6);
        let fov_y = FOV_Y_DEG.to_radians();
        let (az, el, dist) = match spec {
            CameraSpec::Auto => {
                // Fit the bounding sphere in the narrower of the two fields of view.
                let half = (fov_y * 0.5).min((aspect * (fov_y * 0.5).tan()).atan());
                (35.0f64, 25.0f64, radius / half.sin() * 1.02)
            }
            CameraSpec::Orbit {
                azimuth_deg,
                elevation_deg,
                distance,
            } => (azimuth_deg, elevation_deg, distance),
        };
        let (az, el) = (az.to_radians(), el.to_radians());
        let dir = up.orbit_direction(az, el);
        let place = |dist: f64| Camera {
            eye: centre + dir * dist,
            target: centre,
            fov_y,
            aspect,
            near: (dist - 2.0 * radius).max(dist * 1e-3),
            far: dist + 2.0 * radius,
            up: up.vector(),
        };
        let mut cam = place(dist);
        if spec == CameraSpec::Auto {
            // The bounding sphere is conservative: move in until the box's projected corners
            // fill 85% of the narrower half-extent (a few fixed-point steps; always in front).
            let corners: Vec<DVec3> = (0..8)
                .map(|i| {
                    DVec3::new(
                        if i & 1 == 0 { lo.x } else { hi.x },
                        if i & 2 == 0 { lo.y } else { hi.y },
                        if i & 4 == 0 { lo.z } else { hi.z },
                    )
                })
                .collect();
            let fit = if points.is_empty() {
                &corners[..]
            } else {
                points
            };
            for _ in 0..4 {
                let m = cam.projected_extent(fit);
                let d = ((cam.eye - centre).length() * m / 0.85).max(radius * 1.05);
                cam = place(d);
            }
        }
        cam
    }

    /// Largest |x| or |y| in normalised device coordinates over `points`.
    fn projected_extent(&self, points: &[DVec3]) -> f64 {
        let m = self.view_proj().as_dmat4();
        points.iter().fold(0.0f64, |e, p| {
            let c = m * p.extend(1.0);
            let w = c.w.max(1e-9);
            e.max((c.x / w).abs()).max((c.y / w).abs())
        })
    }

    /// World -> Vulkan clip space (right-handed view, y flipped for Vulkan's y-down clip space).
    pub fn view_proj(&self) -> Mat4 {
        let forward = (self.target - self.eye).normalize();
        // Avoid a degenerate basis when looking straight up or down.
        let up = if forward.cross(self.up).length() < 1e-9 {
            self.up.any_orthonormal_vector()
        } else {
            self.up
        };
        let view = DMat4::look_at_rh(self.eye, self.target, up);
        let mut proj = DMat4::perspective_rh(self.fov_y, self.aspect, self.near, self.far);
        proj.y_axis.y = -proj.y_axis.y;
        (proj * view).as_mat4()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parse_camera() {
        assert_eq!(CameraSpec::parse("auto").unwrap(), CameraSpec::Auto);
        assert_eq!(
            CameraSpec::parse("30, -10,5").unwrap(),
            CameraSpec::Orbit {
                azimuth_deg: 30.0,
                elevation_deg: -10.0,
                distance: 5.0
            }
        );
        assert!(CameraSpec::parse("1,2").is_err());
        assert!(CameraSpec::parse("1,2,0").is_err());
        assert!(CameraSpec::parse("a,b,c").is_err());
    }

    #[test]
    fn target_projects_to_centre_and_up_is_up() {
        let cam = Camera::frame(
            CameraSpec::Orbit {
                azimuth_deg: 0.0,
                elevation_deg: 0.0,
                distance: 10.0,
            },
            DVec3::splat(-1.0),
            DVec3::splat(1.0),
            1.0,
        );
        let m = cam.view_proj();
        let c = m * glam::Vec4::new(0.0, 0.0, 0.0, 1.0);
        assert!((c.x / c.w).abs() < 1e-6 && (c.y / c.w).abs() < 1e-6);
        let z = c.z / c.w;
        assert!(z > 0.0 && z < 1.0, "depth {z}");
        // +y in the world is up on screen: negative clip y in Vulkan.
        let top = m * glam::Vec4::new(0.0, 1.0, 0.0, 1.0);
        assert!(top.y / top.w < 0.0);
        // Looking from +z, +x is on the right.
        let right = m * glam::Vec4::new(1.0, 0.0, 0.0, 1.0);
        assert!(right.x / right.w > 0.0);
    }

    #[test]
    fn auto_frames_the_whole_box() {
        let (lo, hi) = (DVec3::new(-3.0, -1.0, -2.0), DVec3::new(5.0, 2.0, 1.0));
        let cam = Camera::frame(CameraSpec::Auto, lo, hi, 1.5);
        let m = cam.view_proj();
        let mut extent = 0.0f32;
        for i in 0..8 {
            let p = DVec3::new(
                if i & 1 == 0 { lo.x } else { hi.x },
                if i & 2 == 0 { lo.y } else { hi.y },
                if i & 4 == 0 { lo.z } else { hi.z },
            );
            let c = m * p.as_vec3().extend(1.0);
            let (x, y, z) = (c.x / c.w, c.y / c.w, c.z / c.w);
            assert!(
                x.abs() <= 1.0 && y.abs() <= 1.0,
                "corner {i} off screen: {x} {y}"
            );
            assert!((0.0..=1.0).contains(&z), "corner {i} clipped in depth: {z}");
            extent = extent.max(x.abs()).max(y.abs());
        }
        assert!(
            extent > 0.8,
            "the box fills only {extent} of the half-frame"
        );
    }
}
