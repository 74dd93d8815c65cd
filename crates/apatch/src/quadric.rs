//! Local quadric fits: the default free parameter that gives quadric precision.
//!
//! Theorem 4.2 of Xu–Huang–Bajaj 2001: when the vertex data come from a quadric Q, the face
//! cubic is `Q + [f_0003 − Q(u)] τ_3²`, so `f_0003 = Q(u)` reproduces Q. The face's own data
//! cannot tell which Q: every `Q + c·L²`, with `L` the plane of the face, has the same values
//! and gradients at the three vertices — exactly the free-parameter family. Data off that plane
//! (the neighbours of the face's vertices) fix `c`. [`Quadric::fit`] solves the least-squares
//! problem `Q(p_i) = 0`, `∇Q(p_i) = N_i` over such a neighbourhood; it is exact when the data lie
//! on one quadric, and otherwise a smooth local estimate.

use crate::ApatchError;
use glam::{DMat3, DVec3};
use nalgebra::{DMatrix, DVector};

/// `Q(x) = xᵀ A x + bᵀ x + c` with symmetric `A`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quadric {
    /// Symmetric quadratic part.
    pub a: DMat3,
    /// Linear part.
    pub b: DVec3,
    /// Constant.
    pub c: f64,
}

impl Quadric {
    /// Value at `x`.
    pub fn value(&self, x: DVec3) -> f64 {
        x.dot(self.a * x) + self.b.dot(x) + self.c
    }

    /// Gradient `2 A x + b`.
    pub fn gradient(&self, x: DVec3) -> DVec3 {
        self.a * x * 2.0 + self.b
    }

    /// The 20 BB coefficients (storage order of `algesurf_bb::multi_index`) of Q as a cubic on
    /// `tet`, computed about `origin` (a point near the tetrahedron, to keep the products small).
    ///
    /// The blossom of a quadratic is `Q[x, y] = xᵀ A y + bᵀ(x + y)/2 + c`; about `o` it is
    /// `(x − o)ᵀ A (y − o) + ∇Q(o)ᵀ((x − o) + (y − o))/2 + Q(o)`, the same bilinear form (expand
    /// it). Degree-elevated to a cubic, the blossom is `(Q[x,y] + Q[x,z] + Q[y,z])/3`, and the
    /// coefficient `λ` is that blossom at the vertices repeated as `λ` says (Farin, "Curves and
    /// Surfaces for CAGD", §18): the same polynomial `BbPoly::from_cartesian` produces, without
    /// its generic power-basis composition.
    pub(crate) fn cubic_coefficients(
        &self,
        tet: &algesurf_bb::Tetrahedron,
        origin: DVec3,
    ) -> [f64; 20] {
        let g = self.gradient(origin);
        let q0 = self.value(origin);
        let d: [DVec3; 4] = std::array::from_fn(|i| tet.vertex(i) - origin);
        let mut p = [[0.0; 4]; 4];
        for i in 0..4 {
            for j in i..4 {
                let v = d[i].dot(self.a * d[j]) + g.dot(d[i] + d[j]) * 0.5 + q0;
                p[i][j] = v;
                p[j][i] = v;
            }
        }
        let mut out = [0.0; 20];
        for (&[i, j, k], x) in crate::cubic::ARGS3.iter().zip(out.iter_mut()) {
            *x = (p[i][j] + p[i][k] + p[j][k]) / 3.0;
        }
        out
    }

    /// Least-squares fit to points `p_i` with gradients `N_i`: `Q(p_i) = 0`, `∇Q(p_i) = N_i`.
    ///
    /// The unknowns are expressed about the centroid and scaled by the neighbourhood radius
    /// `h`, and the value equations are divided by `h`, so all equations carry the units of a
    /// gradient and the system's conditioning does not depend on where or how large the mesh
    /// is. Rank deficiency (e.g. all points coplanar, where `Q + c L²` fit equally well) is
    /// resolved by the minimum-norm solution of the scaled problem, which adds no `L²` term.
    pub fn fit(samples: &[(DVec3, DVec3)]) -> Result<Quadric, ApatchError> {
        let (local, centre, h) = local_samples(samples)?;
        if let Some(q) = seminormal_solve(&local) {
            return Ok(Quadric::from_local(&q, centre, h));
        }
        let q = qr_solve(&local)?;
        Ok(Quadric::from_local(&q, centre, h))
    }

    /// The quadric `Q(x) = h·q(y)`, `y = (x − centre)/h`, from the local coefficients
    /// `q = [a₀₀, a₁₁, a₂₂, a₀₁, a₀₂, a₁₂, b₀, b₁, b₂, c]` of
    /// `q(y) = Σ_{k≤l} a_kl y_k y_l + Σ b_k y_k + c` (the unknowns of the fits, which are set up
    /// in those centred, scaled coordinates to keep their systems' entries O(1)).
    pub(crate) fn from_local(q: &[f64], centre: DVec3, h: f64) -> Quadric {
        let al = DMat3::from_cols_array(&[
            q[0],
            q[3] / 2.0,
            q[4] / 2.0,
            q[3] / 2.0,
            q[1],
            q[5] / 2.0,
            q[4] / 2.0,
            q[5] / 2.0,
            q[2],
        ]);
        let bl = DVec3::new(q[6], q[7], q[8]);
        // h·[ (x−c)ᵀ A_l (x−c)/h² + b_lᵀ (x−c)/h + c_l ]
        let a = al / h;
        let b = bl - a * centre * 2.0;
        let c = centre.dot(a * centre) - bl.dot(centre) + h * q[9];
        Quadric { a, b, c }
    }
}

/// One sample of a fit in local coordinates: `y = (x − centre)/h` and the gradient `N`.
type LocalSample = ([f64; 3], [f64; 3]);

/// The samples in local coordinates `y = (x − centre)/h` about their centroid, scaled by the
/// largest distance `h` from it, with that centre and `h`. In them `Q(x) = h·q(y)` with
/// `q(y) = Σ_{k≤l} a_kl y_k y_l + Σ b_k y_k + c` (10 unknowns), so `∇_x Q = ∇_y q`.
fn local_samples(
    samples: &[(DVec3, DVec3)],
) -> Result<(Vec<LocalSample>, DVec3, f64), ApatchError> {
    if samples.len() < 3 {
        return Err(ApatchError::Degenerate(format!(
            "a quadric fit needs at least 3 points, got {}",
            samples.len()
        )));
    }
    let centre = samples.iter().map(|s| s.0).sum::<DVec3>() / samples.len() as f64;
    let h = samples
        .iter()
        .map(|s| s.0.distance(centre))
        .fold(0.0, f64::max);
    if !(h > 0.0 && h.is_finite()) {
        return Err(ApatchError::Degenerate(
            "quadric fit to coincident points".into(),
        ));
    }
    let local = samples
        .iter()
        .map(|(x, n)| (((*x - centre) / h).to_array(), n.to_array()))
        .collect();
    Ok((local, centre, h))
}

/// The fit's least-squares solution (unknowns as in [`Quadric::from_local`]) by Householder QR,
/// then back substitution when `R` is well conditioned and the minimum-norm SVD solution
/// otherwise: the general path, for fits the semi-normal equations do not certify.
fn qr_solve(local: &[LocalSample]) -> Result<[f64; N], ApatchError> {
    // Column-major, 4 rows (value, three gradient components) per sample.
    let rows = local.len() * 4;
    let mut m = vec![0.0; rows * N];
    let mut r = vec![0.0; rows];
    for (s, (y, n)) in local.iter().enumerate() {
        let (value, gradient) = sample_rows(*y);
        let row = 4 * s;
        for (k, v) in value.into_iter().enumerate() {
            m[k * rows + row] = v;
        }
        for (d, entries) in gradient.iter().enumerate() {
            for &(k, v) in entries {
                m[k * rows + row + 1 + d] = v;
            }
        }
        r[row + 1..row + 4].copy_from_slice(n);
    }
    // Householder QR first (`m = Q R`, Q with 10 orthonormal columns): then
    // `‖m x − r‖² = ‖R x − Qᵀr‖² + ‖(I − QQᵀ) r‖²`, so the minimum-norm least-squares
    // solution of `m` is that of the 10 × 10 `R` with right-hand side `Qᵀr`, and `R` has
    // `m`'s singular values (Q is orthonormal). The SVD then works on 10 × 10 instead of
    // 4k × 10 with its 4k × 10 U (Golub–Van Loan §5.4.5, "R-SVD").
    let (rmat, qtr) = householder_r(&mut m, &mut r, rows);
    if let Some(q) = well_conditioned_solve(&rmat, &qtr) {
        return Ok(q);
    }
    let rmat = DMatrix::<f64>::from_fn(N, N, |i, j| rmat[i][j]);
    let svd = rmat.svd(true, true);
    // Singular values below 1e-10 of the largest are treated as zero: they are the
    // rank-deficient directions (coplanar data) or noise at the level of f64 rounding in
    // a system whose entries are O(1) by construction.
    let tol = 1e-10 * svd.singular_values.max();
    let q = svd
        .solve(&DVector::from_column_slice(&qtr), tol)
        .map_err(|e| ApatchError::Degenerate(format!("quadric fit: {e}")))?;
    Ok(std::array::from_fn(|i| q[i]))
}

/// The number of unknowns of a quadric fit.
const N: usize = 10;

/// Householder QR of the column-major `rows × 10` matrix `m` (overwritten), applied to `r` as
/// well: the upper-triangular `R` and the first 10 entries of `Qᵀr` (Golub–Van Loan
/// Algorithm 5.2.1, with the reflector's sign chosen against cancellation, `α = −sign(x₀)‖x‖`).
/// A column already zero below and on the diagonal takes no reflector. Needs `rows ≥ 10`.
fn householder_r(m: &mut [f64], r: &mut [f64], rows: usize) -> ([[f64; N]; N], [f64; N]) {
    debug_assert!(rows >= N && m.len() == rows * N && r.len() == rows);
    let mut v = vec![0.0; rows];
    for k in 0..N {
        let col = &m[k * rows..(k + 1) * rows];
        let norm = col[k..].iter().map(|x| x * x).sum::<f64>().sqrt();
        if norm == 0.0 {
            continue;
        }
        let alpha = if col[k] >= 0.0 { -norm } else { norm };
        // v = x − α e₁, so H x = α e₁ with H = I − 2 v vᵀ / vᵀv.
        v[k..].copy_from_slice(&col[k..]);
        v[k] -= alpha;
        let vv = v[k..].iter().map(|x| x * x).sum::<f64>();
        if vv == 0.0 {
            continue;
        }
        let reflect = |x: &mut [f64]| {
            let s = 2.0 * v[k..].iter().zip(&x[k..]).map(|(a, b)| a * b).sum::<f64>() / vv;
            for (xi, vi) in x[k..].iter_mut().zip(&v[k..]) {
                *xi -= s * vi;
            }
        };
        for j in k + 1..N {
            reflect(&mut m[j * rows..(j + 1) * rows]);
        }
        reflect(r);
        let col = &mut m[k * rows..(k + 1) * rows];
        col[k] = alpha;
        col[k + 1..].fill(0.0);
    }
    let rmat = std::array::from_fn(|i| {
        std::array::from_fn(|j| if j >= i { m[j * rows + i] } else { 0.0 })
    });
    let qtr = std::array::from_fn(|i| r[i]);
    (rmat, qtr)
}

/// The fit's rows at one sample `y` (local coordinates), in the unknowns' order
/// `[a₀₀, a₁₁, a₂₂, a₀₁, a₀₂, a₁₂, b₀, b₁, b₂, c]`: the value row `q(y) = 0` (dense) and the
/// gradient rows `∂q/∂y_d = n_d`, which have four non-zeros each:
/// `∂(y_d²)/∂y_d = 2y_d`, `∂(y_d y_e)/∂y_d = y_e` and `∂(b_d y_d)/∂y_d = 1`.
fn sample_rows(y: [f64; 3]) -> ([f64; N], [[(usize, f64); 4]; 3]) {
    let value = [
        y[0] * y[0],
        y[1] * y[1],
        y[2] * y[2],
        y[0] * y[1],
        y[0] * y[2],
        y[1] * y[2],
        y[0],
        y[1],
        y[2],
        1.0,
    ];
    let gradient = [
        [(0, 2.0 * y[0]), (3, y[1]), (4, y[2]), (6, 1.0)],
        [(1, 2.0 * y[1]), (3, y[0]), (5, y[2]), (7, 1.0)],
        [(2, 2.0 * y[2]), (4, y[0]), (5, y[1]), (8, 1.0)],
    ];
    (value, gradient)
}

/// `Mᵀ s` of the fit's matrix `M` (rows of [`sample_rows`] at the samples' `y`) and residual
/// `s`, four entries per sample (value, three gradient components).
fn transpose_times(local: &[LocalSample], s: &[f64]) -> [f64; N] {
    let mut out = [0.0; N];
    for ((y, _), s) in local.iter().zip(s.chunks_exact(4)) {
        let (value, gradient) = sample_rows(*y);
        for (o, v) in out.iter_mut().zip(value) {
            *o += v * s[0];
        }
        for (row, sd) in gradient.iter().zip(&s[1..]) {
            for &(k, v) in row {
                out[k] += v * sd;
            }
        }
    }
    out
}

/// The fit's least-squares solution by the corrected semi-normal equations when the problem is
/// certifiably well conditioned, else `None` (the caller then takes Householder QR and, if
/// need be, the SVD).
///
/// `MᵀM = RᵀR` by Cholesky gives the same `R` as Householder QR (up to row signs); the solution
/// `x₀ = R⁻¹R⁻ᵀMᵀr` is corrected once by the same solve on the residual `r − Mx₀`
/// (Björck, "Stability analysis of the method of seminormal equations for linear least squares
/// problems", Linear Algebra Appl. 88/89, 1987: one correction makes the error comparable to a
/// backward-stable QR solve when `κ(M)² ε ≲ 1`). Taken only when `‖R‖_F ‖R⁻¹‖_F < 1e4`, which
/// bounds `κ(M)` by 1e4 (`κ² ε < 1.2e-8`, so Cholesky cannot break down on rounding and the
/// correction converges) and keeps every singular value above `1e-4 σ_max`, far from the
/// SVD's rank cut (`1e-10 σ_max`): in exact arithmetic it is the SVD's solution.
///
/// Why: `M` has four rows per sample but the gradient rows have four non-zeros each, so
/// `MᵀM` costs ~85 products per sample against ~800 for Householder's reflections of the dense
/// 4k × 10 matrix; fitting was 7 % of `algesurf smooth`'s samples on the bunny.
fn seminormal_solve(local: &[LocalSample]) -> Option<[f64; N]> {
    // The right-hand side: 0 for the value rows, the gradient for the gradient rows.
    let r: Vec<f64> = local
        .iter()
        .flat_map(|(_, n)| [0.0, n[0], n[1], n[2]])
        .collect();
    // Upper triangle of the Gram matrix MᵀM.
    let mut gram = [[0.0f64; N]; N];
    for (y, _) in local {
        let (value, gradient) = sample_rows(*y);
        for i in 0..N {
            for j in i..N {
                gram[i][j] += value[i] * value[j];
            }
        }
        for row in &gradient {
            // Column indices increase along a row, so (a, b) with a ≤ b is upper.
            for (a, &(i, vi)) in row.iter().enumerate() {
                for &(j, vj) in &row[a..] {
                    gram[i][j] += vi * vj;
                }
            }
        }
    }
    let chol = cholesky_upper(&gram)?;
    let (inv, cond) = inverse_and_condition(&chol)?;
    if cond >= 1e4 {
        return None;
    }
    // x = R⁻¹ R⁻ᵀ z for MᵀM x = z.
    let normal_solve = |z: [f64; N]| -> [f64; N] {
        let w: [f64; N] = std::array::from_fn(|i| (0..=i).map(|k| inv[k][i] * z[k]).sum());
        std::array::from_fn(|i| (i..N).map(|k| inv[i][k] * w[k]).sum())
    };
    let mut x = normal_solve(transpose_times(local, &r));
    // The residual r − M x₀, and the correction.
    let residual: Vec<f64> = local
        .iter()
        .map(|(y, _)| y)
        .zip(r.chunks_exact(4))
        .flat_map(|(y, rs)| {
            let (value, gradient) = sample_rows(*y);
            let v = rs[0] - value.iter().zip(&x).map(|(a, b)| a * b).sum::<f64>();
            let g = std::array::from_fn::<f64, 3, _>(|d| {
                rs[1 + d] - gradient[d].iter().map(|&(k, a)| a * x[k]).sum::<f64>()
            });
            [v, g[0], g[1], g[2]]
        })
        .collect();
    let dx = normal_solve(transpose_times(local, &residual));
    for (xi, d) in x.iter_mut().zip(dx) {
        *xi += d;
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

/// `R` upper triangular with `RᵀR = g` (Cholesky, `g`'s upper triangle read), or `None` when a
/// pivot is not positive (`g` not numerically positive definite).
fn cholesky_upper(g: &[[f64; N]; N]) -> Option<[[f64; N]; N]> {
    let mut r = [[0.0f64; N]; N];
    for i in 0..N {
        let d = g[i][i] - (0..i).map(|k| r[k][i] * r[k][i]).sum::<f64>();
        if !(d > 0.0 && d.is_finite()) {
            return None;
        }
        r[i][i] = d.sqrt();
        for j in i + 1..N {
            r[i][j] = (g[i][j] - (0..i).map(|k| r[k][i] * r[k][j]).sum::<f64>()) / r[i][i];
        }
    }
    Some(r)
}

/// `R⁻¹` of an upper-triangular `R` by back substitution on the unit vectors, and the bound
/// `‖R‖_F ‖R⁻¹‖_F ≥ κ₂(R)`; `None` for a zero or non-finite pivot, or a non-finite bound.
fn inverse_and_condition(r: &[[f64; N]; N]) -> Option<([[f64; N]; N], f64)> {
    if r.iter()
        .enumerate()
        .any(|(i, row)| row[i] == 0.0 || !row[i].is_finite())
    {
        return None;
    }
    // The pivots' reciprocals once: 10 divisions instead of 55 in the substitution's
    // dependency chains (each product then rounds twice, a relative 2ε instead of ε per entry,
    // immaterial to a bound that decides on a factor 100 and a solution corrected afterwards).
    let recip: [f64; N] = std::array::from_fn(|i| 1.0 / r[i][i]);
    let mut inv = [[0.0f64; N]; N];
    // Column j of R⁻¹: back substitution on e_j (upper triangular, so rows ≤ j only).
    for j in 0..N {
        for i in (0..=j).rev() {
            let mut s = if i == j { 1.0 } else { 0.0 };
            for k in i + 1..=j {
                s -= r[i][k] * inv[k][j];
            }
            inv[i][j] = s * recip[i];
        }
    }
    // Frobenius norms of the upper triangles (the rest is zero).
    let (mut rr, mut ii) = (0.0, 0.0);
    for i in 0..N {
        for j in i..N {
            rr += r[i][j] * r[i][j];
            ii += inv[i][j] * inv[i][j];
        }
    }
    let cond = rr.sqrt() * ii.sqrt();
    // NaN (an overflowing inverse) fails too.
    (!cond.is_nan()).then_some((inv, cond))
}

/// `R⁻¹ b[0..10]` by back substitution when the 10 × 10 upper-triangular `R` is certifiably far
/// from the SVD's rank cut, else `None`.
///
/// Why it is the same solution: `σ_max(R) ≤ ‖R‖_F` and `σ_min(R) = 1/‖R⁻¹‖_2 ≥ 1/‖R⁻¹‖_F`, so
/// `‖R‖_F ‖R⁻¹‖_F < 1e8` proves every singular value above `1e-8 σ_max`, a hundred times the
/// fit's cut (`1e-10 σ_max`; the hundredfold also covers the rounding of the computed `R⁻¹`,
/// relative `≈ cond · ε ≤ 1e-8`). Then the SVD solve truncates nothing and equals `R⁻¹ b` in
/// exact arithmetic. Rank-deficient fits (coplanar neighbourhoods) fail the test and take the
/// SVD.
fn well_conditioned_solve(r: &[[f64; N]; N], b: &[f64; N]) -> Option<[f64; N]> {
    let (_, cond) = inverse_and_condition(r)?;
    if cond >= 1e8 {
        return None;
    }
    let mut x = [0.0; N];
    for i in (0..N).rev() {
        let mut s = b[i];
        for k in i + 1..N {
            s -= r[i][k] * x[k];
        }
        x[i] = s / r[i][i];
    }
    Some(x)
}

#[cfg(test)]
mod tests {
    use super::*;
    use algesurf_bb::{BbPoly, PowerPoly, Tetrahedron};

    /// A bunny-like neighbourhood: `k` points of a bumpy surface patch of radius `spread`
    /// around `origin` (a sphere of radius 3 plus a wave), with its normals jittered by `noise`
    /// (so the fit has a non-zero residual, the general case).
    fn neighbourhood(
        rng: &mut algesurf_mesh::test_rng::Lcg,
        origin: DVec3,
        k: usize,
        spread: f64,
        noise: f64,
    ) -> Vec<(DVec3, DVec3)> {
        (0..k)
            .map(|_| {
                let d = (DVec3::Z * 3.0 + rng.vec() * 2.0 * spread).normalize();
                let bump = 1.0 + 0.05 * (7.0 * d.x).sin() * (5.0 * d.y).cos();
                let p = origin + d * 3.0 * bump;
                (p, d + rng.vec() * noise)
            })
            .collect()
    }

    /// The semi-normal path returns the least-squares solution that QR (and the SVD behind it)
    /// returns, to within the rounding its certificate allows, and it is the path normal
    /// neighbourhoods take.
    #[test]
    fn seminormal_equations_give_the_qr_fit() {
        let mut rng = algesurf_mesh::test_rng::Lcg(11);
        let (mut taken, mut worst) = (0, 0.0f64);
        let cases = 400;
        for case in 0..cases {
            let origin = rng.point() * [1.0, 100.0, 1e4][case % 3];
            let k = 7 + case % 9;
            let spread = [0.1, 0.3, 0.6][case % 3];
            let noise = [0.0, 1e-3, 0.1][(case / 3) % 3];
            let s = neighbourhood(&mut rng, origin, k, spread, noise);
            let (local, _, _) = local_samples(&s).unwrap();
            let qr = qr_solve(&local).unwrap();
            if let Some(fast) = seminormal_solve(&local) {
                taken += 1;
                let size = qr.iter().fold(0.0f64, |m, x| m.max(x.abs()));
                for (a, b) in fast.iter().zip(&qr) {
                    worst = worst.max((a - b).abs() / size);
                }
            }
        }
        assert!(
            taken > cases * 3 / 4,
            "semi-normal path taken {taken} of {cases} times"
        );
        // κ(M) < 1e4 by the certificate: both solutions are within ~κ·ε of the exact one.
        assert!(worst < 1e-11, "largest relative difference {worst:e}");
    }

    /// Rank-deficient and nearly rank-deficient fits are declined, so they keep QR's
    /// certificate and the SVD's minimum-norm solution.
    #[test]
    fn seminormal_equations_decline_ill_conditioned_fits() {
        // Coplanar points with the plane's normal: `Q + c L²` fit equally well.
        let coplanar: Vec<(DVec3, DVec3)> = [
            DVec3::new(0.0, 0.0, 1.0),
            DVec3::new(1.0, 0.0, 1.0),
            DVec3::new(0.0, 1.0, 1.0),
            DVec3::new(0.7, 0.6, 1.0),
        ]
        .map(|p| (p, DVec3::Z))
        .to_vec();
        assert!(seminormal_solve(&local_samples(&coplanar).unwrap().0).is_none());
        // A patch so small that its curvature is barely visible: κ(M) far above 1e4.
        let mut rng = algesurf_mesh::test_rng::Lcg(5);
        let tiny = neighbourhood(&mut rng, DVec3::ZERO, 12, 1e-4, 0.0);
        assert!(seminormal_solve(&local_samples(&tiny).unwrap().0).is_none());
    }

    #[test]
    fn back_substitution_only_where_the_svd_would_truncate_nothing() {
        // Well conditioned: the same solution as the SVD.
        let r: [[f64; N]; N] = std::array::from_fn(|i| {
            std::array::from_fn(|j| {
                if i == j {
                    2.0 + i as f64 * 0.1
                } else if j > i {
                    ((i * 7 + j * 3) as f64).sin() * 0.3
                } else {
                    0.0
                }
            })
        });
        let b: [f64; N] = std::array::from_fn(|i| (i as f64 * 0.7).cos());
        let fast = well_conditioned_solve(&r, &b).expect("well conditioned");
        let svd = DMatrix::<f64>::from_fn(N, N, |i, j| r[i][j]).svd(true, true);
        let slow = svd
            .solve(
                &DVector::from_column_slice(&b),
                1e-10 * svd.singular_values.max(),
            )
            .unwrap();
        for (x, y) in fast.iter().zip(slow.iter()) {
            assert!((x - y).abs() < 1e-13, "{x} vs {y}");
        }
        // Rank deficient (a zero pivot) or nearly so: left to the SVD.
        let mut singular = r;
        singular[9][9] = 0.0;
        assert!(well_conditioned_solve(&singular, &b).is_none());
        let mut near = r;
        near[4][4] = 1e-12;
        assert!(well_conditioned_solve(&near, &b).is_none());
    }

    /// The Householder `R` and `Qᵀr` give the least-squares solution that nalgebra's SVD of
    /// the whole matrix gives, and `RᵀR = MᵀM` (R is M's triangular factor up to row signs);
    /// with a zero column too (no reflector there).
    #[test]
    fn householder_r_is_the_triangular_factor() {
        let rows = 24;
        for zero_col in [None, Some(3)] {
            let mut m: Vec<f64> = (0..rows * N)
                .map(|i| ((i * 37 % 101) as f64 / 50.0 - 1.0) + if i % 11 == 0 { 0.5 } else { 0.0 })
                .collect();
            if let Some(c) = zero_col {
                m[c * rows..(c + 1) * rows].fill(0.0);
            }
            let r: Vec<f64> = (0..rows).map(|i| (i as f64 * 0.37).sin()).collect();
            let full = DMatrix::<f64>::from_column_slice(rows, N, &m);
            let (rm, qtr) = householder_r(&mut m.clone(), &mut r.clone(), rows);
            let rr = DMatrix::<f64>::from_fn(N, N, |i, j| rm[i][j]);
            let gram = full.transpose() * &full;
            assert!((rr.transpose() * &rr - &gram).amax() < 1e-12 * gram.amax());
            let want = full
                .clone()
                .svd(true, true)
                .solve(&DVector::from_column_slice(&r), 1e-10)
                .unwrap();
            let svd = rr.svd(true, true);
            let got = svd
                .solve(
                    &DVector::from_column_slice(&qtr),
                    1e-10 * svd.singular_values.max(),
                )
                .unwrap();
            assert!((got - &want).amax() < 1e-12 * want.amax(), "{zero_col:?}");
        }
    }

    #[test]
    fn cubic_coefficients_are_the_quadric_on_the_tetrahedron() {
        let q = Quadric {
            a: DMat3::from_cols_array(&[0.7, 0.2, -0.1, 0.2, -0.4, 0.3, -0.1, 0.3, 0.9]),
            b: DVec3::new(0.5, -1.2, 0.8),
            c: -0.3,
        };
        // A unit-sized tetrahedron away from the origin, and an origin near it.
        let o = DVec3::new(4.0, -3.0, 2.5);
        let tet = Tetrahedron::new([
            o + DVec3::new(0.0, 0.0, 0.0),
            o + DVec3::new(1.0, 0.1, 0.0),
            o + DVec3::new(0.2, 0.9, 0.1),
            o + DVec3::new(0.3, 0.2, 1.1),
        ])
        .unwrap();
        let coeffs = q.cubic_coefficients(&tet, o + DVec3::new(0.4, 0.3, 0.2));
        let poly = BbPoly::<f64, 4>::new(3, coeffs.to_vec()).unwrap();
        // Every point: the BB form's value is Q's (up to the rounding of O(10) terms).
        for tau in [
            [1.0, 0.0, 0.0, 0.0],
            [0.25, 0.25, 0.25, 0.25],
            [0.1, 0.6, 0.2, 0.1],
            [0.0, 0.0, 0.3, 0.7],
        ] {
            let x = (0..4).map(|i| tet.vertex(i) * tau[i]).sum::<DVec3>();
            let (got, want) = (poly.eval(tau), q.value(x));
            assert!(
                (got - want).abs() < 1e-12 * 50.0,
                "{got} vs {want} at {tau:?}"
            );
        }
        // And the same coefficients as the generic conversion.
        let a = q.a.to_cols_array_2d();
        let mut qp = PowerPoly::<4>::zero(2);
        for (e, val) in [
            ([2, 0, 0], a[0][0]),
            ([0, 2, 0], a[1][1]),
            ([0, 0, 2], a[2][2]),
            ([1, 1, 0], 2.0 * a[0][1]),
            ([1, 0, 1], 2.0 * a[0][2]),
            ([0, 1, 1], 2.0 * a[1][2]),
            ([1, 0, 0], q.b.x),
            ([0, 1, 0], q.b.y),
            ([0, 0, 1], q.b.z),
            ([0, 0, 0], q.c),
        ] {
            qp.set(&e, val).unwrap();
        }
        let generic = BbPoly::from_cartesian(&tet, &qp, 3).unwrap();
        for (x, y) in coeffs.iter().zip(generic.coeffs()) {
            assert!((x - y).abs() < 1e-12 * 50.0, "{x} vs {y}");
        }
    }
}
