//! Univariate B-spline bases on general (non-decreasing) knot vectors: knot span search,
//! Cox–de Boor evaluation of the non-zero basis functions, their derivatives of any order, and
//! a B-spline curve evaluator (§2.4 of Bajaj 1994 gives the recurrence; the algorithms are
//! those of Piegl–Tiller, *The NURBS Book*, A2.1–A2.3, written from the recurrences).
//!
//! Notation: degree p, knots `u_0 ≤ … ≤ u_{m}` (m + 1 knots), `n = m − p` basis functions
//! `N_{i,p}`, `i = 0 … n − 1`, domain `[u_p, u_{m−p}]`. The Cox–de Boor recurrence:
//! `N_{i,0}(t) = 1` on `[u_i, u_{i+1})`, and
//! `N_{i,p}(t) = (t − u_i)/(u_{i+p} − u_i) N_{i,p−1}(t) + (u_{i+p+1} − t)/(u_{i+p+1} − u_{i+1}) N_{i+1,p−1}(t)`
//! with 0/0 = 0. At the right end of the domain the last non-empty span is used, so the
//! basis is right-continuous inside and left-continuous at the end (the usual convention).
//!
//! ```
//! use algesurf_bb::bspline::KnotVector;
//! // The uniform cubic B-spline at a knot: 1/6, 4/6, 1/6.
//! let kv = KnotVector::uniform(3, 4)?;
//! let (span, n) = kv.basis(0.5)?;
//! assert_eq!(span, 5);
//! assert!((n[0] - 1.0 / 6.0).abs() < 1e-15 && (n[1] - 4.0 / 6.0).abs() < 1e-15);
//! assert!((n[2] - 1.0 / 6.0).abs() < 1e-15 && n[3].abs() < 1e-15);
//! # Ok::<(), algesurf_bb::BbError>(())
//! ```

use crate::{BbError, Coeff};

/// A validated knot vector with its degree.
#[derive(Clone, Debug, PartialEq)]
pub struct KnotVector {
    degree: usize,
    knots: Vec<f64>,
}

impl KnotVector {
    /// Validates `knots` for degree `degree`: finite, non-decreasing, at least `2(p + 1)`
    /// knots, no interior knot of multiplicity above `p + 1` (the basis would be
    /// discontinuous beyond repair), and a non-empty domain `u_p < u_{m−p}`.
    pub fn new(degree: usize, knots: Vec<f64>) -> Result<Self, BbError> {
        if knots.iter().any(|k| !k.is_finite()) {
            return Err(BbError::NonFinite { what: "knot" });
        }
        if knots.windows(2).any(|w| w[1] < w[0]) {
            return Err(BbError::InvalidArgument(
                "knots must be non-decreasing".into(),
            ));
        }
        if knots.len() < 2 * (degree + 1) {
            return Err(BbError::InvalidArgument(format!(
                "degree {degree} needs at least {} knots, got {}",
                2 * (degree + 1),
                knots.len()
            )));
        }
        let mut run = 1;
        for w in knots.windows(2) {
            run = if w[1] == w[0] { run + 1 } else { 1 };
            if run > degree + 1 {
                return Err(BbError::InvalidArgument(format!(
                    "knot {} has multiplicity above degree + 1 = {}",
                    w[0],
                    degree + 1
                )));
            }
        }
        let m = knots.len() - 1;
        if knots[degree] >= knots[m - degree] {
            return Err(BbError::InvalidArgument(
                "empty domain: u_p must be below u_{m−p}".into(),
            ));
        }
        Ok(KnotVector { degree, knots })
    }

    /// Uniform (unclamped) knots with `spans` spans on the domain `[0, 1]`:
    /// `u_i = (i − p)/spans`, `i = 0 … spans + 2p` (`spans + p` basis functions, each a
    /// translate of the uniform B-spline — the bases `N_{i3}^σ` of the shell paper for
    /// `spans = 2^σ`, p = 3).
    pub fn uniform(degree: usize, spans: usize) -> Result<Self, BbError> {
        if spans == 0 {
            return Err(BbError::InvalidArgument("at least one span".into()));
        }
        let h = 1.0 / spans as f64;
        let knots = (0..=spans + 2 * degree)
            .map(|i| (i as f64 - degree as f64) * h)
            .collect();
        KnotVector::new(degree, knots)
    }

    /// Clamped (open) uniform knots on `[0, 1]`: `p + 1` knots at each end, `spans − 1`
    /// interior knots `k/spans`. The curve interpolates its end control points.
    pub fn clamped_uniform(degree: usize, spans: usize) -> Result<Self, BbError> {
        if spans == 0 {
            return Err(BbError::InvalidArgument("at least one span".into()));
        }
        let mut knots = vec![0.0; degree + 1];
        knots.extend((1..spans).map(|k| k as f64 / spans as f64));
        knots.extend(std::iter::repeat_n(1.0, degree + 1));
        KnotVector::new(degree, knots)
    }

    /// The Bézier knot vector `[0^{p+1}, 1^{p+1}]`: its basis is the Bernstein basis `B_i^p`.
    pub fn bezier(degree: usize) -> Self {
        KnotVector {
            degree,
            knots: [vec![0.0; degree + 1], vec![1.0; degree + 1]].concat(),
        }
    }

    /// The degree p.
    #[inline]
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// The knots.
    #[inline]
    pub fn knots(&self) -> &[f64] {
        &self.knots
    }

    /// Number of basis functions, `m − p` (= number of control points of a curve).
    #[inline]
    pub fn num_basis(&self) -> usize {
        self.knots.len() - self.degree - 1
    }

    /// The parameter domain `[u_p, u_{m−p}]`.
    #[inline]
    pub fn domain(&self) -> (f64, f64) {
        let m = self.knots.len() - 1;
        (self.knots[self.degree], self.knots[m - self.degree])
    }

    /// The knot span index `s` with `u_s ≤ t < u_{s+1}`, `p ≤ s ≤ n − 1` (at `t = u_{m−p}` the
    /// last non-empty span), by binary search (Piegl–Tiller A2.1). Errors when t is outside
    /// the domain or NaN.
    pub fn find_span(&self, t: f64) -> Result<usize, BbError> {
        let (lo, hi) = self.domain();
        if !(t >= lo && t <= hi) {
            return Err(BbError::InvalidArgument(format!(
                "parameter {t} outside the domain [{lo}, {hi}]"
            )));
        }
        let p = self.degree;
        let n = self.num_basis();
        if t == hi {
            // Last span with u_s < u_{s+1}: scan down from n − 1 over repeated end knots.
            let mut s = n - 1;
            while self.knots[s] == self.knots[s + 1] {
                s -= 1;
            }
            return Ok(s);
        }
        // Invariant: u_low ≤ t < u_high.
        let (mut low, mut high) = (p, n);
        while high - low > 1 {
            let mid = (low + high) / 2;
            if t < self.knots[mid] {
                high = mid;
            } else {
                low = mid;
            }
        }
        Ok(low)
    }

    /// The `p + 1` basis functions `N_{s−p,p}(t), …, N_{s,p}(t)` that can be non-zero at t, in
    /// span `s` (Piegl–Tiller A2.2: the triangular Cox–de Boor scheme with the left/right
    /// differences `t − u_{s+1−j}` and `u_{s+j} − t`, both ≥ 0 in the span, so every step is a
    /// sum of non-negative terms and the values are non-negative and sum to 1 up to rounding).
    pub fn basis_in_span(&self, span: usize, t: f64) -> Vec<f64> {
        let p = self.degree;
        let u = &self.knots;
        let mut n = vec![0.0; p + 1];
        let mut left = vec![0.0; p + 1];
        let mut right = vec![0.0; p + 1];
        n[0] = 1.0;
        for j in 1..=p {
            left[j] = t - u[span + 1 - j];
            right[j] = u[span + j] - t;
            let mut saved = 0.0;
            for r in 0..j {
                let den = right[r + 1] + left[j - r];
                // den ≥ u_{s+1} − u_s > 0 inside a non-empty span.
                let temp = n[r] / den;
                n[r] = saved + right[r + 1] * temp;
                saved = left[j - r] * temp;
            }
            n[j] = saved;
        }
        n
    }

    /// `(s, [N_{s−p,p}(t) … N_{s,p}(t)])`: the span and the non-zero basis functions at t.
    pub fn basis(&self, t: f64) -> Result<(usize, Vec<f64>), BbError> {
        let s = self.find_span(t)?;
        Ok((s, self.basis_in_span(s, t)))
    }

    /// The span s and `ders[k][r] = N^{(k)}_{s−p+r,p}(t)` for `k = 0 … order` (Piegl–Tiller
    /// A2.3). Derivatives above the degree are zero. From the derivative of the recurrence,
    /// `N^{(k)}_{i,p} = p/(u_{i+p} − u_i) N^{(k−1)}_{i,p−1} − p/(u_{i+p+1} − u_{i+1}) N^{(k−1)}_{i+1,p−1}`
    /// (Piegl–Tiller (2.9)), evaluated on the triangular table of lower-degree values.
    pub fn basis_derivatives(
        &self,
        t: f64,
        order: usize,
    ) -> Result<(usize, Vec<Vec<f64>>), BbError> {
        let span = self.find_span(t)?;
        let p = self.degree;
        let u = &self.knots;
        // ndu[j][r] (r ≤ j): N_{s−j+r, j}(t); ndu[r][j] (r < j): the knot differences.
        let mut ndu = vec![vec![0.0; p + 1]; p + 1];
        let mut left = vec![0.0; p + 1];
        let mut right = vec![0.0; p + 1];
        ndu[0][0] = 1.0;
        for j in 1..=p {
            left[j] = t - u[span + 1 - j];
            right[j] = u[span + j] - t;
            let mut saved = 0.0;
            for r in 0..j {
                ndu[j][r] = right[r + 1] + left[j - r];
                let temp = ndu[r][j - 1] / ndu[j][r];
                ndu[r][j] = saved + right[r + 1] * temp;
                saved = left[j - r] * temp;
            }
            ndu[j][j] = saved;
        }
        let mut ders = vec![vec![0.0; p + 1]; order + 1];
        for r in 0..=p {
            ders[0][r] = ndu[r][p];
        }
        let mut a = [vec![0.0; p + 1], vec![0.0; p + 1]];
        for r in 0..=p {
            let (mut s1, mut s2) = (0usize, 1usize);
            a[0][0] = 1.0;
            for k in 1..=order.min(p) {
                let mut d = 0.0;
                let rk = r as isize - k as isize;
                let pk = p - k;
                if r >= k {
                    let rk = rk as usize;
                    a[s2][0] = a[s1][0] / ndu[pk + 1][rk];
                    d = a[s2][0] * ndu[rk][pk];
                }
                let j1 = if rk >= -1 { 1 } else { (-rk) as usize };
                let j2 = if r as isize - 1 <= pk as isize {
                    k - 1
                } else {
                    p - r
                };
                for j in j1..=j2 {
                    let idx = (rk + j as isize) as usize;
                    a[s2][j] = (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][idx];
                    d += a[s2][j] * ndu[idx][pk];
                }
                if r <= pk {
                    a[s2][k] = -a[s1][k - 1] / ndu[pk + 1][r];
                    d += a[s2][k] * ndu[r][pk];
                }
                ders[k][r] = d;
                std::mem::swap(&mut s1, &mut s2);
            }
        }
        // Multiply by p!/(p−k)!.
        let mut factor = p as f64;
        for (k, row) in ders.iter_mut().enumerate().skip(1) {
            if k > p {
                row.fill(0.0);
                continue;
            }
            for v in row.iter_mut() {
                *v *= factor;
            }
            factor *= (p - k) as f64;
        }
        Ok((span, ders))
    }
}

/// A B-spline curve `C(t) = Σ_i N_{i,p}(t) P_i` with control points of any [`Coeff`] type.
///
/// ```
/// use algesurf_bb::bspline::{BSplineCurve, KnotVector};
/// use glam::DVec2;
/// let kv = KnotVector::clamped_uniform(2, 2)?;
/// let c = BSplineCurve::new(kv, vec![DVec2::ZERO, DVec2::X, DVec2::ONE, DVec2::Y])?;
/// assert_eq!(c.eval(0.0)?, DVec2::ZERO);
/// assert_eq!(c.eval(1.0)?, DVec2::Y);
/// # Ok::<(), algesurf_bb::BbError>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct BSplineCurve<C> {
    knots: KnotVector,
    control: Vec<C>,
}

impl<C: Coeff> BSplineCurve<C> {
    /// A curve from its knots and `num_basis()` control points.
    pub fn new(knots: KnotVector, control: Vec<C>) -> Result<Self, BbError> {
        if control.len() != knots.num_basis() {
            return Err(BbError::InvalidArgument(format!(
                "{} control points for {} basis functions",
                control.len(),
                knots.num_basis()
            )));
        }
        Ok(BSplineCurve { knots, control })
    }

    /// The knot vector.
    pub fn knots(&self) -> &KnotVector {
        &self.knots
    }

    /// The control points.
    pub fn control(&self) -> &[C] {
        &self.control
    }

    /// The point at t (a convex combination of the p + 1 active control points).
    pub fn eval(&self, t: f64) -> Result<C, BbError> {
        let (span, n) = self.knots.basis(t)?;
        let p = self.knots.degree;
        Ok(n.iter().enumerate().fold(C::ZERO, |acc, (r, &w)| {
            acc.add_scaled(self.control[span - p + r], w)
        }))
    }

    /// The k-th derivative at t.
    pub fn derivative(&self, t: f64, k: usize) -> Result<C, BbError> {
        let (span, d) = self.knots.basis_derivatives(t, k)?;
        let p = self.knots.degree;
        Ok(d[k].iter().enumerate().fold(C::ZERO, |acc, (r, &w)| {
            acc.add_scaled(self.control[span - p + r], w)
        }))
    }
}
