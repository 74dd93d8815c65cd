//! Multi-indices λ ∈ Z₊^N with |λ| = n: the labels of the Bernstein basis polynomials
//! `B_λ^n(τ) = n!/(λ_0!⋯λ_{N−1}!) τ_0^{λ_0}⋯τ_{N−1}^{λ_{N−1}}` in N barycentric variables.
//!
//! # Order
//! Coefficients are stored in **reverse lexicographic order**: λ_0 decreasing, then λ_1
//! decreasing, and so on. For N = 3, n = 2:
//! `(2,0,0) (1,1,0) (1,0,1) (0,2,0) (0,1,1) (0,0,2)`.
//! The first coefficient is at vertex 0 (`n e_0`), the last at vertex N−1.
//!
//! [`rank`] is O(N) and [`unrank`] is O(N·n); both are exact integer arithmetic.
//!
//! ```
//! use algesurf_bb::multi_index::{count, iter, rank, unrank};
//! assert_eq!(count::<4>(3), 20);
//! for (r, lambda) in iter::<4>(3).enumerate() {
//!     assert_eq!(rank(&lambda), r);
//!     assert_eq!(unrank::<4>(3, r), lambda);
//! }
//! ```

/// A multi-index of N barycentric exponents.
pub type MultiIndex<const N: usize> = [usize; N];

/// Rows of the binomial table: `a < BINOM_ROWS`, `b < BINOM_COLS` are table lookups.
const BINOM_ROWS: usize = 72;
const BINOM_COLS: usize = 8;

/// Pascal's triangle, computed at compile time: `rank` runs in every de Casteljau step, and a
/// table lookup there is several times faster than the division loop below.
const BINOM: [[usize; BINOM_COLS]; BINOM_ROWS] = {
    let mut t = [[0usize; BINOM_COLS]; BINOM_ROWS];
    let mut a = 0;
    while a < BINOM_ROWS {
        t[a][0] = 1;
        let mut b = 1;
        while b < BINOM_COLS {
            t[a][b] = if a == 0 {
                0
            } else {
                t[a - 1][b - 1] + t[a - 1][b]
            };
            b += 1;
        }
        a += 1;
    }
    t
};

/// Binomial coefficient C(a, b) (0 when b > a), exact whenever it fits in `usize`, and
/// `usize::MAX` when it does not (no polynomial has that many coefficients, so a count that
/// large can only fail to allocate, as `Vec` does).
///
/// The running value `C(a, i)` of the multiplicative formula `C(a, i + 1) = C(a, i)(a − i)/(i + 1)`
/// grows with `i ≤ b ≤ a/2` towards the result, so when the result fits in `usize` every
/// product `C(a, i)(a − i) = C(a, i + 1)(i + 1)` fits in `u128` and every division is exact.
/// (In `usize` the product overflowed first: C(64, 32) fits, its last product does not.)
///
/// ```
/// use algesurf_bb::multi_index::binomial;
/// assert_eq!(binomial(64, 32), 1_832_624_140_942_590_534);
/// assert_eq!(binomial(3, 5), 0);
/// assert_eq!(binomial(200, 100), usize::MAX); // ~9.1e58 does not fit
/// ```
#[inline]
pub const fn binomial(a: usize, b: usize) -> usize {
    if a < BINOM_ROWS && b < BINOM_COLS {
        return BINOM[a][b];
    }
    if b > a {
        return 0;
    }
    let b = if b > a - b { a - b } else { b };
    let mut r: u128 = 1;
    let mut i = 0;
    while i < b {
        // r = C(a, i) ≤ usize::MAX here, so the product fits in u128.
        r = r * (a - i) as u128 / (i + 1) as u128;
        if r > usize::MAX as u128 {
            return usize::MAX;
        }
        i += 1;
    }
    r as usize
}

/// Binomial coefficient C(a, b) as `f64` (0 when b > a), for weights: correctly rounded while
/// the products `C(a, i + 1)(i + 1)` fit in `u128` (the exact integer, rounded once; a ≤ 125
/// always), beyond that within a relative `2b·u` (u = 2^−53: the multiplicative formula
/// continued in `f64`, two roundings a step), and `+∞` beyond `f64`'s range
/// (C(1030, 515) ≈ 2.9e308). Equal to `binomial(a, b) as f64` wherever that is exact.
///
/// ```
/// use algesurf_bb::multi_index::binomial_f64;
/// assert_eq!(binomial_f64(64, 32), 1_832_624_140_942_590_534u64 as f64);
/// let c = binomial_f64(1000, 500); // ≈ 2.7029e299
/// assert!((c / 2.702882409454365e299 - 1.0).abs() < 1e-12);
/// ```
pub fn binomial_f64(a: usize, b: usize) -> f64 {
    if b > a {
        return 0.0;
    }
    let b = b.min(a - b);
    let mut r: u128 = 1;
    let mut i = 0;
    // Exact while C(a, i + 1)(i + 1) fits in u128 (see `binomial`).
    while i < b {
        match r.checked_mul((a - i) as u128) {
            Some(p) => r = p / (i + 1) as u128,
            None => break,
        }
        i += 1;
    }
    let mut x = r as f64;
    while i < b {
        x = x * (a - i) as f64 / (i + 1) as f64;
        i += 1;
    }
    x
}

/// Number of multi-indices of degree `n` in `N` variables: C(n + N − 1, N − 1).
#[inline]
pub const fn count<const N: usize>(n: usize) -> usize {
    if N == 0 {
        return 0;
    }
    binomial(n.saturating_add(N - 1), N - 1)
}

/// The degree |λ| of a multi-index.
#[inline]
pub fn degree<const N: usize>(lambda: &MultiIndex<N>) -> usize {
    lambda.iter().sum()
}

/// Position of `lambda` in the storage order of its degree (O(N)).
///
/// At position k, with r = n − Σ_{i<k} λ_i still to distribute over m = N − k variables, the
/// indices that precede λ are those whose k-th entry exceeds λ_k; by the hockey-stick identity
/// there are C(r − λ_k − 1 + m − 1, m − 1) of them.
#[inline]
pub fn rank<const N: usize>(lambda: &MultiIndex<N>) -> usize {
    let mut r = degree(lambda);
    let mut pos = 0;
    for k in 0..N.saturating_sub(1) {
        let m = N - k;
        if r > lambda[k] {
            pos += binomial(r - lambda[k] - 1 + m - 1, m - 1);
        }
        r -= lambda[k];
    }
    pos
}

/// The multi-index of degree `n` at position `r` of the storage order (O(N·n)).
///
/// # Panics
/// Panics if `r >= count::<N>(n)`; use [`checked_unrank`] for untrusted input.
pub fn unrank<const N: usize>(n: usize, r: usize) -> MultiIndex<N> {
    checked_unrank(n, r).expect("rank out of range")
}

/// The multi-index of degree `n` at position `r`, or `None` when `r` is out of range.
pub fn checked_unrank<const N: usize>(n: usize, mut r: usize) -> Option<MultiIndex<N>> {
    if N == 0 || r >= count::<N>(n) {
        return None;
    }
    let mut lambda = [0; N];
    let mut rem = n;
    for (k, slot) in lambda.iter_mut().enumerate().take(N - 1) {
        let m = N - k;
        // Entry values a = rem, rem−1, …: each block holds count::<m−1>(rem − a) indices.
        let mut a = rem;
        loop {
            let block = binomial(rem - a + m - 2, m - 2);
            if r < block {
                break;
            }
            r -= block;
            a -= 1;
        }
        *slot = a;
        rem -= a;
    }
    lambda[N - 1] = rem;
    Some(lambda)
}

/// The successor of `lambda` in storage order, or `None` at the last index (`n e_{N−1}`).
#[inline]
pub fn next<const N: usize>(lambda: &MultiIndex<N>) -> Option<MultiIndex<N>> {
    if N < 2 {
        return None;
    }
    // Largest k ≤ N−2 with λ_k > 0: decrement it and move everything after it to k+1.
    let k = (0..N - 1).rev().find(|&k| lambda[k] > 0)?;
    let mut out = *lambda;
    let tail: usize = lambda[k + 1..].iter().sum();
    out[k] -= 1;
    for v in out[k + 1..].iter_mut() {
        *v = 0;
    }
    out[k + 1] = tail + 1;
    Some(out)
}

/// All multi-indices of degree `n` in storage order.
pub fn iter<const N: usize>(n: usize) -> impl Iterator<Item = MultiIndex<N>> {
    let mut first = [0; N];
    if N > 0 {
        first[0] = n;
    }
    std::iter::successors((N > 0).then_some(first), next)
}

/// The multi-indices of degree `n` whose entry `j` equals `s` (the layer `λ_j = s`), in
/// storage order. This is the index set of the coefficients that make up B_s(q) in (4.8) of
/// Xu–Huang–Bajaj 2001.
pub fn layer<const N: usize>(n: usize, j: usize, s: usize) -> impl Iterator<Item = MultiIndex<N>> {
    iter::<N>(n).filter(move |l| j < N && l[j] == s)
}

/// The unit multi-index `e_i` scaled by `n`: the label of vertex `i` in degree `n`.
#[inline]
pub fn vertex<const N: usize>(n: usize, i: usize) -> MultiIndex<N> {
    let mut l = [0; N];
    l[i] = n;
    l
}

/// Multinomial coefficient n!/(λ_0!⋯λ_{N−1}!) as f64: the product of the binomials
/// `C(λ_0 + … + λ_k, λ_k)` ([`binomial_f64`]), so exact below 2^53 (n ≤ 20 always) and within
/// a relative `(2n + N)·u` beyond; `+∞` beyond `f64`'s range (n > 1029 for two variables).
///
/// ```
/// use algesurf_bb::multi_index::multinomial;
/// assert_eq!(multinomial(&[1, 1, 1]), 6.0);
/// // C(100, 50) ≈ 1.0089e29: right at degrees where an integer product would overflow.
/// assert!((multinomial(&[50, 50]) / 1.0089134454556419e29 - 1.0).abs() < 1e-14);
/// ```
pub fn multinomial<const N: usize>(lambda: &MultiIndex<N>) -> f64 {
    let mut acc = 1.0;
    let mut sum = 0;
    for &l in lambda {
        sum += l;
        acc *= binomial_f64(sum, l);
    }
    acc
}
