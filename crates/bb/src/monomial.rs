//! Conversion between the Bernstein basis and the monomial (power) basis.
//!
//! A [`PowerPoly<N>`] is a polynomial of total degree ≤ n in N − 1 variables
//! `x_1 … x_{N−1}`. Its coefficients are indexed by the same multi-indices as a BB polynomial
//! with N variables: `λ = (n − |μ|, μ_1, …, μ_{N−1})` labels the monomial `x^μ` (the first entry
//! is the homogenising slack), so both bases share [`crate::multi_index`].
//!
//! On a simplex the natural power basis is in the local affine coordinates `u_k = τ_k`
//! (k ≥ 1, with `τ_0 = 1 − Σu`): [`BbPoly::to_power`] and [`BbPoly::from_power`]. For a
//! tetrahedron in R^3, [`BbPoly::from_cartesian`] and [`BbPoly::to_cartesian`] go to and from
//! polynomials in `x, y, z` — the usual way to state an implicit surface.
//!
//! ```
//! use algesurf_bb::{BbPoly, PowerPoly, Tetrahedron};
//! use glam::DVec3;
//! // The unit sphere x² + y² + z² − 1 as a quadratic on a tetrahedron.
//! let mut s = PowerPoly::<4>::zero(2);
//! s.set(&[2, 0, 0], 1.0).unwrap();
//! s.set(&[0, 2, 0], 1.0).unwrap();
//! s.set(&[0, 0, 2], 1.0).unwrap();
//! s.set(&[0, 0, 0], -1.0).unwrap();
//! let tet = Tetrahedron::new([DVec3::ZERO, DVec3::X * 2.0, DVec3::Y * 2.0, DVec3::Z * 2.0]).unwrap();
//! let f = BbPoly::from_cartesian(&tet, &s, 3).unwrap();
//! let p = DVec3::new(0.6, 0.0, 0.8);
//! assert!(f.value_at(&tet, p).abs() < 1e-14);
//! ```

use crate::multi_index::{self, MultiIndex, binomial_f64, count, multinomial, rank};
use crate::{BbError, BbPoly, Tetrahedron};

/// A polynomial in N − 1 variables of total degree ≤ n in the power basis (see the module
/// docs for the indexing).
#[derive(Clone, Debug, PartialEq)]
pub struct PowerPoly<const N: usize> {
    degree: usize,
    coeffs: Vec<f64>,
}

impl<const N: usize> PowerPoly<N> {
    /// The zero polynomial with room for total degree `degree`.
    pub fn zero(degree: usize) -> Self {
        PowerPoly {
            degree,
            coeffs: vec![0.0; count::<N>(degree)],
        }
    }

    /// The constant polynomial `c`.
    pub fn constant(c: f64) -> Self {
        PowerPoly {
            degree: 0,
            coeffs: vec![c],
        }
    }

    /// The affine polynomial `c + Σ_k a_k x_k` (`a.len()` must be N − 1).
    pub fn affine(c: f64, a: &[f64]) -> Result<Self, BbError> {
        if a.len() != N - 1 {
            return Err(BbError::InvalidArgument(format!(
                "an affine function of {} variables needs {} coefficients, got {}",
                N - 1,
                N - 1,
                a.len()
            )));
        }
        let mut p = PowerPoly::zero(1);
        p.set(&vec![0; N - 1], c)?;
        for (k, &ak) in a.iter().enumerate() {
            let mut e = vec![0; N - 1];
            e[k] = 1;
            p.set(&e, ak)?;
        }
        Ok(p)
    }

    /// The bound n on the total degree.
    pub fn degree(&self) -> usize {
        self.degree
    }

    fn index(&self, exps: &[usize]) -> Result<MultiIndex<N>, BbError> {
        if exps.len() != N - 1 {
            return Err(BbError::InvalidArgument(format!(
                "a monomial in {} variables needs {} exponents, got {}",
                N - 1,
                N - 1,
                exps.len()
            )));
        }
        let total: usize = exps.iter().sum();
        if total > self.degree {
            return Err(BbError::Degree(format!(
                "monomial of degree {total} in a polynomial of degree ≤ {}",
                self.degree
            )));
        }
        let mut l = [0; N];
        l[0] = self.degree - total;
        l[1..].copy_from_slice(exps);
        Ok(l)
    }

    /// The coefficient of `x^exps`.
    pub fn coeff(&self, exps: &[usize]) -> Result<f64, BbError> {
        Ok(self.coeffs[rank(&self.index(exps)?)])
    }

    /// Sets the coefficient of `x^exps`.
    pub fn set(&mut self, exps: &[usize], c: f64) -> Result<(), BbError> {
        let r = rank(&self.index(exps)?);
        self.coeffs[r] = c;
        Ok(())
    }

    /// `(exponents, coefficient)` of every monomial (including zero ones).
    pub fn terms(&self) -> impl Iterator<Item = (MultiIndex<N>, f64)> + '_ {
        multi_index::iter::<N>(self.degree).zip(self.coeffs.iter().copied())
    }

    /// Value at `x` (`x.len()` must be N − 1).
    pub fn eval(&self, x: &[f64]) -> f64 {
        assert_eq!(x.len(), N - 1, "point dimension");
        self.terms()
            .map(|(l, c)| {
                let mut m = c;
                for k in 1..N {
                    m *= x[k - 1].powi(l[k] as i32);
                }
                m
            })
            .sum()
    }

    /// The same polynomial with room for a higher total degree.
    pub fn with_degree(&self, degree: usize) -> Result<Self, BbError> {
        if degree < self.degree {
            return Err(BbError::Degree(format!(
                "cannot store a degree-{} polynomial in degree {degree}",
                self.degree
            )));
        }
        let mut out = PowerPoly::zero(degree);
        for (l, c) in self.terms() {
            let mut m = l;
            m[0] += degree - self.degree;
            out.coeffs[rank(&m)] = c;
        }
        Ok(out)
    }

    /// Sum.
    pub fn add(&self, other: &Self) -> Self {
        let n = self.degree.max(other.degree);
        let a = self.with_degree(n).expect("n ≥ degree");
        let b = other.with_degree(n).expect("n ≥ degree");
        PowerPoly {
            degree: n,
            coeffs: a.coeffs.iter().zip(&b.coeffs).map(|(x, y)| x + y).collect(),
        }
    }

    /// `self * s`.
    pub fn scale(&self, s: f64) -> Self {
        PowerPoly {
            degree: self.degree,
            coeffs: self.coeffs.iter().map(|c| c * s).collect(),
        }
    }

    /// Product (degrees add; the slack entries add too, so multi-index addition is monomial
    /// multiplication).
    pub fn mul(&self, other: &Self) -> Self {
        let mut out = PowerPoly::zero(self.degree + other.degree);
        for (a, ca) in self.terms().filter(|t| t.1 != 0.0) {
            for (b, cb) in other.terms().filter(|t| t.1 != 0.0) {
                let mut l = a;
                for k in 0..N {
                    l[k] += b[k];
                }
                out.coeffs[rank(&l)] += ca * cb;
            }
        }
        out
    }

    /// Substitutes `x_k = offset_k + Σ_l matrix[k][l] y_l` (an affine change of variables)
    /// and returns the polynomial in `y`.
    pub fn compose_affine(&self, offset: &[f64], matrix: &[Vec<f64>]) -> Result<Self, BbError> {
        if offset.len() != N - 1 || matrix.len() != N - 1 || matrix.iter().any(|r| r.len() != N - 1)
        {
            return Err(BbError::InvalidArgument(format!(
                "an affine map of R^{} needs a {}-vector and a {}×{} matrix",
                N - 1,
                N - 1,
                N - 1,
                N - 1
            )));
        }
        // Powers L_k^e of the substituted linear forms, e = 0..=n, computed once.
        let lin: Vec<PowerPoly<N>> = (0..N - 1)
            .map(|k| PowerPoly::affine(offset[k], &matrix[k]))
            .collect::<Result<_, _>>()?;
        let powers: Vec<Vec<PowerPoly<N>>> = lin
            .iter()
            .map(|l| {
                let mut v = vec![PowerPoly::constant(1.0)];
                for e in 1..=self.degree {
                    let next = v[e - 1].mul(l);
                    v.push(next);
                }
                v
            })
            .collect();
        let mut out = PowerPoly::zero(self.degree);
        for (l, c) in self.terms().filter(|t| t.1 != 0.0) {
            let mut term = PowerPoly::constant(c);
            for k in 1..N {
                term = term.mul(&powers[k - 1][l[k]]);
            }
            out = out.add(
                &term
                    .with_degree(self.degree)
                    .expect("degree of a composed term"),
            );
        }
        Ok(out)
    }
}

impl<const N: usize> BbPoly<f64, N> {
    /// The polynomial in the power basis of the local coordinates `u_k = τ_k` (k ≥ 1):
    /// `c_μ = n!/((n−|μ|)! μ!) Δ^μ b_{n e_0}`, the forward differences
    /// `Δ^μ b = Σ_{ν≤μ} (−1)^{|μ−ν|} Π_k C(μ_k, ν_k) b_{(n−|ν|) e_0 + ν}` (Farin 1990, §18.2,
    /// generalised to N variables).
    ///
    /// The power basis is ill-conditioned against the Bernstein basis (Farouki & Rajan 1987):
    /// the alternating sums cancel, so a round trip through [`BbPoly::from_power`] loses digits
    /// with the degree. Measured on coefficients of size ~0.5: ~1e-15 at degree 4, ~3e-8 at
    /// degree 20, ~1e2 at degree 40 (curves and triangles alike). Keep to low degrees.
    pub fn to_power(&self) -> PowerPoly<N> {
        let n = self.degree();
        let coeffs = multi_index::iter::<N>(n)
            .map(|mu| {
                // Enumerate ν ≤ μ in the components 1..N.
                let mut sum = 0.0;
                let mut nu = [0usize; N];
                loop {
                    let nu_tot: usize = nu[1..].iter().sum();
                    let mut w = 1.0;
                    let mut sign_exp = 0;
                    for k in 1..N {
                        w *= binomial_f64(mu[k], nu[k]);
                        sign_exp += mu[k] - nu[k];
                    }
                    let mut idx = nu;
                    idx[0] = n - nu_tot;
                    let b = self.coeffs()[rank(&idx)];
                    sum += if sign_exp % 2 == 0 { w * b } else { -w * b };
                    // Next ν (odometer over components 1..N).
                    let mut k = 1;
                    while k < N {
                        if nu[k] < mu[k] {
                            nu[k] += 1;
                            break;
                        }
                        nu[k] = 0;
                        k += 1;
                    }
                    if k == N {
                        break;
                    }
                }
                multinomial(&mu) * sum
            })
            .collect();
        PowerPoly { degree: n, coeffs }
    }

    /// The BB form of degree `degree` (≥ the power polynomial's degree bound) of a polynomial
    /// given in the local power basis: `b_λ = Σ_{μ ≤ λ} c_μ Π_k C(λ_k, μ_k) / C(n; μ)`, the
    /// blossom of `u^μ` at the vertices (each vertex `e_k` makes `u_k` one and the others zero).
    pub fn from_power(p: &PowerPoly<N>, degree: usize) -> Result<Self, BbError> {
        let p = p.with_degree(degree)?;
        Ok(BbPoly::from_fn(degree, |lambda| {
            p.terms()
                .filter(|(mu, c)| *c != 0.0 && (1..N).all(|k| mu[k] <= lambda[k]))
                .map(|(mu, c)| {
                    let mut w = c / multinomial(&mu);
                    for k in 1..N {
                        w *= binomial_f64(lambda[k], mu[k]);
                    }
                    w
                })
                .sum()
        }))
    }
}

impl BbPoly<f64, 4> {
    /// The BB form on `tet` of a polynomial in Cartesian `x, y, z` (degree ≤ `degree`):
    /// substitute `x = v_0 + Σ_k u_k (v_k − v_0)`, then [`BbPoly::from_power`].
    pub fn from_cartesian(
        tet: &Tetrahedron,
        p: &PowerPoly<4>,
        degree: usize,
    ) -> Result<Self, BbError> {
        let v = tet.vertices();
        let e: Vec<_> = (1..4).map(|k| v[k] - v[0]).collect();
        let matrix: Vec<Vec<f64>> = (0..3)
            .map(|row| e.iter().map(|ek| ek.to_array()[row]).collect())
            .collect();
        let local = p.compose_affine(&v[0].to_array(), &matrix)?;
        BbPoly::from_power(&local, degree)
    }

    /// The polynomial in Cartesian `x, y, z` of this BB form on `tet`: [`BbPoly::to_power`]
    /// then `u_k = ∇τ_k · (x − v_0)`.
    pub fn to_cartesian(&self, tet: &Tetrahedron) -> PowerPoly<4> {
        let g = tet.barycentric_gradients();
        let v0 = tet.vertex(0);
        let matrix: Vec<Vec<f64>> = (1..4).map(|k| g[k].to_array().to_vec()).collect();
        let offset: Vec<f64> = (1..4).map(|k| -g[k].dot(v0)).collect();
        self.to_power()
            .compose_affine(&offset, &matrix)
            .expect("dimensions are fixed for a tetrahedron")
    }
}
