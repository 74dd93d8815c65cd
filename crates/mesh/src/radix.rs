//! Sorting `(key, id)` pairs by a radix sort: the edge keys of [`crate::topology`] and the
//! Morton codes of the small trees of [`crate::morton`] (large trees sort theirs in parallel
//! by comparisons, faster on two cores for 63-bit keys).
//!
//! A comparison sort of the Stanford bunny's hull tetrahedra's 305 k Morton codes, its 208 k
//! corners' edge keys and the refinement rounds' smaller lists was 2 % of the `algesurf
//! smooth` run's instructions (`rayon::slice::sort`, 300 M of 14.6 G, `callgrind`): about
//! `n log₂ n ≈ 18 n` comparisons and moves. A least-significant-digit radix sort moves every
//! pair once per 11-bit digit of the key that is not the same in every key (6 for a 63-bit
//! Morton code, 3 for the bunny's 32-bit edge keys), after one pass that counts them all.
//!
//! ```
//! use algesurf_mesh::radix::sort_pairs;
//! let mut pairs = vec![(7u64 << 40, 0u32), (3, 1), (7 << 40, 2), (0, 3)];
//! sort_pairs(&mut pairs);
//! assert_eq!(pairs, vec![(0, 3), (3, 1), (7 << 40, 0), (7 << 40, 2)]);
//! ```

/// Below this many pairs [`sort_pairs`] calls `sort_by_key`: a radix pass's 2048 counters
/// cost more than the comparisons of a short list.
const COMPARISON_BELOW: usize = 256;

/// Bits per digit: 11 bits cover a 63-bit Morton code in 6 passes (8 with bytes), and the
/// 2048 counters of a digit (16 KiB) still sit in the first-level cache.
const DIGIT_BITS: u32 = 11;
const RADIX: usize = 1 << DIGIT_BITS;

/// Digit `d` of `key`.
#[inline]
fn digit(key: u64, d: u32) -> usize {
    ((key >> (DIGIT_BITS * d)) & (RADIX as u64 - 1)) as usize
}

/// The digits, least significant first, in which some key differs from another: only those
/// need a pass (`any ^ all` has a bit set where some key has it and another has not).
fn varying_digits(any: u64, all: u64) -> Vec<u32> {
    let varying = any ^ all;
    (0..64u32.div_ceil(DIGIT_BITS))
        .filter(|&d| (varying >> (DIGIT_BITS * d)) & (RADIX as u64 - 1) != 0)
        .collect()
}

/// The running `(any, all)` of the keys: their bitwise or and and.
fn or_and(pairs: &[(u64, u32)]) -> (u64, u64) {
    pairs
        .iter()
        .fold((0, !0), |(any, all), &(k, _)| (any | k, all & k))
}

/// Moves `from` into `to` sorted stably by digit `d`, whose counts are `count`; `start`
/// (`RADIX` long) is scratch.
fn scatter(
    from: &[(u64, u32)],
    to: &mut [(u64, u32)],
    d: u32,
    count: &[usize],
    start: &mut [usize],
) {
    let mut sum = 0;
    for (s, &c) in start.iter_mut().zip(count) {
        *s = sum;
        sum += c;
    }
    for &p in from {
        let b = digit(p.0, d);
        to[start[b]] = p;
        start[b] += 1;
    }
}

/// Sorts `data` stably by key, in series, with `buf` (the same length) as scratch. Returns
/// `true` when the sorted pairs ended in `buf` (an odd number of passes), `false` when in
/// `data`. Short lists are [`sort_pairs`]' to sort by comparisons.
fn lsd(data: &mut [(u64, u32)], buf: &mut [(u64, u32)]) -> bool {
    let (any, all) = or_and(data);
    let digits = varying_digits(any, all);
    let mut counts = vec![0usize; RADIX * digits.len()];
    for &(k, _) in data.iter() {
        for (c, &d) in counts.chunks_exact_mut(RADIX).zip(&digits) {
            c[digit(k, d)] += 1;
        }
    }
    let mut in_buf = false;
    let mut start = vec![0usize; RADIX];
    for (c, &d) in counts.chunks_exact(RADIX).zip(&digits) {
        if in_buf {
            scatter(buf, data, d, c, &mut start);
        } else {
            scatter(data, buf, d, c, &mut start);
        }
        in_buf = !in_buf;
    }
    in_buf
}

/// Sorts `pairs` by key, pairs of equal keys kept in their given order (a stable sort by
/// key). When every key's ids are given in increasing order — as in the callers, which number
/// the pairs by their position — this is the order of sorting the pairs themselves
/// (`(key, id)` lexicographically), so it is the order `sort_unstable` gave before, pair for
/// pair, and does not depend on the thread count.
///
/// Least-significant-digit radix sort on 11-bit digits, skipping the digits that are equal
/// in every key, with one scratch buffer of the same length. In series: a parallel variant
/// (one pass by the top digit, its buckets sorted in parallel) sorted 305 k Morton codes in
/// 4.2–6.0 ms instead of 7.4 ms on two cores, but 208 k edge keys in 3.4 ms instead of 2.3 ms,
/// and cost the bunny's run 40–200 M more instructions (the buckets' counters, or their
/// comparison sorts): a wash.
pub fn sort_pairs(pairs: &mut Vec<(u64, u32)>) {
    if pairs.len() < COMPARISON_BELOW {
        // Stable, as the radix sort is.
        pairs.sort_by_key(|p| p.0);
        return;
    }
    let mut buf = vec![(0u64, 0u32); pairs.len()];
    if lsd(pairs, &mut buf) {
        *pairs = buf;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::Lcg;

    /// The radix order is the comparison sort's, pair for pair, for keys of every width the
    /// callers use (edge keys of small ids, 63-bit Morton codes, many repeats) and for lengths
    /// on both sides of the comparison-sort cut.
    #[test]
    fn radix_order_is_the_pairs_sorted_order() {
        let mut rng = Lcg(11);
        for (case, &(n, bits)) in [
            (10usize, 64u32),
            (255, 63),
            (256, 63),
            (1000, 63),
            (5000, 20),
            (5000, 3),
            (40_000, 40),
            (3000, 64),
            // Longer lists, of wide keys and of narrow ones.
            (100_000, 63),
            (70_000, 14),
            (90_000, 64),
        ]
        .iter()
        .enumerate()
        {
            let mask = if bits == 64 { !0 } else { (1u64 << bits) - 1 };
            let mut pairs: Vec<(u64, u32)> = (0..n)
                .map(|i| {
                    let r = (rng.next() * 2f64.powi(53)) as u64;
                    let k = (r ^ (r << 11) ^ (r >> 7)) & mask;
                    // Every third key repeats an earlier one.
                    (k, i as u32)
                })
                .collect();
            for i in (3..n).step_by(3) {
                pairs[i].0 = pairs[i / 3].0;
            }
            let mut expected = pairs.clone();
            expected.sort_unstable();
            sort_pairs(&mut pairs);
            assert_eq!(pairs, expected, "case {case}: {n} pairs of {bits}-bit keys");
        }
    }

    #[test]
    fn equal_keys_need_no_pass() {
        let mut pairs: Vec<(u64, u32)> = (0..1000).map(|i| (42, i)).collect();
        let expected = pairs.clone();
        sort_pairs(&mut pairs);
        assert_eq!(pairs, expected);
    }
}
