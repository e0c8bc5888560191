//! A word-at-a-time hash for the maps of the limit masks and the end-cap rows, keyed by ids,
//! counts and bit patterns of the crate's own topology (not adversarial input): the
//! multiply-rotate step of rustc's `FxHasher`, one step per 8 bytes instead of SipHash's rounds
//! per word, and no random seed (instruction counts repeat from run to run). Lookups only: no
//! output depends on a map's iteration order. In `subdiv` so that both `subdiv` and `patch` use
//! it (`patch::gregory::word_hash` re-exports it).

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

/// `HashMap` with [`WordHasher`].
pub type WordHashMap<K, V> = HashMap<K, V, BuildHasherDefault<WordHasher>>;

/// The hasher of [`WordHashMap`].
#[derive(Debug, Default, Clone, Copy)]
pub struct WordHasher(u64);

impl WordHasher {
    fn add(&mut self, word: u64) {
        self.0 = (self.0.rotate_left(5) ^ word).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }
}

impl Hasher for WordHasher {
    fn write(&mut self, bytes: &[u8]) {
        let mut chunks = bytes.chunks_exact(8);
        for c in &mut chunks {
            self.add(u64::from_le_bytes(c.try_into().expect("8 bytes")));
        }
        let rest = chunks.remainder();
        if !rest.is_empty() {
            let mut last = [0u8; 8];
            last[..rest.len()].copy_from_slice(rest);
            self.add(u64::from_le_bytes(last));
        }
    }

    fn write_u32(&mut self, x: u32) {
        self.add(u64::from(x));
    }

    fn write_u64(&mut self, x: u64) {
        self.add(x);
    }

    fn write_usize(&mut self, x: usize) {
        self.add(x as u64);
    }

    fn finish(&self) -> u64 {
        self.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::hash::{BuildHasher, Hash};

    /// Keys that differ in one word, in their length only, or in a trailing partial word hash
    /// apart (fails if the remainder of a slice is dropped or the length is not mixed in).
    #[test]
    fn near_keys_hash_apart() {
        let h = |k: &[u32]| BuildHasherDefault::<WordHasher>::default().hash_one(k);
        let keys: [&[u32]; 6] = [&[], &[0], &[0, 0], &[0, 0, 0], &[1, 0, 0], &[0, 0, 1]];
        for (i, a) in keys.iter().enumerate() {
            for b in &keys[i + 1..] {
                assert_ne!(h(a), h(b), "{a:?} {b:?}");
            }
        }
        let mut m: WordHashMap<Vec<u32>, usize> = WordHashMap::default();
        for (i, k) in keys.iter().enumerate() {
            m.insert(k.to_vec(), i);
        }
        assert!(keys.iter().enumerate().all(|(i, k)| m[*k] == i));
        let mut one = WordHasher::default();
        7u32.hash(&mut one);
        assert_ne!(one.finish(), 0);
    }
}
