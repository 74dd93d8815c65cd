//! Minimum-norm solutions of consistent, possibly rank-deficient linear systems `A x = d`
//! through an orthonormal basis of `A`'s row space (Gram–Schmidt with reorthogonalisation).
//!
//! The minimum-norm solution lies in the row space: `x = Qᵀ z` with the rows of `Q` an
//! orthonormal basis of it. Gram–Schmidt over the rows of `A`, in order, writes each kept row as
//! `a_k = Σ_{j<k} h_kj q_j + h_kk q_k` — lower-triangular in the kept rows — so `z` follows from
//! forward substitution on the kept equations; a row whose component orthogonal to the earlier
//! ones is below the rank tolerance is a combination of them and is dropped (for a consistent
//! system its equation is implied). This is the QR factorisation of `Aᵀ` with dependent columns
//! skipped, `x = A⁺ d` for consistent `d`; "twice is enough" (Giraud, Langou, Rozložník, 2005):
//! two Gram–Schmidt passes give orthogonality to working precision for any numerically
//! nonsingular set, which is what makes the result as accurate as the SVD it replaces (the
//! second pass is skipped where the first did not cancel, the classical criterion).

/// Orthonormal basis of the row space of a dense row-major `m × n` matrix, with the
/// triangular coefficients of the kept rows.
///
/// A basis is factored ([`RowBasis::factor`]) and solved ([`RowBasis::solve_into`]) in its
/// own buffers and the caller's, so that one basis serves many small systems without
/// allocating (the split faces' dense step, `constrained::DenseScratch`).
#[derive(Debug, Default)]
pub(crate) struct RowBasis {
    n: usize,
    /// Indices of the kept rows, in order.
    kept: Vec<usize>,
    /// Orthonormal rows, `kept.len() × n`.
    q: Vec<f64>,
    /// `h[k][j]` (`j ≤ k`), row-major `kept.len() × kept.len()`.
    h: Vec<f64>,
    /// Work space of [`RowBasis::factor`]: the packed rows of `h`, the current row's
    /// coefficients and the row being orthogonalised.
    packed: Vec<f64>,
    hk: Vec<f64>,
    v: Vec<f64>,
}

impl RowBasis {
    /// The basis of `a` ([`RowBasis::factor`] on a new basis).
    #[cfg(test)]
    pub(crate) fn new(a: &[f64], m: usize, n: usize, rel_tol: f64) -> Self {
        let mut basis = RowBasis::default();
        basis.factor(a, m, n, rel_tol);
        basis
    }

    /// Factors `a` (`m × n`, row-major) into this basis, replacing what it held and reusing
    /// its buffers. Rows whose residual after projection is at most `rel_tol` times the
    /// largest row norm are dropped as dependent.
    pub(crate) fn factor(&mut self, a: &[f64], m: usize, n: usize, rel_tol: f64) {
        debug_assert_eq!(a.len(), m * n);
        let max_norm = (0..m)
            .map(|i| {
                a[i * n..(i + 1) * n]
                    .iter()
                    .map(|x| x * x)
                    .sum::<f64>()
                    .sqrt()
            })
            .fold(0.0, f64::max);
        let cut = rel_tol * max_norm;
        // At most min(m, n) rows are kept.
        let most = m.min(n);
        self.n = n;
        let (kept, q, coeffs) = (&mut self.kept, &mut self.q, &mut self.packed);
        kept.clear();
        q.clear();
        // `h` row k (k + 1 entries) at `coeffs[k(k+1)/2..]`.
        coeffs.clear();
        let (hk, v) = (&mut self.hk, &mut self.v);
        hk.clear();
        hk.resize(most, 0.0);
        v.clear();
        v.resize(n, 0.0);
        let norm_of = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
        for i in 0..m {
            let r = kept.len();
            if r == n {
                // The kept rows span R^n: every further row's residual is rounding, below the
                // cut, so it would be dropped; skip the projection.
                break;
            }
            v.copy_from_slice(&a[i * n..(i + 1) * n]);
            let before = norm_of(v);
            if before <= cut {
                // Projection only shrinks the norm, so the residual is below the cut too
                // (zero rows: equations whose unknowns were all eliminated).
                continue;
            }
            hk[..=r].fill(0.0);
            let mut norm = before;
            // Second pass only where the first cancelled more than half the norm (Daniel,
            // Gragg, Kaufman, Stewart 1976): otherwise one pass is already orthogonal to
            // working precision. A row whose first-pass residual is below the cut is dependent
            // whatever the second pass would say: the basis is orthonormal to ~ε, so the first
            // pass's residual is exact to ~ε·|row|, far below the cut.
            for pass in 0..2 {
                if pass == 1 && (norm <= cut || norm >= 0.5 * before) {
                    break;
                }
                for j in 0..r {
                    let qj = &q[j * n..(j + 1) * n];
                    let d: f64 = qj.iter().zip(v.iter()).map(|(a, b)| a * b).sum();
                    hk[j] += d;
                    for (x, y) in v.iter_mut().zip(qj) {
                        *x -= d * y;
                    }
                }
                norm = norm_of(v);
            }
            if norm <= cut || norm == 0.0 {
                continue;
            }
            hk[r] = norm;
            q.extend(v.iter().map(|x| x / norm));
            kept.push(i);
            coeffs.extend_from_slice(&hk[..=r]);
        }
        let r = kept.len();
        self.h.clear();
        self.h.resize(r * r, 0.0);
        for k in 0..r {
            let start = k * (k + 1) / 2;
            self.h[k * r..k * r + k + 1].copy_from_slice(&coeffs[start..start + k + 1]);
        }
    }

    /// [`RowBasis::solve_into`] into new vectors.
    #[cfg(test)]
    pub(crate) fn solve(&self, d: &[f64]) -> Vec<f64> {
        let (mut z, mut x) = (Vec::new(), Vec::new());
        self.solve_into(d, &mut z, &mut x);
        x
    }

    /// The minimum-norm `x` with `A x = d` on the kept rows (all rows when `d` is consistent),
    /// written into `x`, with `z` for the triangular solve (both overwritten).
    pub(crate) fn solve_into(&self, d: &[f64], z: &mut Vec<f64>, x: &mut Vec<f64>) {
        let r = self.kept.len();
        z.clear();
        z.resize(r, 0.0);
        for k in 0..r {
            let row = &self.h[k * r..(k + 1) * r];
            let s: f64 = (0..k).map(|j| row[j] * z[j]).sum();
            z[k] = (d[self.kept[k]] - s) / row[k];
        }
        x.clear();
        x.resize(self.n, 0.0);
        for (k, zk) in z.iter().enumerate() {
            for (xi, qi) in x.iter_mut().zip(&self.q[k * self.n..(k + 1) * self.n]) {
                *xi += zk * qi;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn minimum_norm_solution_of_a_system_with_repeated_rows() {
        // Rows 0 and 2 repeat, row 3 = row 0 + row 1; rank 2 in R^3.
        let a = [
            1.0, 2.0, 0.0, //
            0.0, 1.0, 1.0, //
            1.0, 2.0, 0.0, //
            1.0, 3.0, 1.0,
        ];
        let x_true = [0.3, -0.2, 0.5];
        let d: Vec<f64> = (0..4)
            .map(|i| (0..3).map(|j| a[i * 3 + j] * x_true[j]).sum())
            .collect();
        let basis = RowBasis::new(&a, 4, 3, 1e-10);
        assert_eq!(basis.kept, vec![0, 1]);
        let x = basis.solve(&d);
        for i in 0..4 {
            let ax: f64 = (0..3).map(|j| a[i * 3 + j] * x[j]).sum();
            assert!((ax - d[i]).abs() < 1e-14, "row {i}");
        }
        // Minimum norm: x is orthogonal to the null space, spanned by (2, −1, 1).
        let null = [2.0, -1.0, 1.0];
        let dot: f64 = x.iter().zip(null).map(|(a, b)| a * b).sum();
        assert!(dot.abs() < 1e-14);
    }
}
