//! Fixed-size kernels for trivariate cubics in BB form (20 coefficients in the storage order of
//! [`algesurf_bb::multi_index`]): blossoms, shooting polynomials and gradients without
//! allocation.
//!
//! Everything here is the blossom (polar form) `b[a, b, c]` of the cubic, computed by three
//! de Casteljau steps on fixed arrays (de Casteljau's algorithm *is* the blossom evaluated at
//! repeated arguments; Farin, "Curves and Surfaces for CAGD", §3 and §18):
//!
//! * the shooting polynomial (4.8)/(4.9) along the segment from `a` to `b` has Bernstein
//!   coefficients `b_k = b[a^{3−k}, b^k]`, k = 0..3;
//! * the formal partials are `∂F/∂τ_i = 3 b[τ, τ, e_i]`;
//! * a coefficient of the cubic continued onto another tetrahedron is the blossom at that
//!   tetrahedron's vertices (Lemma 2.2), a linear form in the 20 coefficients whose weights are
//!   [`blossom_weights`].
//!
//! These replace [`algesurf_bb::BbPoly::restrict_to_segment`] / `blossom` /
//! `directional_derivative` on the hot paths (one call per ray of the tessellation and of the
//! Step 6 bounds); they compute the same multilinear forms with the same kind of convex-
//! combination arithmetic, so they agree with those to rounding (tested below).

/// Rank of a 4-index of degree `n` in reverse lexicographic order (λ_0 decreasing, then λ_1, …).
const fn rank(l: [usize; 4], n: usize) -> usize {
    let mut r = 0;
    let mut a = n;
    // Count the indices before `l`: those with a larger λ_0, then equal λ_0 and larger λ_1, …
    while a > l[0] {
        let rest = n - a;
        r += (rest + 1) * (rest + 2) / 2;
        a -= 1;
    }
    let rest = n - l[0];
    let mut b = rest;
    while b > l[1] {
        r += rest - b + 1;
        b -= 1;
    }
    r + (rest - l[1] - l[2])
}

/// `UP[r][i]`: rank in degree `n` of `unrank_{n−1}(r) + e_i`.
const fn up_table<const M: usize>(n: usize) -> [[usize; 4]; M] {
    let mut t = [[0usize; 4]; M];
    let d = n - 1;
    let mut a = d as isize;
    while a >= 0 {
        let mut b = (d as isize) - a;
        while b >= 0 {
            let mut c = (d as isize) - a - b;
            while c >= 0 {
                let l = [a as usize, b as usize, c as usize, d - (a + b + c) as usize];
                let r = rank(l, d);
                let mut i = 0;
                while i < 4 {
                    let mut k = l;
                    k[i] += 1;
                    t[r][i] = rank(k, n);
                    i += 1;
                }
                c -= 1;
            }
            b -= 1;
        }
        a -= 1;
    }
    t
}

const UP3: [[usize; 4]; 10] = up_table::<10>(3);
const UP2: [[usize; 4]; 4] = up_table::<4>(2);

/// `(RANK3, INDICES3)` in one pass over the degree-3 indices.
const TABLES3: ([[[usize; 4]; 4]; 4], [[usize; 4]; 20]) = {
    let mut ranks = [[[0usize; 4]; 4]; 4];
    let mut indices = [[0usize; 4]; 20];
    let mut a = 0;
    while a <= 3 {
        let mut b = 0;
        while a + b <= 3 {
            let mut c = 0;
            while a + b + c <= 3 {
                let l = [a, b, c, 3 - a - b - c];
                let r = rank(l, 3);
                ranks[a][b][c] = r;
                indices[r] = l;
                c += 1;
            }
            b += 1;
        }
        a += 1;
    }
    (ranks, indices)
};

/// `RANK3[16 λ_0 + 4 λ_1 + λ_2]`: the rank of the degree-3 index
/// `(λ_0, λ_1, λ_2, 3 − λ_0 − λ_1 − λ_2)` (entries with `λ_0 + λ_1 + λ_2 > 3` unused). Flat
/// bytes, one cache line, indexed with a mask that the compiler sees is in range: the nested
/// `usize` table cost three bounds checks per lookup, and `rank3` runs about a thousand times
/// per face (the edge cubics' blossoms, the split faces' mid-edge rows).
const RANK3: [u8; 64] = {
    let mut flat = [0u8; 64];
    let mut k = 0;
    while k < 64 {
        flat[k] = TABLES3.0[k >> 4][(k >> 2) & 3][k & 3] as u8;
        k += 1;
    }
    flat
};

/// The 20 multi-indices of degree 3 in storage order (`INDICES3[rank3(l)] == l`): a table
/// for the hot loops, which `algesurf_bb::multi_index::iter` would walk by successor steps.
pub(crate) const INDICES3: [[usize; 4]; 20] = TABLES3.1;

/// Rank of a degree-3 multi-index in storage order (the same as
/// `algesurf_bb::multi_index::rank`, by table).
#[inline]
pub(crate) fn rank3(l: [usize; 4]) -> usize {
    debug_assert!(
        l[0] <= 3 && l[1] <= 3 && l[2] <= 3,
        "a degree-3 index: {l:?}"
    );
    RANK3[((l[0] << 4) | (l[1] << 2) | l[2]) & 63] as usize
}

/// The C0/C1 rows of a join between two tetrahedra A and B sharing a face, in index form
/// (see `split`'s `System::join`): for every coefficient `λ` of B with `λ_opp ≤ 1`, in storage
/// order, B's rank and either A's rank of `μ` (the shared part of `λ` in A's indexing; a C0
/// row, `λ_opp = 0`) or A's ranks of `μ + e_k`, k = 0..3 (a C1 row, `λ_opp = 1`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct JoinPattern {
    /// A's vertex of each of B's vertices (`None` for the one not shared).
    pub(crate) shared: [Option<usize>; 4],
    /// B's vertex not shared with A.
    pub(crate) opp: usize,
    /// `(B's rank, the row)`: 10 C0 rows and 6 C1 rows, in B's storage order.
    pub(crate) rows: [(usize, JoinRow); 16],
}

/// What B's coefficient `λ` equals in a join ([`JoinPattern`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum JoinRow {
    /// `λ_opp = 0`: A's coefficient at this rank (of `μ`, the shared part of `λ`).
    C0(usize),
    /// `λ_opp = 1`: `Σ_k v_k a_{μ + e_k}`, A's ranks of `μ + e_k` for k = 0..3.
    C1([usize; 4]),
}

impl JoinPattern {
    /// The pattern of a join where B's vertex `s` is A's vertex `shared[s]` (`None` for the
    /// one vertex of B that A lacks).
    pub(crate) const fn new(shared: [Option<usize>; 4]) -> JoinPattern {
        let mut opp = 0;
        while shared[opp].is_some() {
            opp += 1;
        }
        let mut rows = [(0usize, JoinRow::C0(0)); 16];
        let mut n = 0;
        let mut r = 0;
        while r < 20 {
            let lambda = INDICES3[r];
            if lambda[opp] <= 1 {
                let mut mu = [0usize; 4];
                let mut s = 0;
                while s < 4 {
                    if let Some(k) = shared[s] {
                        mu[k] += lambda[s];
                    }
                    s += 1;
                }
                if lambda[opp] == 0 {
                    rows[n] = (r, JoinRow::C0(rank(mu, 3)));
                } else {
                    let mut up = [0usize; 4];
                    let mut k = 0;
                    while k < 4 {
                        let mut l = mu;
                        l[k] += 1;
                        up[k] = rank(l, 3);
                        k += 1;
                    }
                    rows[n] = (r, JoinRow::C1(up));
                }
                n += 1;
            }
            r += 1;
        }
        JoinPattern { shared, opp, rows }
    }
}

/// The 20 BB coefficients of a cubic on a tetrahedron.
pub(crate) type Coeffs = [f64; 20];

/// The coefficients of a `BbPoly` of degree 3 in four variables as a fixed array.
pub(crate) fn coeffs_of(poly: &algesurf_bb::BbPoly<f64, 4>) -> Coeffs {
    poly.coeffs()
        .try_into()
        .expect("a trivariate cubic has 20 coefficients")
}

#[inline]
fn step3(c: &Coeffs, a: [f64; 4]) -> [f64; 10] {
    std::array::from_fn(|r| {
        let u = UP3[r];
        a[0] * c[u[0]] + a[1] * c[u[1]] + a[2] * c[u[2]] + a[3] * c[u[3]]
    })
}

#[inline]
fn step2(c: &[f64; 10], a: [f64; 4]) -> [f64; 4] {
    std::array::from_fn(|r| {
        let u = UP2[r];
        a[0] * c[u[0]] + a[1] * c[u[1]] + a[2] * c[u[2]] + a[3] * c[u[3]]
    })
}

#[inline]
fn dot(c: [f64; 4], a: [f64; 4]) -> f64 {
    a[0] * c[0] + a[1] * c[1] + a[2] * c[2] + a[3] * c[3]
}

/// The blossom `b[a, b, c]` of the cubic.
pub(crate) fn blossom(c: &Coeffs, a: [f64; 4], b: [f64; 4], d: [f64; 4]) -> f64 {
    dot(step2(&step3(c, a), b), d)
}

/// Bernstein coefficients `b_k = b[a^{3−k}, b^k]` of the cubic restricted to the segment from
/// `a` to `b` (barycentric points): the shooting polynomial of (4.8)/(4.9).
pub(crate) fn segment(c: &Coeffs, a: [f64; 4], b: [f64; 4]) -> [f64; 4] {
    let ca = step3(c, a);
    let cb = step3(c, b);
    let caa = step2(&ca, a);
    let cbb = step2(&cb, b);
    [dot(caa, a), dot(caa, b), dot(cbb, a), dot(cbb, b)]
}

/// `p[0] + p[1] + p[2] + p[3]` (left to right, like [`step3`]) over the terms whose bit is set
/// in the mask `M`, the others being products with an exact zero coordinate.
///
/// Why this equals the full sum: a skipped term is `0 · c = ±0`, and `x + (±0) = x` exactly for
/// every `x` (also when the zero comes first: `±0 + x = x`), except that the sign of an exact
/// zero result can differ (`−0 + +0 = +0`). Comparisons treat ±0 alike, so every decision
/// taken on the result is the same.
#[inline(always)]
fn sum_masked<const M: u8>(p: [f64; 4]) -> f64 {
    let mut acc = 0.0;
    let mut first = true;
    for (i, &x) in p.iter().enumerate() {
        if M >> i & 1 == 1 {
            if first {
                acc = x;
                first = false;
            } else {
                acc += x;
            }
        }
    }
    acc
}

/// [`step3`] for an argument that is zero outside the mask `M` (bit i: coordinate i).
#[inline(always)]
fn step3_masked<const M: u8>(c: &Coeffs, a: [f64; 4]) -> [f64; 10] {
    std::array::from_fn(|r| {
        let u = UP3[r];
        sum_masked::<M>([
            a[0] * c[u[0]],
            a[1] * c[u[1]],
            a[2] * c[u[2]],
            a[3] * c[u[3]],
        ])
    })
}

/// [`step2`] for an argument that is zero outside the mask `M`.
#[inline(always)]
fn step2_masked<const M: u8>(c: &[f64; 10], a: [f64; 4]) -> [f64; 4] {
    std::array::from_fn(|r| {
        let u = UP2[r];
        sum_masked::<M>([
            a[0] * c[u[0]],
            a[1] * c[u[1]],
            a[2] * c[u[2]],
            a[3] * c[u[3]],
        ])
    })
}

/// [`segment`] for end points that vanish outside the masks `MA` and `MB` (bit i: coordinate
/// i): the products with the zero coordinates are skipped, which leaves the result of
/// `segment(c, a, b)` bit for bit, up to the sign of exact zeros (see `sum_masked`). The rays
/// of the tessellation have two or three nonzero coordinates at each end, so this does about
/// half the work. Debug builds check the masks.
#[inline]
pub(crate) fn segment_masked<const MA: u8, const MB: u8>(
    c: &Coeffs,
    a: [f64; 4],
    b: [f64; 4],
) -> [f64; 4] {
    debug_assert!(
        (0..4).all(|i| MA >> i & 1 == 1 || a[i] == 0.0),
        "a outside its mask"
    );
    debug_assert!(
        (0..4).all(|i| MB >> i & 1 == 1 || b[i] == 0.0),
        "b outside its mask"
    );
    let ca = step3_masked::<MA>(c, a);
    let cb = step3_masked::<MB>(c, b);
    let caa = step2_masked::<MA>(&ca, a);
    let cbb = step2_masked::<MB>(&cb, b);
    [
        sum_masked::<MA>(std::array::from_fn(|i| a[i] * caa[i])),
        sum_masked::<MB>(std::array::from_fn(|i| b[i] * caa[i])),
        sum_masked::<MA>(std::array::from_fn(|i| a[i] * cbb[i])),
        sum_masked::<MB>(std::array::from_fn(|i| b[i] * cbb[i])),
    ]
}

/// Value at `tau` by de Casteljau's algorithm on the fixed-size coefficients: the same bits as
/// [`algesurf_bb::BbPoly::eval`] (tested), without its generic loops.
pub(crate) fn value(c: &Coeffs, tau: [f64; 4]) -> f64 {
    dot(step2(&step3(c, tau), tau), tau)
}

/// Value and formal partials `∂F/∂τ_i = 3 b[τ, τ, e_i]` at `tau`.
pub(crate) fn value_partials(c: &Coeffs, tau: [f64; 4]) -> (f64, [f64; 4]) {
    let c1 = step2(&step3(c, tau), tau);
    (dot(c1, tau), c1.map(|x| 3.0 * x))
}

/// The midpoint `m = (e_0 + e_1)/2` of the first edge of a tetrahedron, in barycentric
/// coordinates: where the split faces' mid-edge rows take `D_d F(m) = 3 b[d, m, m]`.
pub(crate) const FIRST_EDGE_MIDPOINT: [f64; 4] = [0.5, 0.5, 0.0, 0.0];

/// The terms of [`blossom_weights`]`(d, m, m)` for `m` = [`FIRST_EDGE_MIDPOINT`] that its loops
/// do not skip for `m`, in their order: `(i, rank of e_i + e_j + e_k)` for the `j, k` where
/// `m` is not zero (both such components are ½, which [`first_edge_midpoint_weights`] uses as
/// a literal: checked here at compile time).
const FIRST_EDGE_MIDPOINT_TERMS: [(usize, u8); 16] = {
    let m = FIRST_EDGE_MIDPOINT;
    let mut terms = [(0usize, 0u8); 16];
    let mut t = 0;
    let mut i = 0;
    while i < 4 {
        let mut j = 0;
        while j < 4 {
            let mut k = 0;
            while k < 4 {
                if m[j] != 0.0 && m[k] != 0.0 {
                    assert!(m[j] == 0.5 && m[k] == 0.5, "m's non-zero components are ½");
                    let mut l = [0usize; 4];
                    l[i] += 1;
                    l[j] += 1;
                    l[k] += 1;
                    terms[t] = (i, RANK3[(l[0] << 4) | (l[1] << 2) | l[2]]);
                    t += 1;
                }
                k += 1;
            }
            j += 1;
        }
        i += 1;
    }
    assert!(t == 16, "two non-zero components of m");
    terms
};

/// [`blossom_weights`]`(d, m, m)` for `m` = [`FIRST_EDGE_MIDPOINT`], bit for bit for a finite
/// `d` (an infinite or NaN component gives a NaN weight either way, not always the same
/// ones): the same products `(d_i · m_j) · m_k = (d_i · ½) · ½`, skipped where `d_i · ½` is
/// zero as there, added to the same weights in the same order, with the loops over `m`'s zero
/// components and the ranks worked out at compile time. The split faces make twelve of these
/// rows per face: the general loops and their 192 rank lookups per face were 1.6 % of the
/// bunny's instructions (`cachegrind`, `algesurf smooth` at 3 × 2: `split::constraints`
/// 655 M → 399 M; reading `m_j`, `m_k` from the array instead of the literal gave 713 M).
pub(crate) fn first_edge_midpoint_weights(d: [f64; 4]) -> Coeffs {
    let mut w = [0.0; 20];
    for &(i, rank) in &FIRST_EDGE_MIDPOINT_TERMS {
        let ab = d[i] * 0.5;
        if ab != 0.0 {
            w[rank as usize] += ab * 0.5;
        }
    }
    w
}

/// Weights `w` with `b[a, b, d] = Σ_μ w[rank μ] c_μ` for every cubic `c`: the blossom of each
/// Bernstein basis polynomial, `Σ a_i b_j d_k` over the ordered triples with `e_i + e_j + e_k = μ`
/// (the polar form of `B_μ = 3!/μ! τ^μ` is `μ!/3!` times that sum, and the factors cancel).
pub(crate) fn blossom_weights(a: [f64; 4], b: [f64; 4], d: [f64; 4]) -> Coeffs {
    let mut w = [0.0; 20];
    for i in 0..4 {
        for j in 0..4 {
            let ab = a[i] * b[j];
            if ab == 0.0 {
                continue;
            }
            for k in 0..4 {
                // A zero factor adds ±0 to the weight, which changes no sum: skipped (the
                // mid-edge rows' `m` has two zero components).
                if d[k] == 0.0 {
                    continue;
                }
                let mut l = [0usize; 4];
                l[i] += 1;
                l[j] += 1;
                l[k] += 1;
                w[rank3(l)] += ab * d[k];
            }
        }
    }
    w
}

/// `ARGS3[rank3(λ)]`: the vertices of the three blossom arguments of the coefficient `λ`,
/// vertex `s` repeated `λ[s]` times, in vertex order (a table, so that the hot loops over the
/// 20 coefficients index with constants instead of counting out each `λ`).
pub(crate) const ARGS3: [[usize; 3]; 20] = {
    let mut args = [[0usize; 3]; 20];
    let mut r = 0;
    while r < 20 {
        let l = INDICES3[r];
        let mut n = 0;
        let mut s = 0;
        while s < 4 {
            let mut k = 0;
            while k < l[s] {
                args[r][n] = s;
                n += 1;
                k += 1;
            }
            s += 1;
        }
        r += 1;
    }
    args
};

/// The vertices of the three blossom arguments of the coefficient `lambda`: vertex `s`
/// repeated `lambda[s]` times, in vertex order ([`ARGS3`]).
pub(crate) fn arg_vertices(lambda: [usize; 4]) -> [usize; 3] {
    debug_assert_eq!(lambda.iter().sum::<usize>(), 3, "a cubic coefficient");
    ARGS3[rank3(lambda)]
}

/// The three blossom arguments of the coefficient `lambda`: `verts[s]` repeated `lambda[s]`
/// times ([`arg_vertices`]).
pub(crate) fn blossom_args(verts: &[[f64; 4]; 4], lambda: [usize; 4]) -> [[f64; 4]; 3] {
    arg_vertices(lambda).map(|s| verts[s])
}

#[cfg(test)]
mod tests {
    use super::*;
    use algesurf_bb::{BbPoly, multi_index};

    /// The value of [`value_partials`] is de Casteljau's ([`BbPoly::eval`]) bit for bit: the
    /// same products summed in the same order (`FaceCubic::value` and the check battery rely
    /// on it to give the generic evaluation's values without its generic loops).
    #[test]
    fn the_value_of_value_partials_is_de_casteljaus_bit_for_bit() {
        let mut rng = algesurf_mesh::test_rng::Lcg(3);
        for case in 0..20_000 {
            let p = BbPoly::<f64, 4>::from_fn(3, |_| rng.next() * 2.0 - 1.0);
            // Inside the tetrahedron and outside it (a negative coordinate).
            let mut tau = [rng.next() * 1.4 - 0.2, rng.next(), rng.next(), 0.0];
            tau[3] = 1.0 - tau[0] - tau[1] - tau[2];
            let c = coeffs_of(&p);
            assert_eq!(
                value_partials(&c, tau).0.to_bits(),
                p.eval(tau).to_bits(),
                "case {case}"
            );
            assert_eq!(
                value(&c, tau).to_bits(),
                p.eval(tau).to_bits(),
                "case {case}"
            );
        }
    }

    /// Every row of a join pattern is the rank arithmetic spelled out: B's index `λ`, A's
    /// shared part `μ`, and `μ + e_k`, for every way two tetrahedra can share a face.
    #[test]
    fn join_patterns_are_the_ranks_of_the_shared_indices() {
        for opp in 0..4 {
            let perms = (0..27)
                .map(|x: usize| [x / 9, x / 3 % 3, x % 3])
                .filter(|p| p[0] != p[1] && p[1] != p[2] && p[0] != p[2]);
            for perm in perms {
                for missing in 0..4 {
                    // A's vertices other than `missing`, assigned to B's shared ones.
                    let others: Vec<usize> = (0..4).filter(|&k| k != missing).collect();
                    let mut shared = [None; 4];
                    let mut next = perm.iter().map(|&i| others[i]);
                    for (s, slot) in shared.iter_mut().enumerate() {
                        if s != opp {
                            *slot = next.next();
                        }
                    }
                    let pattern = JoinPattern::new(shared);
                    assert_eq!(pattern.opp, opp);
                    let mut rows = pattern.rows.iter();
                    for (r, lambda) in INDICES3.iter().enumerate() {
                        if lambda[opp] > 1 {
                            continue;
                        }
                        let &(rank, row) = rows.next().expect("16 rows");
                        assert_eq!(rank, r);
                        let mut mu = [0usize; 4];
                        for (s, k) in shared.iter().enumerate() {
                            if let Some(k) = k {
                                mu[*k] += lambda[s];
                            }
                        }
                        if lambda[opp] == 0 {
                            assert_eq!(row, JoinRow::C0(rank3(mu)), "{shared:?} {lambda:?}");
                        } else {
                            let JoinRow::C1(up) = row else {
                                panic!("{shared:?} {lambda:?}: a C1 row");
                            };
                            for (k, &u) in up.iter().enumerate() {
                                let mut l = mu;
                                l[k] += 1;
                                assert_eq!(u, rank3(l), "{shared:?} {lambda:?} + e_{k}");
                            }
                        }
                    }
                    assert!(rows.next().is_none());
                }
            }
        }
    }

    #[test]
    fn blossom_argument_table_repeats_each_vertex_as_the_index_says() {
        for (l, args) in INDICES3.iter().zip(ARGS3) {
            let mut count = [0usize; 4];
            for s in args {
                count[s] += 1;
            }
            assert_eq!(&count, l);
            assert!(
                args.windows(2).all(|w| w[0] <= w[1]),
                "{args:?} in vertex order"
            );
        }
    }

    #[test]
    fn index_tables_are_the_storage_order() {
        let order: Vec<[usize; 4]> = multi_index::iter::<4>(3).collect();
        assert_eq!(order, INDICES3.to_vec());
        for l in order {
            assert_eq!(rank3(l), multi_index::rank(&l));
        }
    }

    fn sample() -> BbPoly<f64, 4> {
        BbPoly::from_fn(3, |l| {
            (l[0] as f64 * 1.3 - l[1] as f64 * 0.7 + (l[2] * l[3]) as f64 * 0.4 + 0.1).sin()
        })
    }

    #[test]
    fn ranks_match_the_storage_order_of_multi_index() {
        for n in 0..=3 {
            for (r, l) in multi_index::iter::<4>(n).enumerate() {
                assert_eq!(rank(l, n), r, "{l:?}");
            }
        }
    }

    #[test]
    fn segment_equals_restrict_to_segment_to_rounding() {
        let p = sample();
        let c = coeffs_of(&p);
        let a = [0.2, 0.5, 0.3, 0.0];
        let b = [0.6, -0.1, 0.0, 0.5];
        let want = p.restrict_to_segment(a, b);
        let got = segment(&c, a, b);
        for k in 0..4 {
            assert!((got[k] - want.coeffs()[k]).abs() < 1e-14, "b_{k}");
        }
    }

    /// `==` on the values with ±0 alike, and the same bits otherwise.
    fn same(x: f64, y: f64) -> bool {
        x == y && (x == 0.0 || x.to_bits() == y.to_bits())
    }

    #[test]
    fn masked_segments_equal_segment_bit_for_bit() {
        let c = coeffs_of(&sample());
        // The ray shapes of the tessellation: face point to apex, edge ray, split-face ray.
        for k in 0..50 {
            let x = (k as f64 * 0.37).fract();
            let y = (k as f64 * 0.61 + 0.1).fract();
            let (p, q) = (x * (1.0 - y), y * 0.7);
            let face = [p, q, 1.0 - p - q, 0.0];
            let apex = [0.0, 0.0, 0.0, 1.0];
            let got = segment_masked::<0b0111, 0b1000>(&c, face, apex);
            let want = segment(&c, face, apex);
            assert!((0..4).all(|i| same(got[i], want[i])), "{got:?} {want:?}");
            let (a, b) = ([0.0, x, 1.0 - x, 0.0], [1.0 - y, 0.0, 0.0, y]);
            let got = segment_masked::<0b0110, 0b1001>(&c, a, b);
            let want = segment(&c, a, b);
            assert!((0..4).all(|i| same(got[i], want[i])), "{got:?} {want:?}");
        }
    }

    #[test]
    fn blossom_weights_reproduce_the_blossom_and_the_directional_derivative() {
        let p = sample();
        let c = coeffs_of(&p);
        let (a, b, d) = (
            [0.1, 0.2, 0.3, 0.4],
            [1.0, 0.0, 0.0, 0.0],
            [-0.5, 0.7, 0.3, 0.5],
        );
        let w = blossom_weights(a, b, d);
        let via_w: f64 = w.iter().zip(&c).map(|(w, c)| w * c).sum();
        let want = p.blossom(&[a, b, d]).unwrap();
        assert!((via_w - want).abs() < 1e-14);
        assert!((blossom(&c, a, b, d) - want).abs() < 1e-14);
        // D_d F(m) = 3 b[d, m, m].
        let m = [0.25, 0.25, 0.5, 0.0];
        let w = blossom_weights(d, m, m).map(|x| 3.0 * x);
        let via_w: f64 = w.iter().zip(&c).map(|(w, c)| w * c).sum();
        assert!((via_w - p.directional_derivative(m, &[d])).abs() < 1e-13);
    }

    /// The first-edge midpoint's weights are the general blossom's, bit for bit, also for
    /// zero, negative-zero and subnormal direction components.
    #[test]
    fn first_edge_midpoint_weights_are_the_general_ones_bit_for_bit() {
        let mut rng = algesurf_mesh::test_rng::Lcg(5);
        let specials = [0.0, -0.0, 5e-324, -1e-310, 1.0, -3.5];
        for case in 0..2000 {
            let d: [f64; 4] = std::array::from_fn(|k| {
                if (case + k) % 5 == 0 {
                    specials[(case / 5 + k) % specials.len()]
                } else {
                    (rng.next() - 0.5) * 10f64.powi((case % 7) as i32 - 3)
                }
            });
            let fast = first_edge_midpoint_weights(d);
            let general = blossom_weights(d, FIRST_EDGE_MIDPOINT, FIRST_EDGE_MIDPOINT);
            assert_eq!(fast.map(f64::to_bits), general.map(f64::to_bits), "{d:?}");
        }
    }

    #[test]
    fn partials_are_the_derivatives_along_the_vertex_directions() {
        let p = sample();
        let c = coeffs_of(&p);
        let tau = [0.1, 0.2, 0.3, 0.4];
        let (v, g) = value_partials(&c, tau);
        assert!((v - p.eval(tau)).abs() < 1e-14);
        for i in 0..4 {
            let mut e = [0.0; 4];
            e[i] = 1.0;
            assert!((g[i] - p.directional_derivative(tau, &[e])).abs() < 1e-13);
        }
    }
}
