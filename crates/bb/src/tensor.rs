//! Tensor-product Bernstein bases and the "mixed" triangle × interval basis of §2.4 of
//! Bajaj 1994 ("Polynomial surface patch representations").
//!
//! * [`TensorBb`] (`TensorBb2`, `TensorBb3`): `P(x) = Σ_{i} w_{i_1…i_D} Π_k B_{i_k}^{n_k}(x_k)`
//!   on the unit square or cube, degrees per direction (§2.4 "Tensor", bivariate and
//!   trivariate). The trivariate tensor form is also the four-sided prism ("4-prism") variant
//!   of the shell construction (Bajaj–Xu, mixed prism fat surfaces): bilinear (u, v) on the
//!   quadrilateral times the thickness parameter λ — see [`QuadPrismBb`].
//! * [`PrismBb`]: `P(τ, t) = Σ_{|λ|=n} Σ_{l=0}^{m} b_{λ,l} B_λ^n(τ) B_l^m(t)` with barycentric
//!   `τ` on a triangle and `t ∈ [0, 1]` (§2.4 "Mixed": `B_{ij}^n(x, y) B_k^p(z)`), the basis of
//!   the three-sided prisms ("3-prisms") of the shell paper.
//!
//! Evaluation is by de Casteljau in each direction (every step a convex combination on the
//! domain, so the result is as stable as univariate de Casteljau); derivatives and degree
//! elevation act on one direction at a time by the univariate formulas (Farin 1990, §4.3 and
//! §5.1) applied to every fibre.

use crate::multi_index::{self, count};
use crate::{BbError, BbPoly, Coeff};

/// A tensor-product Bernstein polynomial in `D` variables on `[0, 1]^D`.
///
/// Coefficients are stored row-major: index `(i_1, …, i_D)` at
/// `Σ_k i_k Π_{l>k} (n_l + 1)` (the last direction varies fastest).
///
/// ```
/// use algesurf_bb::tensor::TensorBb2;
/// // w_ij = i + 2j reproduces the bilinear-in-degree function n_1 x + 2 n_2 y.
/// let p = TensorBb2::<f64>::from_fn([2, 3], |[i, j]| (i + 2 * j) as f64);
/// assert!((p.eval([0.25, 0.5]) - (2.0 * 0.25 + 2.0 * 3.0 * 0.5)).abs() < 1e-15);
/// let dx = p.derivative(0)?;
/// assert!((dx.eval([0.7, 0.1]) - 2.0).abs() < 1e-14);
/// # Ok::<(), algesurf_bb::BbError>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct TensorBb<C, const D: usize> {
    degrees: [usize; D],
    coeffs: Vec<C>,
}

/// Bivariate tensor-product Bernstein polynomial on the unit square.
pub type TensorBb2<C> = TensorBb<C, 2>;
/// Trivariate tensor-product Bernstein polynomial on the unit cube.
pub type TensorBb3<C> = TensorBb<C, 3>;
/// The four-sided prism basis of the shell paper: (u, v) on the quadrilateral (its bilinear
/// parametrisation) times the thickness direction — a trivariate tensor product.
pub type QuadPrismBb<C> = TensorBb<C, 3>;

/// `(outer, len, inner)` of the fibres along `axis` of a row-major array of `shape`.
fn fibre_layout(shape: &[usize], axis: usize) -> (usize, usize, usize) {
    let outer = shape[..axis].iter().product();
    let inner = shape[axis + 1..].iter().product();
    (outer, shape[axis], inner)
}

/// Applies `f` to every fibre along `axis`, producing fibres of length `new_len`.
fn map_fibres<C: Coeff>(
    data: &[C],
    shape: &[usize],
    axis: usize,
    new_len: usize,
    f: impl Fn(&[C]) -> Vec<C>,
) -> Vec<C> {
    let (outer, len, inner) = fibre_layout(shape, axis);
    let mut out = vec![C::ZERO; outer * new_len * inner];
    let mut fibre = Vec::with_capacity(len);
    for o in 0..outer {
        for i in 0..inner {
            fibre.clear();
            fibre.extend((0..len).map(|j| data[(o * len + j) * inner + i]));
            let g = f(&fibre);
            for (j, v) in g.into_iter().enumerate() {
                out[(o * new_len + j) * inner + i] = v;
            }
        }
    }
    out
}

/// Univariate de Casteljau value of a coefficient fibre at t.
fn de_casteljau<C: Coeff>(c: &[C], t: f64) -> C {
    let mut w = c.to_vec();
    let s = 1.0 - t;
    for level in (1..w.len()).rev() {
        for i in 0..level {
            w[i] = w[i] * s + w[i + 1] * t;
        }
    }
    w[0]
}

/// Univariate derivative coefficients `n (c_{i+1} − c_i)` (zero fibre for degree 0).
fn diff<C: Coeff>(c: &[C]) -> Vec<C> {
    if c.len() <= 1 {
        return vec![C::ZERO];
    }
    let n = (c.len() - 1) as f64;
    c.windows(2).map(|w| (w[1] - w[0]) * n).collect()
}

/// Univariate degree elevation by one: `c'_i = (i/(n+1)) c_{i−1} + (1 − i/(n+1)) c_i`.
fn elevate1<C: Coeff>(c: &[C]) -> Vec<C> {
    let n1 = c.len();
    (0..=n1)
        .map(|i| {
            let a = i as f64 / n1 as f64;
            let mut v = C::ZERO;
            if i > 0 {
                v = v.add_scaled(c[i - 1], a);
            }
            if i < n1 {
                v = v.add_scaled(c[i], 1.0 - a);
            }
            v
        })
        .collect()
}

impl<C: Coeff, const D: usize> TensorBb<C, D> {
    fn shape(degrees: &[usize; D]) -> [usize; D] {
        degrees.map(|n| n + 1)
    }

    /// A polynomial from its coefficients in row-major order.
    pub fn new(degrees: [usize; D], coeffs: Vec<C>) -> Result<Self, BbError> {
        let expected: usize = Self::shape(&degrees).iter().product();
        if coeffs.len() != expected {
            return Err(BbError::InvalidArgument(format!(
                "degrees {degrees:?} need {expected} coefficients, got {}",
                coeffs.len()
            )));
        }
        Ok(TensorBb { degrees, coeffs })
    }

    /// The polynomial whose coefficient at `(i_1, …, i_D)` is `f([i_1, …, i_D])`.
    pub fn from_fn(degrees: [usize; D], mut f: impl FnMut([usize; D]) -> C) -> Self {
        let shape = Self::shape(&degrees);
        let total: usize = shape.iter().product();
        let coeffs = (0..total)
            .map(|mut r| {
                let mut idx = [0; D];
                for k in (0..D).rev() {
                    idx[k] = r % shape[k];
                    r /= shape[k];
                }
                f(idx)
            })
            .collect();
        TensorBb { degrees, coeffs }
    }

    /// Degrees per direction.
    #[inline]
    pub fn degrees(&self) -> [usize; D] {
        self.degrees
    }

    /// Coefficients in row-major order.
    #[inline]
    pub fn coeffs(&self) -> &[C] {
        &self.coeffs
    }

    /// The coefficient at a multi-index, or `None` out of range.
    pub fn get(&self, idx: [usize; D]) -> Option<C> {
        let shape = Self::shape(&self.degrees);
        let mut r = 0;
        for k in 0..D {
            if idx[k] >= shape[k] {
                return None;
            }
            r = r * shape[k] + idx[k];
        }
        Some(self.coeffs[r])
    }

    /// Value at `x ∈ [0, 1]^D` (outside allowed, the polynomial is defined everywhere): de
    /// Casteljau along the last direction for every fibre, then the next, and so on.
    pub fn eval(&self, x: [f64; D]) -> C {
        let mut data = self.coeffs.clone();
        let shape = Self::shape(&self.degrees);
        for axis in (0..D).rev() {
            let len = shape[axis];
            // The fibres along the last remaining axis are contiguous.
            data = data.chunks(len).map(|f| de_casteljau(f, x[axis])).collect();
        }
        data[0]
    }

    /// The partial derivative `∂/∂x_axis`, a tensor polynomial of degree `n_axis − 1` in that
    /// direction (degree 0 gives the zero polynomial of degree 0 there).
    pub fn derivative(&self, axis: usize) -> Result<Self, BbError> {
        if axis >= D {
            return Err(BbError::Index(format!("direction {axis} of {D}")));
        }
        let shape = Self::shape(&self.degrees);
        let n = self.degrees[axis];
        let new_len = n.max(1);
        let coeffs = map_fibres(&self.coeffs, &shape, axis, new_len, diff);
        let mut degrees = self.degrees;
        degrees[axis] = n.saturating_sub(1);
        Ok(TensorBb { degrees, coeffs })
    }

    /// Degree elevation by `k` in direction `axis` (the same polynomial).
    pub fn elevate(&self, axis: usize, k: usize) -> Result<Self, BbError> {
        if axis >= D {
            return Err(BbError::Index(format!("direction {axis} of {D}")));
        }
        let mut p = self.clone();
        for _ in 0..k {
            let shape = Self::shape(&p.degrees);
            let n = p.degrees[axis];
            p.coeffs = map_fibres(&p.coeffs, &shape, axis, n + 2, elevate1);
            p.degrees[axis] = n + 1;
        }
        Ok(p)
    }

    /// The basis function `Π_k B_{i_k}^{n_k}(x_k)` (0 for an index out of range).
    pub fn basis(degrees: [usize; D], idx: [usize; D], x: [f64; D]) -> f64 {
        (0..D)
            .map(|k| bernstein(degrees[k], idx[k], x[k]))
            .product()
    }
}

/// The univariate Bernstein polynomial `B_i^n(t) = C(n, i) t^i (1 − t)^{n−i}` (0 for i > n).
pub fn bernstein(n: usize, i: usize, t: f64) -> f64 {
    if i > n {
        return 0.0;
    }
    multi_index::binomial_f64(n, i) * t.powi(i as i32) * (1.0 - t).powi((n - i) as i32)
}

/// The mixed triangle × interval BB polynomial of §2.4 of Bajaj 1994:
/// `P(τ, t) = Σ_{|λ|=n} Σ_{l=0}^{m} b_{λ,l} B_λ^n(τ) B_l^m(t)`, τ barycentric on a triangle.
///
/// Storage: `b_{λ,l}` at `rank(λ)·(m + 1) + l` (triangle index in the order of
/// [`crate::multi_index`], the interval index fastest).
///
/// ```
/// use algesurf_bb::tensor::PrismBb;
/// // b_{λ,l} = λ_0 / n + l / m reproduces τ_0 + t (both bases reproduce linear functions).
/// let p = PrismBb::<f64>::from_fn(2, 3, |lambda, l| lambda[0] as f64 / 2.0 + l as f64 / 3.0);
/// assert!((p.eval([0.2, 0.3, 0.5], 0.4) - 0.6).abs() < 1e-15);
/// let dt = p.derivative_t();
/// assert!((dt.eval([0.6, 0.1, 0.3], 0.9) - 1.0).abs() < 1e-14);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct PrismBb<C> {
    n: usize,
    m: usize,
    coeffs: Vec<C>,
}

impl<C: Coeff> PrismBb<C> {
    /// A prism polynomial of triangle degree `n` and interval degree `m` from its coefficients.
    pub fn new(n: usize, m: usize, coeffs: Vec<C>) -> Result<Self, BbError> {
        let expected = count::<3>(n) * (m + 1);
        if coeffs.len() != expected {
            return Err(BbError::InvalidArgument(format!(
                "triangle degree {n} × interval degree {m} needs {expected} coefficients, got {}",
                coeffs.len()
            )));
        }
        Ok(PrismBb { n, m, coeffs })
    }

    /// The polynomial with `b_{λ,l} = f(λ, l)`.
    pub fn from_fn(n: usize, m: usize, mut f: impl FnMut([usize; 3], usize) -> C) -> Self {
        let mut coeffs = Vec::with_capacity(count::<3>(n) * (m + 1));
        for lambda in multi_index::iter::<3>(n) {
            for l in 0..=m {
                coeffs.push(f(lambda, l));
            }
        }
        PrismBb { n, m, coeffs }
    }

    /// `(n, m)`: triangle and interval degrees.
    #[inline]
    pub fn degrees(&self) -> (usize, usize) {
        (self.n, self.m)
    }

    /// Coefficients in storage order.
    #[inline]
    pub fn coeffs(&self) -> &[C] {
        &self.coeffs
    }

    /// The triangle polynomial `Σ_λ (Σ_l b_{λ,l} B_l^m(t)) B_λ^n` at fixed t.
    pub fn at_t(&self, t: f64) -> BbPoly<C, 3> {
        let coeffs = self
            .coeffs
            .chunks(self.m + 1)
            .map(|f| de_casteljau(f, t))
            .collect();
        BbPoly::new(self.n, coeffs).expect("count matches by construction")
    }

    /// The layer `l` as a triangle polynomial (coefficients `b_{·,l}`).
    pub fn layer(&self, l: usize) -> Option<BbPoly<C, 3>> {
        (l <= self.m).then(|| {
            let coeffs = self
                .coeffs
                .iter()
                .skip(l)
                .step_by(self.m + 1)
                .copied()
                .collect();
            BbPoly::new(self.n, coeffs).expect("count matches by construction")
        })
    }

    fn from_layers(m: usize, layers: &[BbPoly<C, 3>]) -> Self {
        let n = layers[0].degree();
        let k = count::<3>(n);
        let mut coeffs = Vec::with_capacity(k * (m + 1));
        for r in 0..k {
            for layer in layers {
                coeffs.push(layer.coeffs()[r]);
            }
        }
        PrismBb { n, m, coeffs }
    }

    /// Value at barycentric `tau` on the triangle and `t` on the interval (de Casteljau in t
    /// for every triangle index, then de Casteljau on the triangle).
    pub fn eval(&self, tau: [f64; 3], t: f64) -> C {
        self.at_t(t).eval(tau)
    }

    /// `∂P/∂t`: interval degree m − 1 (the zero polynomial of interval degree 0 when m = 0).
    pub fn derivative_t(&self) -> Self {
        let m_new = self.m.max(1) - 1;
        let coeffs = self.coeffs.chunks(self.m + 1).flat_map(diff).collect();
        PrismBb {
            n: self.n,
            m: m_new,
            coeffs,
        }
    }

    /// The derivative in the barycentric direction `d` (Σd = 0) of the triangle variables:
    /// triangle degree n − 1 ([`BbPoly::derivative`] on every layer).
    pub fn derivative_tau(&self, d: [f64; 3]) -> Self {
        let layers: Vec<_> = (0..=self.m)
            .map(|l| self.layer(l).expect("l ≤ m").derivative(d))
            .collect();
        Self::from_layers(self.m, &layers)
    }

    /// Degree elevation by `k` in t.
    pub fn elevate_t(&self, k: usize) -> Self {
        let mut p = self.clone();
        for _ in 0..k {
            p.coeffs = p.coeffs.chunks(p.m + 1).flat_map(elevate1).collect();
            p.m += 1;
        }
        p
    }

    /// Degree elevation by `k` on the triangle ([`BbPoly::elevate`] on every layer).
    pub fn elevate_tau(&self, k: usize) -> Self {
        let layers: Vec<_> = (0..=self.m)
            .map(|l| self.layer(l).expect("l ≤ m").elevate(k))
            .collect();
        Self::from_layers(self.m, &layers)
    }

    /// The basis function `B_λ^n(τ) B_l^m(t)` (0 when `|λ| ≠ n` or `l > m`).
    pub fn basis(n: usize, m: usize, lambda: [usize; 3], l: usize, tau: [f64; 3], t: f64) -> f64 {
        if multi_index::degree(&lambda) != n {
            return 0.0;
        }
        let b: f64 = multi_index::multinomial(&lambda)
            * (0..3)
                .map(|i| tau[i].powi(lambda[i] as i32))
                .product::<f64>();
        b * bernstein(m, l, t)
    }
}
