//! [`BbPoly`]: a polynomial of degree n in Bernstein–Bézier form over an (N−1)-simplex,
//! `p(τ) = Σ_{|λ|=n} b_λ B_λ^n(τ)`, with coefficients of any [`Coeff`] type.
//!
//! Evaluation is by de Casteljau's algorithm (the reference: numerically stable, every
//! intermediate a convex combination inside the simplex) or by [`BbEvaluator`] (the fast path
//! for hot loops: Bernstein basis values from power tables). The blossom generalises
//! de Casteljau to n distinct arguments; every other operation of this module — derivatives,
//! subdivision, restriction, reparameterisation — is a blossom evaluation.

use crate::multi_index::{self, MultiIndex, count, multinomial, rank};
use crate::{BbError, Coeff, Simplex};
use glam::{DMat3, DVec3};

/// A polynomial in Bernstein–Bézier form over a simplex with `N` barycentric variables
/// (N = 2 univariate, 3 bivariate/triangular, 4 trivariate/tetrahedral).
///
/// Coefficients are stored in the order of [`crate::multi_index`].
///
/// ```
/// use algesurf_bb::BbPoly;
/// // The univariate cubic with coefficients 0, 1, 1, 0 (a bump) at t = 1/2.
/// let p = BbPoly::<f64, 2>::new(3, vec![0.0, 1.0, 1.0, 0.0]).unwrap();
/// assert_eq!(p.eval([0.5, 0.5]), 0.75);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct BbPoly<C, const N: usize> {
    degree: usize,
    coeffs: Vec<C>,
}

/// A univariate BB polynomial on `[0, 1]` (barycentric `(1 − t, t)`).
pub type BbCurve<C> = BbPoly<C, 2>;
/// A bivariate BB polynomial on a triangle.
pub type BbTriangle<C> = BbPoly<C, 3>;
/// A trivariate BB polynomial on a tetrahedron.
pub type BbTetra<C> = BbPoly<C, 4>;

impl<C: Coeff, const N: usize> BbPoly<C, N> {
    /// A polynomial from its coefficients in storage order.
    pub fn new(degree: usize, coeffs: Vec<C>) -> Result<Self, BbError> {
        let expected = count::<N>(degree);
        if coeffs.len() != expected {
            return Err(BbError::CoefficientCount {
                degree,
                variables: N,
                expected,
                found: coeffs.len(),
            });
        }
        Ok(BbPoly { degree, coeffs })
    }

    /// A polynomial whose coefficient `b_λ` is `f(λ)`.
    pub fn from_fn(degree: usize, mut f: impl FnMut(MultiIndex<N>) -> C) -> Self {
        BbPoly {
            degree,
            coeffs: multi_index::iter::<N>(degree).map(&mut f).collect(),
        }
    }

    /// The zero polynomial of the given degree.
    pub fn zero(degree: usize) -> Self {
        Self::constant(degree, C::ZERO)
    }

    /// The constant `c` written in degree `degree` (all coefficients equal `c`, by the
    /// partition of unity).
    pub fn constant(degree: usize, c: C) -> Self {
        BbPoly {
            degree,
            coeffs: vec![c; count::<N>(degree)],
        }
    }

    /// The degree n.
    #[inline]
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// All coefficients in storage order.
    #[inline]
    pub fn coeffs(&self) -> &[C] {
        &self.coeffs
    }

    /// Mutable access to all coefficients in storage order.
    #[inline]
    pub fn coeffs_mut(&mut self) -> &mut [C] {
        &mut self.coeffs
    }

    /// The coefficients, consuming the polynomial.
    pub fn into_coeffs(self) -> Vec<C> {
        self.coeffs
    }

    /// The coefficient `b_λ`, or `None` when `|λ| ≠ n`.
    #[inline]
    pub fn get(&self, lambda: MultiIndex<N>) -> Option<C> {
        (multi_index::degree(&lambda) == self.degree).then(|| self.coeffs[rank(&lambda)])
    }

    /// The coefficient `b_λ`.
    ///
    /// # Panics
    /// Panics when `|λ| ≠ n`; use [`BbPoly::get`] for untrusted indices.
    #[inline]
    pub fn coeff(&self, lambda: MultiIndex<N>) -> C {
        self.get(lambda)
            .expect("multi-index degree differs from the polynomial's")
    }

    /// Sets `b_λ`.
    ///
    /// # Panics
    /// Panics when `|λ| ≠ n`.
    #[inline]
    pub fn set(&mut self, lambda: MultiIndex<N>, c: C) {
        assert_eq!(
            multi_index::degree(&lambda),
            self.degree,
            "multi-index degree"
        );
        self.coeffs[rank(&lambda)] = c;
    }

    /// `(λ, b_λ)` pairs in storage order.
    pub fn iter(&self) -> impl Iterator<Item = (MultiIndex<N>, C)> + '_ {
        multi_index::iter::<N>(self.degree).zip(self.coeffs.iter().copied())
    }

    /// Applies `f` to every coefficient.
    pub fn map<D: Coeff>(&self, f: impl FnMut(C) -> D) -> BbPoly<D, N> {
        BbPoly {
            degree: self.degree,
            coeffs: self.coeffs.iter().copied().map(f).collect(),
        }
    }

    /// Largest coefficient norm: the scale of relative tolerances.
    pub fn max_coeff_norm(&self) -> f64 {
        // A running extreme from 0 (`crate::extremes`): the same value as `f64::max`.
        self.coeffs
            .iter()
            .map(|c| c.norm())
            .fold(0.0, crate::extremes::max_not_nan)
    }

    /// One de Casteljau step with the (homogeneous) argument `a`: the degree n−1 polynomial
    /// with coefficients `Σ_i a_i b_{λ+e_i}`. With `a` a point (Σa = 1) this is the first step
    /// of evaluation; with `a` a direction (Σa = 0) it is the directional derivative divided
    /// by n. The degree-0 polynomial is returned unchanged.
    pub fn de_casteljau_step(&self, a: [f64; N]) -> Self {
        if self.degree == 0 {
            return self.clone();
        }
        let m = self.degree - 1;
        let coeffs = multi_index::iter::<N>(m)
            .map(|lambda| {
                let mut acc = C::ZERO;
                for i in 0..N {
                    if a[i] != 0.0 {
                        let mut up = lambda;
                        up[i] += 1;
                        acc = acc.add_scaled(self.coeffs[rank(&up)], a[i]);
                    }
                }
                acc
            })
            .collect();
        BbPoly { degree: m, coeffs }
    }

    /// In-place de Casteljau reduction of a coefficient buffer of degree `n` by `steps` steps
    /// with the arguments `args[k]` (one per step). Works on one buffer with no allocation
    /// beyond the initial copy: at level m the coefficient of rank r(λ) for |λ| = m − 1 only
    /// reads ranks of degree m that are ≥ r(λ), so overwriting in increasing rank is safe.
    fn reduce(mut buf: Vec<C>, n: usize, args: &[[f64; N]]) -> Vec<C> {
        let m = Self::reduce_slice(&mut buf, n, args.len(), |k| args[k]);
        buf.truncate(count::<N>(m));
        buf
    }

    /// The de Casteljau reduction on a buffer holding the degree-`n` coefficients, `steps`
    /// steps, the k-th with argument `arg(k)`; returns the final degree. Rank of `λ + e_0` is
    /// the rank of `λ` (indices with λ_0 ≥ 1 come first, in the same order), so only the
    /// other N − 1 neighbours need a rank computation.
    #[inline]
    fn reduce_slice(
        buf: &mut [C],
        n: usize,
        steps: usize,
        arg: impl Fn(usize) -> [f64; N],
    ) -> usize {
        let mut m = n;
        for k in 0..steps {
            debug_assert!(m > 0);
            let a = arg(k);
            for (r, lambda) in multi_index::iter::<N>(m - 1).enumerate() {
                let mut acc = buf[r] * a[0];
                for i in 1..N {
                    let mut up = lambda;
                    up[i] += 1;
                    acc = acc.add_scaled(buf[rank(&up)], a[i]);
                }
                buf[r] = acc;
            }
            m -= 1;
        }
        m
    }

    /// Value at barycentric coordinates `tau` by de Casteljau's algorithm.
    ///
    /// Arguments outside the simplex (negative coordinates) are allowed: the polynomial is
    /// defined everywhere.
    pub fn eval(&self, tau: [f64; N]) -> C {
        const STACK: usize = 64;
        if self.coeffs.len() <= STACK {
            let mut buf = [C::ZERO; STACK];
            buf[..self.coeffs.len()].copy_from_slice(&self.coeffs);
            Self::reduce_slice(&mut buf, self.degree, self.degree, |_| tau);
            return buf[0];
        }
        let mut buf = self.coeffs.clone();
        Self::reduce_slice(&mut buf, self.degree, self.degree, |_| tau);
        buf[0]
    }

    /// The blossom (polar form) `b[a_1, …, a_n]`: the unique symmetric, multi-affine function
    /// whose diagonal `b[τ, …, τ]` is the polynomial. Arguments are homogeneous barycentric
    /// vectors; the blossom is linear in each, so directions (Σ = 0) are allowed too.
    pub fn blossom(&self, args: &[[f64; N]]) -> Result<C, BbError> {
        if args.len() != self.degree {
            return Err(BbError::InvalidArgument(format!(
                "the blossom of a degree-{} polynomial takes {} arguments, got {}",
                self.degree,
                self.degree,
                args.len()
            )));
        }
        Ok(Self::reduce(self.coeffs.clone(), self.degree, args)[0])
    }

    /// The blossom with `args` followed by `tau` repeated: the workhorse of derivatives.
    fn blossom_tail(&self, args: &[[f64; N]], tau: [f64; N]) -> C {
        let mut all = args.to_vec();
        all.resize(self.degree, tau);
        Self::reduce(self.coeffs.clone(), self.degree, &all)[0]
    }

    /// The fast evaluator for hot loops (see [`BbEvaluator`]).
    pub fn evaluator(&self) -> BbEvaluator<C, N> {
        BbEvaluator::new(self)
    }

    /// Degree elevation by `k`: the same polynomial written in degree n + k, using
    /// `b'_λ = Σ_i (λ_i / (n+1)) b_{λ−e_i}` k times (Farin 1990, §18.9).
    pub fn elevate(&self, k: usize) -> Self {
        let mut p = self.clone();
        for _ in 0..k {
            let n1 = p.degree + 1;
            let coeffs = multi_index::iter::<N>(n1)
                .map(|lambda| {
                    let mut acc = C::ZERO;
                    for i in 0..N {
                        if lambda[i] > 0 {
                            let mut down = lambda;
                            down[i] -= 1;
                            acc =
                                acc.add_scaled(p.coeffs[rank(&down)], lambda[i] as f64 / n1 as f64);
                        }
                    }
                    acc
                })
                .collect();
            p = BbPoly { degree: n1, coeffs };
        }
        p
    }

    /// The derivative in the barycentric direction `d` (Σd = 0), a polynomial of degree n−1:
    /// `D_d p = n Σ_λ (Σ_i d_i b_{λ+e_i}) B_λ^{n−1}` (Farin 1990, (17.10)). With `d = e_i` it is
    /// the formal partial derivative ∂p/∂τ_i.
    pub fn derivative(&self, d: [f64; N]) -> Self {
        if self.degree == 0 {
            return BbPoly::zero(0);
        }
        let n = self.degree as f64;
        let mut step = self.de_casteljau_step(d);
        for c in &mut step.coeffs {
            *c = *c * n;
        }
        step
    }

    /// The mixed directional derivative `D_{d_1}⋯D_{d_r} p(τ) = n!/(n−r)! b[d_1, …, d_r, τ, …, τ]`
    /// (zero when r > n).
    pub fn directional_derivative(&self, tau: [f64; N], dirs: &[[f64; N]]) -> C {
        let r = dirs.len();
        if r > self.degree {
            return C::ZERO;
        }
        let falling: f64 = (0..r).map(|i| (self.degree - i) as f64).product();
        self.blossom_tail(dirs, tau) * falling
    }

    /// The polynomial on another simplex whose vertices have barycentric coordinates
    /// `vertices[k]` with respect to this one: `c_μ = b[w_0^{μ_0}, …, w_{N−1}^{μ_{N−1}}]`.
    /// Subdivision, facet continuation and the midpoint split are special cases.
    pub fn reparametrize(&self, vertices: &[[f64; N]; N]) -> Self {
        // One scratch buffer and argument list for all coefficients (this runs per cell of
        // the subdivisions of `sheet::certified_triangle_b_min`).
        let mut args = Vec::with_capacity(self.degree);
        let mut buf = self.coeffs.clone();
        BbPoly::from_fn(self.degree, |mu| {
            args.clear();
            for (k, &m) in mu.iter().enumerate() {
                args.extend(std::iter::repeat_n(vertices[k], m));
            }
            buf.copy_from_slice(&self.coeffs);
            Self::reduce_slice(&mut buf, self.degree, args.len(), |k| args[k]);
            buf[0]
        })
    }

    /// Subdivision at the point `tau`: N polynomials, the i-th on the sub-simplex obtained by
    /// replacing vertex i with the point. (Sub-simplices with a zero-volume piece, when `tau`
    /// lies on a facet, are still returned; they are just degenerate.)
    pub fn subdivide(&self, tau: [f64; N]) -> Vec<Self> {
        (0..N)
            .map(|i| {
                let mut verts = [[0.0; N]; N];
                for (k, v) in verts.iter_mut().enumerate() {
                    v[k] = 1.0;
                }
                verts[i] = tau;
                self.reparametrize(&verts)
            })
            .collect()
    }

    /// Restriction to the segment from `a` to `b` (barycentric points): the univariate
    /// polynomial `t ↦ p((1 − t) a + t b)` with coefficients `c_k = b[a^{n−k}, b^k]`.
    /// With `a` on a face and `b` the opposite vertex this is the paper's shooting polynomial
    /// ((4.8) of Xu–Huang–Bajaj 2001).
    pub fn restrict_to_segment(&self, a: [f64; N], b: [f64; N]) -> BbPoly<C, 2> {
        let n = self.degree;
        let coeffs = (0..=n)
            .rev()
            .map(|k_a| {
                // Storage order of N = 2 is (n,0), (n−1,1), …: k_a copies of a.
                let mut args = vec![a; k_a];
                args.resize(n, b);
                Self::reduce(self.coeffs.clone(), n, &args)[0]
            })
            .collect();
        BbPoly { degree: n, coeffs }
    }

    /// The layer decomposition along vertex `j` ((4.8) of Xu–Huang–Bajaj 2001): entry `s` is
    /// the degree n−s polynomial B_s on the facet opposite vertex `j` built from the
    /// coefficients with `λ_j = s`, so that
    /// `p((1 − t) q + t v_j) = Σ_s B_s(q) B_s^n(t)` for q on that facet.
    /// `M` must be `N − 1` (checked at compile time).
    pub fn layers<const M: usize>(&self, j: usize) -> Result<Vec<BbPoly<C, M>>, BbError> {
        const { assert!(M + 1 == N, "layers live on the facet: M = N − 1") };
        if j >= N {
            return Err(BbError::Index(format!(
                "vertex {j} of a simplex with {N} vertices"
            )));
        }
        let mut out: Vec<Vec<C>> = vec![Vec::new(); self.degree + 1];
        for (lambda, c) in self.iter() {
            out[lambda[j]].push(c);
        }
        Ok(out
            .into_iter()
            .enumerate()
            .map(|(s, coeffs)| BbPoly {
                degree: self.degree - s,
                coeffs,
            })
            .collect())
    }

    /// Restriction to the facet opposite vertex `j` (the layer `λ_j = 0`), as a polynomial in
    /// the remaining N − 1 barycentric variables (in their original order).
    pub fn restrict_to_facet<const M: usize>(&self, j: usize) -> Result<BbPoly<C, M>, BbError> {
        let mut layers = self.layers::<M>(j)?;
        Ok(layers.swap_remove(0))
    }

    /// Product with a scalar polynomial: `c_λ = Σ_{μ+ν=λ} (C(μ) C(ν) / C(λ)) a_μ b_ν`, with C
    /// the multinomial coefficients (Farin 1990, §18.10).
    pub fn mul_scalar_poly(&self, s: &BbPoly<f64, N>) -> Self {
        let n = self.degree + s.degree;
        let mut coeffs = vec![C::ZERO; count::<N>(n)];
        for (mu, a) in s.iter() {
            let cm = multinomial(&mu);
            for (nu, b) in self.iter() {
                let mut lambda = mu;
                for i in 0..N {
                    lambda[i] += nu[i];
                }
                let w = cm * multinomial(&nu) / multinomial(&lambda);
                let r = rank(&lambda);
                coeffs[r] = coeffs[r].add_scaled(b, a * w);
            }
        }
        BbPoly { degree: n, coeffs }
    }

    /// Sum of two polynomials (the lower degree one is elevated first).
    pub fn add_poly(&self, other: &Self) -> Self {
        let n = self.degree.max(other.degree);
        let a = self.elevate(n - self.degree);
        let b = other.elevate(n - other.degree);
        BbPoly {
            degree: n,
            coeffs: a
                .coeffs
                .iter()
                .zip(&b.coeffs)
                .map(|(x, y)| *x + *y)
                .collect(),
        }
    }

    /// `self * s`.
    pub fn scale(&self, s: f64) -> Self {
        self.map(|c| c * s)
    }
}

impl<C: Coeff> BbPoly<C, 3> {
    /// The midpoint 4-split of a triangle: the polynomial on the four sub-triangles
    /// `[v0 m01 m02]`, `[m01 v1 m12]`, `[m02 m12 v2]` and the centre `[m12 m02 m01]`, where
    /// `m_ij` are edge midpoints. All four keep the orientation of the parent.
    pub fn midpoint_split(&self) -> [Self; 4] {
        let v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        let m01 = [0.5, 0.5, 0.0];
        let m02 = [0.5, 0.0, 0.5];
        let m12 = [0.0, 0.5, 0.5];
        [
            self.reparametrize(&[v[0], m01, m02]),
            self.reparametrize(&[m01, v[1], m12]),
            self.reparametrize(&[m02, m12, v[2]]),
            self.reparametrize(&[m12, m02, m01]),
        ]
    }
}

impl BbPoly<f64, 2> {
    /// A univariate polynomial on [0, 1] from its Bernstein coefficients `b_0 … b_n`
    /// (`b_k` multiplies `B_k^n(t) = C(n,k) (1−t)^{n−k} t^k`).
    pub fn univariate(coeffs: &[f64]) -> Result<Self, BbError> {
        if coeffs.is_empty() {
            return Err(BbError::InvalidArgument(
                "a polynomial needs at least one coefficient".into(),
            ));
        }
        BbPoly::new(coeffs.len() - 1, coeffs.to_vec())
    }

    /// Value at the parameter `t` (barycentric `(1 − t, t)`).
    #[inline]
    pub fn eval_t(&self, t: f64) -> f64 {
        self.eval([1.0 - t, t])
    }
}

impl<const N: usize> BbPoly<f64, N> {
    /// The Cartesian gradient of the polynomial defined on `simplex` at the point `p`
    /// (in-plane for a triangle). Uses n − 1 de Casteljau steps to the degree-1 layer `c`,
    /// then `∇p = n Σ_i c_{e_i} ∇τ_i` (the formal partials combined with the barycentric
    /// gradients, which sum to zero so the result does not depend on the homogenisation).
    pub fn gradient_at(&self, simplex: &Simplex<N>, p: DVec3) -> DVec3 {
        if self.degree == 0 {
            return DVec3::ZERO;
        }
        let tau = simplex.barycentric(p);
        let args = vec![tau; self.degree - 1];
        let c = Self::reduce(self.coeffs.clone(), self.degree, &args);
        let g = simplex.barycentric_gradients();
        let mut grad = DVec3::ZERO;
        for i in 0..N {
            // Rank of e_i in degree 1 is i.
            grad += g[i] * c[i];
        }
        grad * self.degree as f64
    }

    /// The Cartesian Hessian at `p`: `n(n−1) Σ_{ij} c_{e_i+e_j} ∇τ_i ∇τ_jᵀ` with `c` the
    /// degree-2 layer after n − 2 de Casteljau steps.
    pub fn hessian_at(&self, simplex: &Simplex<N>, p: DVec3) -> DMat3 {
        if self.degree < 2 {
            return DMat3::ZERO;
        }
        let tau = simplex.barycentric(p);
        let args = vec![tau; self.degree - 2];
        let c = Self::reduce(self.coeffs.clone(), self.degree, &args);
        let g = simplex.barycentric_gradients();
        let mut h = DMat3::ZERO;
        for i in 0..N {
            for j in 0..N {
                let mut l = [0; N];
                l[i] += 1;
                l[j] += 1;
                let cij = c[rank(&l)];
                h +=
                    DMat3::from_cols(g[j] * g[i].x, g[j] * g[i].y, g[j] * g[i].z).transpose() * cij;
            }
        }
        h * (self.degree * (self.degree - 1)) as f64
    }

    /// The value at the Cartesian point `p` of the polynomial defined on `simplex`.
    pub fn value_at(&self, simplex: &Simplex<N>, p: DVec3) -> f64 {
        self.eval(simplex.barycentric(p))
    }
}

/// Highest degree the level-table evaluator handles with stack buffers; higher degrees fall
/// back to de Casteljau.
pub const MAX_FAST_DEGREE: usize = 15;

/// Stack buffer length of the level-table evaluator (count of the largest level).
const FAST_BUF: usize = 128;

/// Fast evaluation of a fixed polynomial: `p(τ) = Σ_λ (C(λ) b_λ) τ^λ` with the multinomials
/// folded into the coefficients once.
///
/// The monomials `τ^λ` of degree n are built level by level, each as `τ^{λ−e_i} · τ_i` for the
/// first `i` with `λ_i > 0`, from a precomputed parent table: Σ_k count(k) multiplications and
/// one dot product, with no rank arithmetic at run time. The trivariate cubic (the A-patch hot
/// loop) has an unrolled path.
///
/// Accuracy: inside the simplex every monomial is a product of non-negative factors, each
/// formed with one rounding per factor, so the sum has the conditioning of de Casteljau's
/// convex combinations (relative error O(n · count · ε) in the worst case; the tests compare
/// both paths at 1e-13 relative). Outside the simplex both lose accuracy as the basis loses
/// positivity.
///
/// ```
/// use algesurf_bb::BbPoly;
/// let p = BbPoly::<f64, 4>::from_fn(3, |l| (l[0] + 2 * l[1]) as f64 - l[3] as f64);
/// let fast = p.evaluator();
/// let tau = [0.1, 0.2, 0.3, 0.4];
/// assert!((fast.eval(tau) - p.eval(tau)).abs() < 1e-14);
/// ```
#[derive(Clone, Debug)]
pub struct BbEvaluator<C, const N: usize> {
    degree: usize,
    scaled: Vec<C>,
    /// Per level k = 1..=n: for each λ of degree k, (rank of λ − e_i in degree k−1, i).
    levels: Vec<Vec<(u16, u8)>>,
    fallback: Option<BbPoly<C, N>>,
}

impl<C: Coeff, const N: usize> BbEvaluator<C, N> {
    /// Prepares the evaluator (O(n · count · N)).
    pub fn new(p: &BbPoly<C, N>) -> Self {
        let too_big = (0..=p.degree).map(count::<N>).sum::<usize>() > FAST_BUF * 2;
        if p.degree > MAX_FAST_DEGREE || too_big {
            return BbEvaluator {
                degree: p.degree,
                scaled: Vec::new(),
                levels: Vec::new(),
                fallback: Some(p.clone()),
            };
        }
        let scaled = p.iter().map(|(l, c)| c * multinomial(&l)).collect();
        let levels = (1..=p.degree)
            .map(|k| {
                multi_index::iter::<N>(k)
                    .map(|l| {
                        let i = (0..N).find(|&i| l[i] > 0).expect("degree ≥ 1");
                        let mut parent = l;
                        parent[i] -= 1;
                        (rank(&parent) as u16, i as u8)
                    })
                    .collect()
            })
            .collect();
        BbEvaluator {
            degree: p.degree,
            scaled,
            levels,
            fallback: None,
        }
    }

    /// Value at `tau`.
    #[inline]
    pub fn eval(&self, tau: [f64; N]) -> C {
        if let Some(p) = &self.fallback {
            return p.eval(tau);
        }
        if N == 4 && self.degree == 3 {
            return self.eval_cubic_tet(tau);
        }
        // All levels live in one buffer: level k starts where level k−1 ended, so the parent
        // of an entry is `start_{k−1} + parent`. Only the entries written are read, so the
        // buffer needs no meaningful initial contents beyond the constant 1 at position 0.
        let mut buf = [0.0f64; FAST_BUF * 2];
        buf[0] = 1.0;
        let (mut prev_start, mut start) = (0usize, 1usize);
        for level in &self.levels {
            for (r, &(parent, i)) in level.iter().enumerate() {
                buf[start + r] = buf[prev_start + parent as usize] * tau[i as usize];
            }
            prev_start = start;
            start += level.len();
        }
        let mut sum = C::ZERO;
        for (c, m) in self.scaled.iter().zip(&buf[prev_start..]) {
            sum = sum.add_scaled(*c, *m);
        }
        sum
    }

    /// The 20 cubic monomials in four variables, unrolled, in storage order.
    #[inline]
    fn eval_cubic_tet(&self, tau: [f64; N]) -> C {
        let (a, b, c, d) = (tau[0], tau[1], tau[2], tau[3]);
        let (aa, ab, ac, ad) = (a * a, a * b, a * c, a * d);
        let (bb, bc, bd, cc, cd, dd) = (b * b, b * c, b * d, c * c, c * d, d * d);
        let m = [
            aa * a,
            aa * b,
            aa * c,
            aa * d,
            ab * b,
            ab * c,
            ab * d,
            ac * c,
            ac * d,
            ad * d,
            bb * b,
            bb * c,
            bb * d,
            bc * c,
            bc * d,
            bd * d,
            cc * c,
            cc * d,
            cd * d,
            dd * d,
        ];
        let s = &self.scaled;
        let mut sum = C::ZERO;
        for k in 0..20 {
            sum = sum.add_scaled(s[k], m[k]);
        }
        sum
    }
}
