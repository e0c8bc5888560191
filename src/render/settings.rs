//! Render settings shared by the library API and the CLI, and the per-frame uniform block
//! (`Frame` in `glsl/common/frame.glsl`).

use glam::{Mat4, Vec3};

use crate::{Error, Result};

/// How tessellation levels are chosen.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum TessMode {
    /// Every edge gets the requested level.
    #[default]
    Uniform,
    /// Levels from the projected length of each edge (target pixels per segment).
    Adaptive,
    /// Levels from the camera distance of each edge (QAS's camera-distance metric, Boubekeur,
    /// Schlick 2007 §3; per-edge from the midpoint of its end vertices' shared limit points, so
    /// both sides agree): `level × distance / d`, [`TessSettings::distance`].
    Distance,
}

/// Tessellation spacing (SPIR-V `SpacingEqual`, `SpacingFractionalOdd`, `SpacingFractionalEven`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Spacing {
    /// Integer levels (rounded up).
    #[default]
    Equal,
    /// Fractional levels, odd segment counts.
    FractionalOdd,
    /// Fractional levels, even segment counts.
    FractionalEven,
}

impl Spacing {
    /// Parses `equal`, `fractional-odd` or `fractional-even`.
    pub fn parse(s: &str) -> Result<Spacing> {
        match s {
            "equal" => Ok(Spacing::Equal),
            "fractional-odd" => Ok(Spacing::FractionalOdd),
            "fractional-even" => Ok(Spacing::FractionalEven),
            _ => Err(Error::Invalid(format!(
                "spacing `{s}`: expected equal, fractional-odd or fractional-even"
            ))),
        }
    }

    /// Suffix of the TES variant in `glsl/variants.txt`.
    pub(crate) fn shader_suffix(self) -> &'static str {
        match self {
            Spacing::Equal => "equal",
            Spacing::FractionalOdd => "odd",
            Spacing::FractionalEven => "even",
        }
    }
}

/// Surface colouring.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ColorBy {
    /// One neutral material.
    #[default]
    None,
    /// Regular patches gold, irregular purple, triangles green (Gregory-patch paper, Fig. 1).
    PatchType,
    /// Error maps ([`super::heatmap`]): blue (exact) to red by the per-vertex error class;
    /// regular patches blue, exact CPU faces grey.
    Error,
    /// Adaptive-scheme patches by refinement level (Köbler 2013, Fig. 5.1): one colour per level
    /// (0 blue, 1 cyan, 2 green, 3 yellow, 4 orange, 5 red, ...); other schemes' patches neutral.
    Level,
}

/// Tessellation settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TessSettings {
    /// Uniform level (clamped to `1..=maxTessellationGenerationLevel` by [`Self::resolve`]).
    pub level: f32,
    /// Uniform or screen-space adaptive.
    pub mode: TessMode,
    /// Adaptive target: pixels per tessellated segment.
    pub pixels_per_edge: f32,
    /// Distance mode: an edge whose midpoint is this far from the eye gets `level`, nearer
    /// edges more and farther ones fewer (∝ 1 / distance). `0`: the surface's bounding-box
    /// diagonal, set by [`crate::render::resolve_tess`].
    pub distance: f32,
    /// Spacing of the tessellator.
    pub spacing: Spacing,
    /// Uniform mode: patches whose level exceeds this are drawn as 2x2, 4x4, ... sub-patches of
    /// level `level / split` (power-of-two split, so shared edges stay bitwise identical). On
    /// Mesa lavapipe the cost per domain point jumps ~3x above level 24 and ~30x at 31+
    /// (`tessera bench`); `f32::INFINITY` disables splitting.
    pub max_patch_level: f32,
}

impl TessSettings {
    /// Sub-patches per side for uniform mode (1 in adaptive mode or below the limit).
    pub fn split(&self) -> u32 {
        if self.mode != TessMode::Uniform
            || self.max_patch_level.is_nan()
            || self.max_patch_level < 1.0
        {
            return 1;
        }
        let mut s = 1u32;
        while self.level / s as f32 > self.max_patch_level && s < 64 {
            s *= 2;
        }
        s
    }
}

impl Default for TessSettings {
    fn default() -> Self {
        TessSettings {
            level: 8.0,
            mode: TessMode::Uniform,
            pixels_per_edge: 8.0,
            distance: 0.0,
            spacing: Spacing::Equal,
            max_patch_level: 16.0,
        }
    }
}

impl TessSettings {
    /// The settings a surface is drawn with, resolved once (the renderer does this when it is
    /// created, [`crate::render::SurfaceRenderer::tess`]): the level clamped to
    /// `1..=device_max_level`; the largest patch level lowered to what every pass draws well
    /// ([`PatchLevelLimit`]); splitting off when a pass cannot be split with this spacing.
    pub fn resolve(&self, device_max_level: f32, limits: &[PatchLevelLimit]) -> TessSettings {
        let mut t = *self;
        t.level = t.level.clamp(1.0, device_max_level.max(1.0));
        for l in limits {
            t.max_patch_level = t.max_patch_level.min(l.max_patch_level);
        }
        if t.split() > 1 && limits.iter().any(|l| !l.splittable) {
            log::info!(
                "patches are drawn whole at level {}: a pass cannot be split with {:?} spacing \
                 (max patch level ignored)",
                t.level,
                t.spacing
            );
            t.max_patch_level = f32::INFINITY;
        }
        t
    }
}

/// How far a pass can be tessellated per (sub-)patch (a pass's
/// [`crate::render::schemes::PassTables::patch_level_limit`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PatchLevelLimit {
    /// Largest (sub-)patch level drawn well; higher uniform levels are split into sub-patches.
    pub max_patch_level: f32,
    /// Whether patches may be split at all (false: drawn whole whatever the level).
    pub splittable: bool,
}

impl PatchLevelLimit {
    /// Patches drawn whole at any level (passes whose levels are per patch or whose records
    /// cannot be split into sub-patches).
    pub const WHOLE: PatchLevelLimit = PatchLevelLimit {
        max_patch_level: f32::INFINITY,
        splittable: false,
    };
}

impl Default for PatchLevelLimit {
    fn default() -> Self {
        PatchLevelLimit {
            max_patch_level: f32::INFINITY,
            splittable: true,
        }
    }
}

/// How a surface is drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RenderDesc {
    /// Tessellation levels, mode and spacing (resolved against the device and the passes when
    /// the renderer is created: [`crate::render::SurfaceRenderer::tess`]).
    pub tess: TessSettings,
    /// Draw triangle edges only (polygon mode LINE).
    pub wireframe: bool,
    /// Surface colouring.
    pub color_by: ColorBy,
    /// Cull back faces (closed surfaces only; open ones show both sides otherwise).
    pub cull_back_faces: bool,
    /// Record every TES invocation into the capture buffer (`Some(capacity)` in records).
    pub capture_capacity: Option<u32>,
    /// Record every triangle the evaluation stage emits into the capture buffer
    /// (`Some(capacity)` in triangles; a pass-through geometry stage,
    /// `glsl/surface/capture_triangles.geom`, needs `geometryShader`): the frame's own triangles
    /// as drawn, culling included ([`crate::render::static_draw`]). Not with `capture_capacity`.
    pub capture_triangles: Option<u32>,
    /// Displacement of the surface along its normal ([`super::displace`]).
    pub displacement: Displacement,
    /// Patch culling (`--cull`, default on; `--no-cull`): the control stages give zero
    /// tessellation levels to patches whose control hull (grown by the displacement scale) lies
    /// entirely outside the view frustum (`glsl/common/cull.glsl`). The image is unchanged.
    /// Ignored (off) when the TES captures (`capture_capacity`): capture measures the whole
    /// surface.
    pub cull_patches: bool,
}

/// Displacement of the limit surface along its normal, applied in every evaluation stage (and
/// to the CPU-evaluated triangles) after the watertight position and normal.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Displacement {
    /// The limit surface itself.
    #[default]
    None,
    /// `p + scale * d(p) * n` with the fixed function [`super::displace::procedural`] of the
    /// undisplaced limit position (`--displacement procedural --displacement-scale S`).
    Procedural {
        /// World units per unit of `d` (`d` lies in [-1, 1]).
        scale: f32,
    },
    /// `p + scale * d(s, t) * n` with `d = value - 0.5` of the surface's displacement map
    /// ([`super::SurfaceData::set_displacement_map`], [`super::displace::DisplacementMap`])
    /// at the face-varying texture coordinate (`--displacement FILE.png`). The renderer
    /// refuses a surface without a map or without texture coordinates.
    Map {
        /// World units per unit of `d` (`d` lies in [-0.5, 0.5]).
        scale: f32,
    },
}

impl Displacement {
    /// The scale along the normal (0 when off).
    pub fn scale(self) -> f32 {
        match self {
            Displacement::None => 0.0,
            Displacement::Procedural { scale } | Displacement::Map { scale } => scale,
        }
    }

    /// `Frame.displace.y`: 0 procedural, 1 map.
    fn mode(self) -> f32 {
        match self {
            Displacement::Map { .. } => 1.0,
            _ => 0.0,
        }
    }
}

impl Default for RenderDesc {
    fn default() -> Self {
        RenderDesc {
            tess: TessSettings::default(),
            wireframe: false,
            color_by: ColorBy::None,
            cull_back_faces: false,
            capture_capacity: None,
            capture_triangles: None,
            displacement: Displacement::None,
            cull_patches: true,
        }
    }
}

/// The per-frame part of the uniform block the caller sets (camera, light, viewport); the
/// renderer adds the tessellation settings it resolved.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrameUniforms {
    /// World -> Vulkan clip space.
    pub view_proj: Mat4,
    /// Eye position (world).
    pub eye: Vec3,
    /// Framebuffer size in pixels.
    pub viewport: [f32; 2],
    /// Direction towards the key light (world; normalised by the shader).
    pub light_dir: Vec3,
    /// Colouring.
    pub color_by: ColorBy,
}

/// Switches of the `Frame` block the renderer sets (`flags.y`, `flags.z`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct FrameFlags {
    /// The control stages cull patches outside the frustum (`glsl/common/cull.glsl`).
    pub cull: bool,
    /// The surface has texture coordinates (`glsl/common/texcoord.glsl`).
    pub texcoords: bool,
}

/// Size of the std140 `Frame` block.
pub const FRAME_UNIFORM_BYTES: usize = 160;

impl FrameUniforms {
    /// The std140 bytes of the `Frame` block with the resolved tessellation settings `tess`,
    /// the device's `maxTessellationGenerationLevel` `max_level`, the `displacement` and the
    /// renderer's switches (`flags`).
    pub fn to_bytes(
        &self,
        tess: &TessSettings,
        max_level: f32,
        displacement: Displacement,
        flags: FrameFlags,
    ) -> [u8; FRAME_UNIFORM_BYTES] {
        let mut f = [0f32; 32];
        f[..16].copy_from_slice(&self.view_proj.to_cols_array());
        f[16..19].copy_from_slice(&self.eye.to_array());
        f[20] = self.viewport[0];
        f[21] = self.viewport[1];
        f[24] = tess.level;
        f[25] = match tess.mode {
            TessMode::Uniform => 0.0,
            TessMode::Adaptive => 1.0,
            TessMode::Distance => 2.0,
        };
        f[26] = match tess.mode {
            TessMode::Distance => tess.distance,
            _ => tess.pixels_per_edge,
        };
        f[27] = max_level;
        f[28..31].copy_from_slice(&self.light_dir.to_array());
        let mut out = [0u8; FRAME_UNIFORM_BYTES];
        for (k, v) in f.iter().enumerate() {
            out[4 * k..4 * k + 4].copy_from_slice(&v.to_le_bytes());
        }
        let color = match self.color_by {
            ColorBy::None => 0u32,
            ColorBy::PatchType => 1u32,
            ColorBy::Error => 2u32,
            ColorBy::Level => 3u32,
        };
        out[128..132].copy_from_slice(&color.to_le_bytes());
        out[132..136].copy_from_slice(&u32::from(flags.cull).to_le_bytes());
        out[136..140].copy_from_slice(&u32::from(flags.texcoords).to_le_bytes());
        out[144..148].copy_from_slice(&displacement.scale().to_le_bytes());
        out[148..152].copy_from_slice(&displacement.mode().to_le_bytes());
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_block_offsets() {
        let u = FrameUniforms {
            view_proj: Mat4::from_cols_array(&std::array::from_fn(|k| k as f32)),
            eye: Vec3::new(1.0, 2.0, 3.0),
            viewport: [640.0, 480.0],
            light_dir: Vec3::new(0.0, 1.0, 0.0),
            color_by: ColorBy::PatchType,
        };
        let tess = TessSettings {
            level: 5.0,
            mode: TessMode::Adaptive,
            pixels_per_edge: 4.0,
            distance: 2.0,
            spacing: Spacing::Equal,
            max_patch_level: 16.0,
        };
        let b = u.to_bytes(
            &tess,
            64.0,
            Displacement::Procedural { scale: 0.25 },
            FrameFlags {
                cull: true,
                texcoords: true,
            },
        );
        let f = |o: usize| f32::from_le_bytes(b[o..o + 4].try_into().unwrap());
        assert_eq!(f(4 * 15), 15.0);
        assert_eq!(f(64), 1.0);
        assert_eq!(f(80), 640.0);
        assert_eq!(f(96), 5.0);
        assert_eq!(f(100), 1.0);
        assert_eq!(f(108), 64.0);
        assert_eq!(f(116), 1.0);
        assert_eq!(u32::from_le_bytes(b[128..132].try_into().unwrap()), 1);
        assert_eq!(u32::from_le_bytes(b[132..136].try_into().unwrap()), 1);
        assert_eq!(u32::from_le_bytes(b[136..140].try_into().unwrap()), 1);
        assert_eq!((f(144), f(148)), (0.25, 0.0));
        let map = u.to_bytes(
            &tess,
            64.0,
            Displacement::Map { scale: 0.5 },
            FrameFlags::default(),
        );
        let g = |o: usize| f32::from_le_bytes(map[o..o + 4].try_into().unwrap());
        assert_eq!((g(144), g(148)), (0.5, 1.0));
        let distance = TessSettings {
            mode: TessMode::Distance,
            ..tess
        };
        let b = u.to_bytes(
            &distance,
            64.0,
            Displacement::None,
            FrameFlags {
                cull: false,
                texcoords: false,
            },
        );
        let f = |o: usize| f32::from_le_bytes(b[o..o + 4].try_into().unwrap());
        assert_eq!((f(100), f(104)), (2.0, 2.0));
    }

    #[test]
    fn split_is_a_power_of_two_keeping_sub_levels_in_bounds() {
        let t = |level| TessSettings {
            level,
            ..TessSettings::default()
        };
        assert_eq!(t(16.0).split(), 1);
        assert_eq!(t(16.5).split(), 2);
        assert_eq!(t(32.0).split(), 2);
        assert_eq!(t(33.0).split(), 4);
        assert_eq!(t(64.0).split(), 4);
        let adaptive = TessSettings {
            mode: TessMode::Adaptive,
            ..t(64.0)
        };
        assert_eq!(adaptive.split(), 1);
        let off = TessSettings {
            max_patch_level: f32::INFINITY,
            ..t(64.0)
        };
        assert_eq!(off.split(), 1);
    }

    #[test]
    fn spacing_names() {
        assert_eq!(
            Spacing::parse("fractional-odd").unwrap(),
            Spacing::FractionalOdd
        );
        assert!(Spacing::parse("odd").is_err());
    }
}
