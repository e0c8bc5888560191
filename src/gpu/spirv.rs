//! Moves a SPIR-V module's descriptor sets and push-constant block ([`Remap`]), so tessera's
//! shaders can take set and push-constant slots that leave the caller's free.
//!
//! GLSL fixes `layout(set = N)` and push-constant member offsets at compile time and Vulkan
//! cannot specialise them, but in SPIR-V both are single literal operands of decorations
//! (`OpDecorate %var DescriptorSet N`, `OpMemberDecorate %block m Offset o`). Rewriting those
//! literals before `vkCreateShaderModule` gives a module that is valid on every device, with no
//! build-time variant per slot.

use super::error::GpuError;
use crate::Result;

const MAGIC: u32 = 0x0723_0203;
const HEADER_WORDS: usize = 5;
const OP_TYPE_POINTER: u32 = 32;
const OP_DECORATE: u32 = 71;
const OP_MEMBER_DECORATE: u32 = 72;
const DECORATION_DESCRIPTOR_SET: u32 = 34;
const DECORATION_OFFSET: u32 = 35;
const STORAGE_CLASS_PUSH_CONSTANT: u32 = 9;

/// How to move a module's resources: every descriptor set index by `set_base`, every member
/// of push-constant blocks by `push_offset` bytes.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash)]
pub struct Remap {
    /// Added to every `DescriptorSet` decoration.
    pub set_base: u32,
    /// Added to every member `Offset` of a push-constant block (a multiple of 4).
    pub push_offset: u32,
}

impl Remap {
    /// Whether the remap changes nothing.
    pub fn is_identity(&self) -> bool {
        self.set_base == 0 && self.push_offset == 0
    }
}

fn malformed(what: &str) -> crate::Error {
    GpuError::Invalid(format!("SPIR-V remap: {what}")).into()
}

/// The instructions of `words` as `(start index, opcode, word count)`.
fn instructions(words: &[u32]) -> Result<Vec<(usize, u32, usize)>> {
    if words.len() < HEADER_WORDS || words[0] != MAGIC {
        return Err(malformed("not a SPIR-V module"));
    }
    let mut out = Vec::new();
    let mut i = HEADER_WORDS;
    while i < words.len() {
        let count = (words[i] >> 16) as usize;
        if count == 0 || i + count > words.len() {
            return Err(malformed(&format!("truncated instruction at word {i}")));
        }
        out.push((i, words[i] & 0xffff, count));
        i += count;
    }
    Ok(out)
}

/// `words` with `remap` applied.
pub fn remap(words: &[u32], remap: &Remap) -> Result<Vec<u32>> {
    if remap.push_offset % 4 != 0 {
        return Err(malformed(&format!(
            "push-constant offset {} is not a multiple of 4",
            remap.push_offset
        )));
    }
    let ins = instructions(words)?;
    // Types pointed to from the PushConstant storage class: the push-constant blocks.
    let blocks: Vec<u32> = ins
        .iter()
        .filter(|(i, op, n)| {
            *op == OP_TYPE_POINTER && *n == 4 && words[i + 2] == STORAGE_CLASS_PUSH_CONSTANT
        })
        .map(|(i, _, _)| words[i + 3])
        .collect();
    let mut out = words.to_vec();
    for (i, op, n) in ins {
        if op == OP_DECORATE && n == 4 && words[i + 2] == DECORATION_DESCRIPTOR_SET {
            out[i + 3] += remap.set_base;
        } else if op == OP_MEMBER_DECORATE
            && n == 5
            && words[i + 3] == DECORATION_OFFSET
            && blocks.contains(&words[i + 1])
        {
            out[i + 4] += remap.push_offset;
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn word(op: u32, n: u32) -> u32 {
        (n << 16) | op
    }

    /// A hand-assembled fragment: one buffer in set 1, a push block %7 with members at 0 and 4,
    /// a non-push struct %9 with a member at 8.
    #[rustfmt::skip]
    fn module() -> Vec<u32> {
        vec![
            MAGIC, 0x0001_0500, 0, 20, 0,
            word(OP_DECORATE, 4), 5, DECORATION_DESCRIPTOR_SET, 1,
            word(OP_MEMBER_DECORATE, 5), 7, 0, DECORATION_OFFSET, 0,
            word(OP_MEMBER_DECORATE, 5), 7, 1, DECORATION_OFFSET, 4,
            word(OP_MEMBER_DECORATE, 5), 9, 0, DECORATION_OFFSET, 8,
            word(OP_TYPE_POINTER, 4), 8, STORAGE_CLASS_PUSH_CONSTANT, 7,
            word(OP_TYPE_POINTER, 4), 10, 12, 9,
        ]
    }

    #[test]
    fn moves_sets_and_push_members_only() {
        let m = module();
        let r = remap(
            &m,
            &Remap {
                set_base: 2,
                push_offset: 64,
            },
        )
        .unwrap();
        assert_eq!(r[8], 3, "set 1 + 2");
        assert_eq!((r[13], r[18]), (64, 68), "push members moved");
        assert_eq!(
            r[23], 8,
            "a struct outside push constants keeps its offsets"
        );
        assert_eq!(remap(&m, &Remap::default()).unwrap(), m);
    }

    #[test]
    fn refuses_bad_input() {
        let m = module();
        assert!(remap(
            &m,
            &Remap {
                set_base: 0,
                push_offset: 6
            }
        )
        .is_err());
        assert!(remap(&m[..7], &Remap::default()).is_err());
        assert!(remap(&[1, 2, 3, 4, 5], &Remap::default()).is_err());
    }
}
