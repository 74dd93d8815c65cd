//! Simplices of dimension 1, 2, 3 (segment, triangle, tetrahedron) in R^3, with barycentric ↔
//! Cartesian conversion.
//!
//! For a simplex `[v_0 … v_{N−1}]` let `E = [v_1 − v_0, …, v_{N−1} − v_0]`. The barycentric
//! coordinates of `p` are `τ_k = g_k · (p − v_0)` for k ≥ 1 and `τ_0 = 1 − Σ_{k≥1} τ_k`, where the
//! dual vectors `g_k` are the rows of the pseudo-inverse of E. For a tetrahedron this is the
//! exact inverse and `g_k = ∇τ_k`; for a triangle or segment in R^3 it gives the coordinates
//! of the orthogonal projection of `p` onto the simplex's affine hull. The dual vectors are
//! computed once, in closed form, so each conversion costs a few dot products.

use crate::BbError;
use crate::extremes::max_not_nan;
use glam::{DVec2, DVec3};

/// Relative degeneracy threshold: a simplex whose measure `sqrt(det EᵀE)` is below
/// `DEGENERACY_TOLERANCE · L^d` (L the longest edge, d the dimension) is rejected.
///
/// Why this scale: the condition number of the barycentric map grows like `L^d / measure`, so
/// at 1e-10 barycentric coordinates computed in f64 keep about 6 significant digits — the
/// least that the continuity checks of this crate (relative 1e-9) can work with. The ratio is
/// invariant under scaling and translation, so it suits meshes of any size.
pub const DEGENERACY_TOLERANCE: f64 = 1e-10;

/// The squared longest edges `L²` whose simplices [`Simplex::new`] builds in closed form
/// directly: `L ∈ [2^-240, 2^240]`. The closed forms multiply up to four lengths
/// (`|e_0 × e_1|² ∝ L⁴` for a triangle, `det E ∝ L³` for a tetrahedron), and `L⁴` stays within
/// `[2^-960, 2^960]`, clear of overflow and of the subnormal range at the degeneracy
/// tolerance's `10^-20 L⁴`. Simplices outside it are built on a copy scaled by a power of two
/// (`Simplex::rescaled`).
const IN_RANGE_EDGES_SQUARED: std::ops::RangeInclusive<f64> =
    f64::from_bits((1023 - 480) << 52)..=f64::from_bits((1023 + 480) << 52);

/// `2^e` for `e ∈ [-1022, 1023]`, exactly (the normal powers of two).
fn power_of_two(e: i32) -> f64 {
    f64::from_bits(((1023 + e) as u64) << 52)
}

/// A simplex with N vertices in R^3 (N = 2 segment, 3 triangle, 4 tetrahedron).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Simplex<const N: usize> {
    vertices: [DVec3; N],
    /// Dual vectors: `τ_k(p) = duals[k] · (p − v_0)` for k ≥ 1; `duals[0] = −Σ_{k≥1} duals[k]`.
    duals: [DVec3; N],
    relative_measure: f64,
}

/// A line segment `[v_0 v_1]`.
pub type Segment = Simplex<2>;
/// A triangle `[v_0 v_1 v_2]`.
pub type Triangle = Simplex<3>;
/// A tetrahedron `[v_0 v_1 v_2 v_3]`.
pub type Tetrahedron = Simplex<4>;

impl<const N: usize> Simplex<N> {
    /// A simplex from its vertices, rejecting non-finite or degenerate input (see
    /// [`DEGENERACY_TOLERANCE`]).
    ///
    /// ```
    /// use algesurf_bb::Tetrahedron;
    /// use glam::DVec3;
    /// let t = Tetrahedron::new([DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z]).unwrap();
    /// let tau = t.barycentric(DVec3::new(0.25, 0.25, 0.25));
    /// assert!((tau[0] - 0.25).abs() < 1e-15);
    /// assert!(Tetrahedron::new([DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::X + DVec3::Y]).is_err());
    /// // Any size f64 can invert: scaling by 2^e scales the barycentric gradients by 2^-e.
    /// let s = 2f64.powi(900);
    /// let huge = Tetrahedron::new(t.vertices().map(|v| v * s))?;
    /// assert_eq!(huge.barycentric_gradients()[1], t.barycentric_gradients()[1] / s);
    /// # Ok::<(), algesurf_bb::BbError>(())
    /// ```
    ///
    /// # Range
    /// Nothing here depends on the unit: the tolerance is relative, and scaling the vertices
    /// by a power of two scales the barycentric gradients by its inverse, bit for bit, while
    /// the coordinates stay normal numbers (tested from edges of `2^-1018` to `2^1018`).
    ///
    /// # Errors
    /// [`BbError::NonFinite`] for a NaN or infinite coordinate;
    /// [`BbError::DegenerateSimplex`] below the tolerance; [`BbError::InvalidArgument`] when
    /// the edge vectors' largest coordinate is outside `[2^-1022, 2^1019)`, where the
    /// barycentric gradients (of size at least `1/L`) would overflow or be subnormal, or the
    /// edge vectors themselves overflow.
    pub fn new(vertices: [DVec3; N]) -> Result<Self, BbError> {
        const { assert!(N >= 2 && N <= 4, "simplices have 2, 3 or 4 vertices in R^3") };
        if vertices.iter().any(|v| !v.is_finite()) {
            return Err(BbError::NonFinite {
                what: "simplex vertex",
            });
        }
        Self::closed_form(vertices, true)
    }

    /// [`Simplex::new`] on finite vertices by the closed forms, which are trusted only when the
    /// longest edge `L` is in `[2^-240, 2^240]` ([`IN_RANGE_EDGES_SQUARED`]): beyond, their
    /// products of up to four lengths (`|e_0 × e_1|²` of a triangle) could overflow or
    /// underflow, and with `rescale` the simplex goes to [`Simplex::rescaled`] instead (which
    /// calls this without, on a simplex in range). One function returning the simplex, not an
    /// option of it, because this runs for every tetrahedron of a hull: the option's extra
    /// copies of the 200-byte result were 0.3 % of the bunny's instructions.
    #[inline(always)]
    fn closed_form(vertices: [DVec3; N], rescale: bool) -> Result<Self, BbError> {
        // The edge vectors from v_0 (N − 1 ≤ 3 of them; a fixed array, as this runs for every
        // tetrahedron of a hull and every sub-tetrahedron of a split face).
        let mut e = [DVec3::ZERO; 3];
        for k in 1..N {
            e[k - 1] = vertices[k] - vertices[0];
        }
        let mut longest_squared: f64 = 0.0;
        for a in 0..N {
            for b in a + 1..N {
                // A running extreme from 0: never NaN (a NaN distance is skipped, as by
                // `f64::max`; non-finite vertices were refused above).
                longest_squared =
                    max_not_nan(longest_squared, vertices[a].distance_squared(vertices[b]));
            }
        }
        if rescale && !IN_RANGE_EDGES_SQUARED.contains(&longest_squared) {
            return Self::rescaled(vertices);
        }
        // One square root for the six edges: a correctly rounded square root is monotone, so
        // the root of the largest square is the largest of the roots, bit for bit.
        let longest = longest_squared.sqrt();
        // Dual vectors in closed form (rows of E⁻¹ as cross products over the determinant for
        // a tetrahedron, their in-plane analogue for a triangle). Forming them through the Gram
        // matrix (EᵀE)⁻¹Eᵀ would square the condition number κ of the barycentric map: with
        // κ ≈ 16 that showed up as 2e-13 errors in gradients at vertices; these formulas keep
        // the error at O(ε κ).
        let mut duals = [DVec3::ZERO; N];
        let measure = match N {
            2 => {
                duals[1] = e[0] / e[0].length_squared();
                e[0].length()
            }
            3 => {
                let n = e[0].cross(e[1]);
                let nn = n.length_squared();
                duals[1] = e[1].cross(n) / nn;
                duals[2] = n.cross(e[0]) / nn;
                nn.sqrt()
            }
            _ => {
                let det = e[0].dot(e[1].cross(e[2]));
                duals[1] = e[1].cross(e[2]) / det;
                duals[2] = e[2].cross(e[0]) / det;
                duals[3] = e[0].cross(e[1]) / det;
                det.abs()
            }
        };
        let relative_measure = if longest > 0.0 {
            measure / longest.powi(N as i32 - 1)
        } else {
            0.0
        };
        if relative_measure.is_nan() || relative_measure < DEGENERACY_TOLERANCE {
            return Err(BbError::DegenerateSimplex {
                relative_measure,
                tolerance: DEGENERACY_TOLERANCE,
            });
        }
        duals[0] = -duals[1..].iter().copied().sum::<DVec3>();
        Ok(Simplex {
            vertices,
            duals,
            relative_measure,
        })
    }

    /// [`Simplex::new`] for a simplex whose longest edge is outside `[2^-240, 2^240]`: the
    /// simplex is translated to `v_0` and scaled by `s = 2^-k`, `2^k` the largest power of two
    /// at most its largest edge-vector coordinate. Then every edge-vector coordinate is in
    /// `(-2, 2)` and the largest in `[1, 2)`, so the longest edge is in `[1, 4√3)`, in range.
    /// Scaling by a power of two is exact, and the dual vectors of `E = E'/s` are those of `E'`
    /// times `s`, so the result is, bit for bit, the scaled simplex's duals scaled back, and
    /// its relative measure, which does not depend on the scale, the scaled simplex's. Kept
    /// out of the way of the ordinary sizes.
    #[cold]
    fn rescaled(vertices: [DVec3; N]) -> Result<Self, BbError> {
        let edges = vertices.map(|v| v - vertices[0]);
        let largest = edges
            .iter()
            .map(|e| e.abs().max_element())
            .fold(0.0, f64::max);
        if largest == 0.0 {
            return Err(BbError::DegenerateSimplex {
                relative_measure: 0.0,
                tolerance: DEGENERACY_TOLERANCE,
            });
        }
        // The exponent of `largest` (-1023 for a subnormal one; an overflowed edge, whose
        // `largest` is infinite, has 1024).
        let k = ((largest.to_bits() >> 52) & 0x7ff) as i32 - 1023;
        // Below 2^-1022 the barycentric gradients, of size ≥ 1/L, can overflow; beyond 2^1018
        // they can be subnormal (and beyond 2^1023 the edge vectors overflow).
        if !(-1022..=1018).contains(&k) {
            return Err(BbError::InvalidArgument(format!(
                "the simplex's largest edge-vector coordinate is of order 2^{k}, beyond the \
                 range of f64's barycentric coordinates (it must lie in [2^-1022, 2^1019))"
            )));
        }
        let scale = power_of_two(-k);
        // Its edges are in [1, 4√3), in range: no second rescaling.
        let scaled = Self::closed_form(edges.map(|e| e * scale), false)?;
        Ok(Simplex {
            vertices,
            duals: scaled.duals.map(|d| d * scale),
            relative_measure: scaled.relative_measure,
        })
    }

    /// The vertices.
    #[inline]
    pub fn vertices(&self) -> &[DVec3; N] {
        &self.vertices
    }

    /// Vertex `i`.
    #[inline]
    pub fn vertex(&self, i: usize) -> DVec3 {
        self.vertices[i]
    }

    /// The simplex's d-volume times d! (`sqrt(det EᵀE)`) over `L^d`: 0 for a degenerate simplex; about 0.41 (tetrahedron), 0.87
    /// (triangle) and 1 (segment) for regular ones.
    #[inline]
    pub fn relative_measure(&self) -> f64 {
        self.relative_measure
    }

    /// Barycentric coordinates of `p` (of its orthogonal projection onto the affine hull when
    /// N < 4). They sum to 1 up to rounding.
    #[inline]
    pub fn barycentric(&self, p: DVec3) -> [f64; N] {
        let d = p - self.vertices[0];
        let mut tau = [0.0; N];
        let mut rest = 1.0;
        for k in 1..N {
            tau[k] = self.duals[k].dot(d);
            rest -= tau[k];
        }
        tau[0] = rest;
        tau
    }

    /// The point with barycentric coordinates `tau`.
    #[inline]
    pub fn point(&self, tau: [f64; N]) -> DVec3 {
        let mut p = DVec3::ZERO;
        for k in 0..N {
            p += self.vertices[k] * tau[k];
        }
        p
    }

    /// The barycentric direction (components summing to 0) of the Cartesian vector `v`
    /// (of its projection onto the affine hull when N < 4).
    #[inline]
    pub fn barycentric_direction(&self, v: DVec3) -> [f64; N] {
        let mut d = [0.0; N];
        for k in 0..N {
            d[k] = self.duals[k].dot(v);
        }
        d
    }

    /// The Cartesian vector of a barycentric direction.
    #[inline]
    pub fn cartesian_direction(&self, d: [f64; N]) -> DVec3 {
        let mut v = DVec3::ZERO;
        for k in 0..N {
            v += self.vertices[k] * d[k];
        }
        v
    }

    /// The gradients `∇τ_k` of the barycentric coordinates (in-plane for a triangle, along the
    /// segment for a segment). They sum to zero.
    #[inline]
    pub fn barycentric_gradients(&self) -> &[DVec3; N] {
        &self.duals
    }
}

impl Triangle {
    /// A triangle in the plane z = 0 from 2D points: the planar domain triangles of triangular
    /// splines and of the mixed bases.
    pub fn planar(a: DVec2, b: DVec2, c: DVec2) -> Result<Self, BbError> {
        Triangle::new([a.extend(0.0), b.extend(0.0), c.extend(0.0)])
    }

    /// Barycentric coordinates of a 2D point with respect to a [`Triangle::planar`] triangle.
    #[inline]
    pub fn barycentric_2d(&self, p: DVec2) -> [f64; 3] {
        self.barycentric(p.extend(0.0))
    }
}
