//! A fixed-size bitset: visited sets, known sets and failure sets are unions
//! of these, so map exchange is word-wise OR and never allocates.

use serde::{Deserialize, Serialize};

#[derive(Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct Bitset {
    words: Vec<u64>,
}

impl Clone for Bitset {
    fn clone(&self) -> Self {
        Bitset { words: self.words.clone() }
    }

    // Maps sent every slot are copied into recycled ones: no allocation.
    fn clone_from(&mut self, source: &Self) {
        self.words.clone_from(&source.words);
    }
}

impl Bitset {
    pub fn new(bits: usize) -> Self {
        Bitset { words: vec![0; bits.div_ceil(64)] }
    }

    pub fn from_words(words: Vec<u64>) -> Self {
        Bitset { words }
    }

    #[inline]
    pub fn words(&self) -> &[u64] {
        &self.words
    }

    /// Number of bits it can hold (a multiple of 64).
    #[inline]
    pub fn capacity(&self) -> usize {
        self.words.len() * 64
    }

    #[inline]
    pub fn get(&self, k: usize) -> bool {
        self.words.get(k / 64).is_some_and(|w| w >> (k % 64) & 1 == 1)
    }

    #[inline]
    pub fn set(&mut self, k: usize) {
        self.words[k / 64] |= 1 << (k % 64);
    }

    #[inline]
    pub fn clear(&mut self, k: usize) {
        self.words[k / 64] &= !(1 << (k % 64));
    }

    pub fn clear_all(&mut self) {
        self.words.iter_mut().for_each(|w| *w = 0);
    }

    /// Sets bit `k`, growing the set when it is too small (sets whose size
    /// a robot cannot know in advance, such as targets in situation 2).
    pub fn set_growing(&mut self, k: usize) {
        if k / 64 >= self.words.len() {
            self.words.resize(k / 64 + 1, 0);
        }
        self.set(k);
    }

    /// `self |= other`, growing `self` to `other`'s size first if it is smaller.
    pub fn union_growing(&mut self, other: &Bitset) -> bool {
        if other.words.len() > self.words.len() {
            self.words.resize(other.words.len(), 0);
        }
        self.union_with(other)
    }

    /// `self |= other`; returns whether anything changed. Sizes must match.
    pub fn union_with(&mut self, other: &Bitset) -> bool {
        let mut changed = 0;
        for (a, b) in self.words.iter_mut().zip(&other.words) {
            changed |= *b & !*a;
            *a |= *b;
        }
        changed != 0
    }

    /// Whether some bit is set here and not in `other`.
    #[inline]
    pub fn any_not_in(&self, other: &Bitset) -> bool {
        self.words.iter().zip(&other.words).any(|(a, b)| a & !b != 0)
    }

    #[inline]
    pub fn count(&self) -> usize {
        self.words.iter().map(|w| w.count_ones() as usize).sum()
    }

    #[inline]
    pub fn is_subset_of(&self, other: &Bitset) -> bool {
        !self.any_not_in(other)
    }

    #[inline]
    pub fn iter(&self) -> impl Iterator<Item = usize> + '_ {
        ones(&self.words)
    }

    pub fn copy_from(&mut self, other: &Bitset) {
        self.words.copy_from_slice(&other.words);
    }
}

/// The indices of the set bits of `words`, bit `k % 64` of word `k / 64`,
/// in increasing order.
#[inline]
pub fn ones(words: &[u64]) -> impl Iterator<Item = usize> + '_ {
    words.iter().enumerate().flat_map(|(k, &w)| {
        let mut w = w;
        std::iter::from_fn(move || {
            if w == 0 {
                return None;
            }
            let b = w.trailing_zeros() as usize;
            w &= w - 1;
            Some(k * 64 + b)
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn set_union_iter() {
        let mut a = Bitset::new(130);
        let mut b = Bitset::new(130);
        a.set(3);
        a.set(129);
        b.set(64);
        assert!(a.union_with(&b));
        assert!(!a.union_with(&b));
        assert_eq!(a.iter().collect::<Vec<_>>(), vec![3, 64, 129]);
        assert_eq!(a.count(), 3);
        assert!(b.is_subset_of(&a));
        assert!(!a.is_subset_of(&b));
        a.clear(64);
        assert!(!a.get(64));
    }
}
