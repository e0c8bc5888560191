//! [`DrawTarget`]: what tessera's graphics pipelines must match to draw inside the caller's
//! rendering — attachment formats, the render pass or dynamic rendering, and the descriptor-set
//! and push-constant slots left to the caller ([`LayoutSlots`]).
//!
//! Set numbers cannot be specialisation constants, so tessera's pipeline layouts put the
//! caller's set layouts (or empty placeholders, valid on every device) below tessera's first set
//! and its shaders are rewritten to that set index at module creation ([`super::spirv`]). With
//! the caller's layouts below, sets the caller bound there stay bound across tessera's draws
//! (pipeline layouts compatible for those sets); with its push ranges declared too, so do its
//! push constants.

use ash::vk;

use super::spirv::Remap;
use super::target::TargetFormat;
use crate::gpu::error::GpuError;
use crate::Result;

/// How the rendering tessera draws into is begun.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum PassKind {
    /// tessera's own render pass for the format ([`super::RenderTarget`]).
    #[default]
    Tessera,
    /// The caller's render pass: `subpass` has one colour attachment of the format's colour
    /// format and a depth attachment of its depth format, at its sample count.
    RenderPass {
        /// The caller's render pass (kept alive by the caller while tessera draws with it).
        render_pass: vk::RenderPass,
        /// Subpass index tessera draws in.
        subpass: u32,
    },
    /// Dynamic rendering (`vkCmdBeginRendering`, needs `dynamicRendering`) with one colour
    /// attachment and a depth attachment of the format.
    Dynamic,
}

/// A push-constant range of the caller, declared in tessera's pipeline layouts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct PushRange {
    /// Stages of the range (none of tessera's: tessellation control and evaluation).
    pub stages: vk::ShaderStageFlags,
    /// Byte offset.
    pub offset: u32,
    /// Bytes.
    pub size: u32,
}

/// Where tessera's descriptor sets and push constants sit in its graphics pipeline layouts.
#[derive(Debug, Clone, Default, PartialEq, Eq, Hash)]
pub struct LayoutSlots {
    /// Index of tessera's first descriptor set (its sets 0 and 1 become `first_set` and
    /// `first_set + 1`).
    pub first_set: u32,
    /// The caller's set layouts for sets `0..first_set` (so its sets stay bound across
    /// tessera's draws); empty: empty placeholder layouts.
    pub caller_set_layouts: Vec<vk::DescriptorSetLayout>,
    /// Byte offset of tessera's push constants (a multiple of 4).
    pub push_offset: u32,
    /// The caller's push-constant ranges, declared in tessera's layouts; they must not overlap
    /// tessera's range nor use its stages.
    pub caller_push_ranges: Vec<PushRange>,
}

impl LayoutSlots {
    /// The shader rewrite for these slots.
    pub fn remap(&self) -> Remap {
        Remap {
            set_base: self.first_set,
            push_offset: self.push_offset,
        }
    }

    /// Checks the slots against tessera's own `sets` and push range `push` (stages, size):
    /// layouts given for every lower set, within `maxBoundDescriptorSets`, push ranges that
    /// neither overlap tessera's nor share its stages.
    pub fn check(
        &self,
        sets: usize,
        push: Option<(vk::ShaderStageFlags, u32)>,
        max_sets: u32,
        max_push: u32,
    ) -> Result<()> {
        let fail = |m: String| Err(GpuError::Limit(m).into());
        let n = self.caller_set_layouts.len() as u32;
        if n != 0 && n != self.first_set {
            return fail(format!(
                "LayoutSlots: {n} caller set layouts for first_set {} (give one per lower set, \
                 or none for placeholders)",
                self.first_set
            ));
        }
        if self.first_set as usize + sets > max_sets as usize {
            return fail(format!(
                "tessera's {sets} descriptor sets from set {} exceed maxBoundDescriptorSets {max_sets}",
                self.first_set
            ));
        }
        if self.push_offset % 4 != 0 {
            return fail(format!(
                "push-constant offset {} is not a multiple of 4",
                self.push_offset
            ));
        }
        let own = push.map(|(s, size)| (s, self.push_offset, self.push_offset + size));
        for r in &self.caller_push_ranges {
            let end = r.offset + r.size;
            if end > max_push || r.size == 0 {
                return fail(format!(
                    "caller push range {}..{end} is empty or exceeds maxPushConstantsSize {max_push}",
                    r.offset
                ));
            }
            if let Some((stages, start, own_end)) = own {
                if r.stages.intersects(stages) || (r.offset < own_end && start < end) {
                    return fail(format!(
                        "caller push range {}..{end} ({:?}) collides with tessera's \
                         {start}..{own_end} ({stages:?})",
                        r.offset, r.stages
                    ));
                }
            }
        }
        if let Some((_, _, own_end)) = own {
            if own_end > max_push {
                return fail(format!(
                    "tessera's push constants end at byte {own_end}, beyond maxPushConstantsSize \
                     {max_push}"
                ));
            }
        }
        Ok(())
    }
}

/// Everything a tessera graphics pipeline must match to draw into the caller's rendering.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct DrawTarget {
    /// Colour and depth formats and the sample count.
    pub format: TargetFormat,
    /// The render pass, or dynamic rendering.
    pub pass: PassKind,
    /// Descriptor-set and push-constant slots.
    pub slots: LayoutSlots,
}

impl From<TargetFormat> for DrawTarget {
    /// tessera's own render pass, sets from 0, push constants at offset 0.
    fn from(format: TargetFormat) -> DrawTarget {
        DrawTarget {
            format,
            pass: PassKind::Tessera,
            slots: LayoutSlots::default(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slots_are_checked() {
        let tess = vk::ShaderStageFlags::TESSELLATION_CONTROL;
        let push = Some((tess, 12));
        let ok = LayoutSlots {
            first_set: 1,
            push_offset: 64,
            caller_push_ranges: vec![PushRange {
                stages: vk::ShaderStageFlags::VERTEX,
                offset: 0,
                size: 64,
            }],
            ..LayoutSlots::default()
        };
        ok.check(2, push, 4, 128).unwrap();
        assert!(
            ok.check(2, push, 2, 128).is_err(),
            "sets 1-2 need 3 bound sets"
        );
        let mut overlap = ok.clone();
        overlap.push_offset = 60;
        assert!(overlap.check(2, push, 4, 128).is_err());
        let mut stages = ok.clone();
        stages.caller_push_ranges[0].stages |= tess;
        assert!(stages.check(2, push, 4, 128).is_err());
        let mut layouts = ok.clone();
        layouts.caller_set_layouts = vec![vk::DescriptorSetLayout::null(); 2];
        assert!(layouts.check(2, push, 4, 128).is_err());
        assert!(ok.check(2, push, 4, 72).is_err(), "64 + 12 > 72");
    }
}
