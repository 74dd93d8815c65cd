//! A fast, deterministic hasher for the integer keys of the mesh algorithms (grid cells,
//! sorted face corner lists).
//!
//! Why not the std SipHash: it defends against adversarial collision flooding, which costs
//! several times more per key than the lookups themselves, and these maps are keyed by
//! vertex ids and grid cells of the mesh being processed. Worst case with a hostile file is
//! slower hashing, never a wrong result: the maps compare keys exactly, so only speed
//! depends on the hash.

use std::hash::{BuildHasherDefault, Hasher};

/// Multiply-rotate hashing of machine words (the FxHash scheme of rustc) with a final
/// avalanche, so that hashbrown, which takes its control bits from the top of the hash,
/// sees well-mixed high bits also for small, sequential keys.
#[derive(Default, Clone, Copy)]
pub struct FastHasher(u64);

const K: u64 = 0xf135_7aea_2e62_a9c5;

impl FastHasher {
    #[inline]
    fn add(&mut self, w: u64) {
        self.0 = (self.0.rotate_left(26) ^ w).wrapping_mul(K);
    }
}

impl Hasher for FastHasher {
    #[inline]
    fn write(&mut self, bytes: &[u8]) {
        let mut chunks = bytes.chunks_exact(8);
        for c in &mut chunks {
            self.add(u64::from_le_bytes(c.try_into().expect("8 bytes")));
        }
        let rest = chunks.remainder();
        if !rest.is_empty() {
            let mut b = [0u8; 8];
            b[..rest.len()].copy_from_slice(rest);
            self.add(u64::from_le_bytes(b));
        }
    }
    #[inline]
    fn write_u8(&mut self, i: u8) {
        self.add(i as u64);
    }
    #[inline]
    fn write_u32(&mut self, i: u32) {
        self.add(i as u64);
    }
    #[inline]
    fn write_u64(&mut self, i: u64) {
        self.add(i);
    }
    #[inline]
    fn write_i64(&mut self, i: i64) {
        self.add(i as u64);
    }
    #[inline]
    fn write_usize(&mut self, i: usize) {
        self.add(i as u64);
    }
    #[inline]
    fn finish(&self) -> u64 {
        // Avalanche (the murmur3 finaliser) so every input bit reaches the high bits.
        let mut h = self.0;
        h ^= h >> 33;
        h = h.wrapping_mul(0xff51_afd7_ed55_8ccd);
        h ^= h >> 33;
        h
    }
}

/// A `HashMap` with [`FastHasher`].
pub type FastMap<K, V> = std::collections::HashMap<K, V, BuildHasherDefault<FastHasher>>;

/// A `HashSet` with [`FastHasher`].
pub type FastSet<K> = std::collections::HashSet<K, BuildHasherDefault<FastHasher>>;

/// A face's vertex set as a hashable key without a heap allocation for faces of up to four
/// corners (sorted ids, padded with `u32::MAX`, plus the corner count so padding can never
/// be mistaken for a vertex id); larger faces keep their sorted ids in a vector.
#[derive(Clone, PartialEq, Eq, Hash)]
pub(crate) enum FaceKey {
    Small(u8, [u32; 4]),
    Large(Vec<u32>),
}

impl FaceKey {
    pub(crate) fn new(face: &[u32]) -> FaceKey {
        if face.len() <= 4 {
            let mut k = [u32::MAX; 4];
            k[..face.len()].copy_from_slice(face);
            // Insertion sort: for at most four ids it beats the general sort's setup.
            for i in 1..face.len() {
                let mut j = i;
                while j > 0 && k[j - 1] > k[j] {
                    k.swap(j - 1, j);
                    j -= 1;
                }
            }
            FaceKey::Small(face.len() as u8, k)
        } else {
            let mut k = face.to_vec();
            k.sort_unstable();
            FaceKey::Large(k)
        }
    }
}
