//! Affine frames of the domain: the reference triangle Δrst of a triangular patch (thesis
//! Definition 2.2.5, §2.7.3) and the interval frame (r, s) of a curve (§2.3).
//!
//! A point `a` of the plane has the barycentric (affine) coordinates `(λ, μ, ν)` with respect to
//! Δrst when `a = λ r + μ s + ν t`, `λ + μ + ν = 1`; a vector `u` has coordinates summing to 0.
//! These are the arguments the Bernstein–Bézier layer works with.

use crate::PolarError;
use algesurf_bb::simplex::DEGENERACY_TOLERANCE;
use glam::{DAffine2, DVec2};

/// An affine frame Δrst of the domain plane: three affinely independent points (thesis
/// Definition 2.2.5, §2.7.3). Control points of a triangular patch over the frame are the polar
/// values `f(r^i s^j t^k)`.
///
/// Construction rejects non-finite and (nearly) collinear points with the relative tolerance of
/// [`algesurf_bb::simplex::DEGENERACY_TOLERANCE`] applied to `|det(s − r, t − r)| / L²` (L the
/// longest edge), the same measure as [`algesurf_bb::Triangle`]'s.
///
/// ```
/// use algesurf_polar::AffineFrame;
/// use glam::DVec2;
/// let f = AffineFrame::new(DVec2::ZERO, DVec2::new(2.0, 0.0), DVec2::new(0.0, 2.0)).unwrap();
/// assert_eq!(f.barycentric(DVec2::new(1.0, 0.5)), [0.25, 0.5, 0.25]);
/// assert!(AffineFrame::new(DVec2::ZERO, DVec2::X, DVec2::new(2.0, 0.0)).is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AffineFrame {
    r: DVec2,
    s: DVec2,
    t: DVec2,
    /// Rows of the inverse of `[s − r, t − r]`: `μ = inv[0]·(a − r)`, `ν = inv[1]·(a − r)`.
    inv: [DVec2; 2],
    relative_area: f64,
}

impl AffineFrame {
    /// The frame Δrst, or [`PolarError::DegenerateFrame`] / [`PolarError::NonFinite`].
    pub fn new(r: DVec2, s: DVec2, t: DVec2) -> Result<Self, PolarError> {
        if !(r.is_finite() && s.is_finite() && t.is_finite()) {
            return Err(PolarError::NonFinite {
                what: "affine frame point",
            });
        }
        let e1 = s - r;
        let e2 = t - r;
        let det = e1.perp_dot(e2);
        let longest = e1.length().max(e2.length()).max((t - s).length());
        let relative_area = if longest > 0.0 {
            det.abs() / (longest * longest)
        } else {
            0.0
        };
        if relative_area.is_nan() || relative_area < DEGENERACY_TOLERANCE {
            return Err(PolarError::DegenerateFrame {
                relative_area,
                tolerance: DEGENERACY_TOLERANCE,
            });
        }
        let inv = [DVec2::new(e2.y, -e2.x) / det, DVec2::new(-e1.y, e1.x) / det];
        Ok(AffineFrame {
            r,
            s,
            t,
            inv,
            relative_area,
        })
    }

    /// The frame r = (0, 0), s = (1, 0), t = (0, 1).
    pub fn unit() -> Self {
        AffineFrame {
            r: DVec2::ZERO,
            s: DVec2::X,
            t: DVec2::Y,
            inv: [DVec2::X, DVec2::Y],
            relative_area: 0.5,
        }
    }

    /// The frame from its three points in the order r, s, t.
    pub fn from_points(points: [DVec2; 3]) -> Result<Self, PolarError> {
        Self::new(points[0], points[1], points[2])
    }

    /// The first point r.
    #[inline]
    pub fn r(&self) -> DVec2 {
        self.r
    }
    /// The second point s.
    #[inline]
    pub fn s(&self) -> DVec2 {
        self.s
    }
    /// The third point t.
    #[inline]
    pub fn t(&self) -> DVec2 {
        self.t
    }
    /// `[r, s, t]`.
    #[inline]
    pub fn points(&self) -> [DVec2; 3] {
        [self.r, self.s, self.t]
    }
    /// Point `i` of `[r, s, t]`.
    ///
    /// # Panics
    /// Panics when `i > 2`.
    #[inline]
    pub fn point_at(&self, i: usize) -> DVec2 {
        self.points()[i]
    }

    /// `|det(s − r, t − r)| / L²` (L the longest edge): 0 for collinear points, √3/2 ≈ 0.87 for
    /// an equilateral triangle, 0.5 for [`AffineFrame::unit`].
    #[inline]
    pub fn relative_area(&self) -> f64 {
        self.relative_area
    }

    /// The signed area of Δrst, positive when r, s, t turn counter-clockwise.
    #[inline]
    pub fn signed_area(&self) -> f64 {
        0.5 * (self.s - self.r).perp_dot(self.t - self.r)
    }

    /// The longest edge length: the length scale of the domain.
    #[inline]
    pub fn diameter(&self) -> f64 {
        (self.s - self.r)
            .length()
            .max((self.t - self.r).length())
            .max((self.t - self.s).length())
    }

    /// Barycentric coordinates `(λ, μ, ν)` of the point `a = λ r + μ s + ν t`.
    #[inline]
    pub fn barycentric(&self, a: DVec2) -> [f64; 3] {
        let d = a - self.r;
        let mu = self.inv[0].dot(d);
        let nu = self.inv[1].dot(d);
        [1.0 - mu - nu, mu, nu]
    }

    /// Barycentric coordinates of the vector `u` (they sum to 0):
    /// `u = λ r + μ s + ν t` as a vector of the homogenised plane.
    #[inline]
    pub fn barycentric_direction(&self, u: DVec2) -> [f64; 3] {
        let mu = self.inv[0].dot(u);
        let nu = self.inv[1].dot(u);
        [-mu - nu, mu, nu]
    }

    /// The point (or, for coordinates summing to 0, the vector) `λ r + μ s + ν t`.
    #[inline]
    pub fn point(&self, bary: [f64; 3]) -> DVec2 {
        self.r * bary[0] + self.s * bary[1] + self.t * bary[2]
    }

    /// The image frame `ρ(r) ρ(s) ρ(t)` under an affine map of the plane (the reparameterisation
    /// maps of thesis Definition 5.3.2). Fails when ρ is singular.
    pub fn transformed(&self, rho: DAffine2) -> Result<Self, PolarError> {
        Self::new(
            rho.transform_point2(self.r),
            rho.transform_point2(self.s),
            rho.transform_point2(self.t),
        )
    }

    /// Index (0 for r, 1 for s, 2 for t) of the frame point within `tol · diameter` of `a`.
    pub fn vertex_index(&self, a: DVec2, tol: f64) -> Option<usize> {
        let eps = tol * self.diameter();
        self.points().iter().position(|v| v.distance(a) <= eps)
    }

    /// A frame from points known to be affinely independent with the same shape as `self`
    /// (sub-frames of the midpoint split), skipping the degeneracy check.
    fn similar(&self, r: DVec2, s: DVec2, t: DVec2) -> Self {
        let e1 = s - r;
        let e2 = t - r;
        let det = e1.perp_dot(e2);
        AffineFrame {
            r,
            s,
            t,
            inv: [DVec2::new(e2.y, -e2.x) / det, DVec2::new(-e1.y, e1.x) / det],
            relative_area: self.relative_area,
        }
    }

    /// The midpoint 4-split of thesis §2.7.4 (Figure 2.5): with `c`, `b`, `a` the midpoints of
    /// rs, rt, st, the frames `[r c b]`, `[c s a]`, `[b a t]` and the centre `[a b c]` (the
    /// thesis's Δcrb, Δsca, Δbat(=Δabt) and Δbac up to the order of points), in the order and
    /// orientation of [`algesurf_bb::BbPoly::midpoint_split`].
    pub fn midpoint_split(&self) -> [AffineFrame; 4] {
        let a = 0.5 * (self.s + self.t);
        let b = 0.5 * (self.r + self.t);
        let c = 0.5 * (self.r + self.s);
        [
            self.similar(self.r, c, b),
            self.similar(c, self.s, a),
            self.similar(b, a, self.t),
            self.similar(a, b, c),
        ]
    }
}

/// An affine frame (r, s) of the affine line, r ≠ s: control points of a curve over it are the
/// polar values `f(r^i s^j)` (thesis §2.3, e.g. the frame r = −1, s = 3 of §2.3's cubic).
///
/// ```
/// use algesurf_polar::IntervalFrame;
/// let f = IntervalFrame::new(-1.0, 3.0).unwrap();
/// assert_eq!(f.barycentric(0.0), [0.75, 0.25]);
/// assert!(IntervalFrame::new(2.0, 2.0).is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IntervalFrame {
    r: f64,
    s: f64,
}

impl IntervalFrame {
    /// The frame (r, s), or an error when r and s are not finite or coincide up to a relative
    /// [`algesurf_bb::simplex::DEGENERACY_TOLERANCE`].
    pub fn new(r: f64, s: f64) -> Result<Self, PolarError> {
        if !(r.is_finite() && s.is_finite()) {
            return Err(PolarError::NonFinite {
                what: "interval frame point",
            });
        }
        if (s - r).abs() <= DEGENERACY_TOLERANCE * r.abs().max(s.abs()) {
            return Err(PolarError::DegenerateInterval { r, s });
        }
        Ok(IntervalFrame { r, s })
    }

    /// The frame (0, 1).
    pub fn unit() -> Self {
        IntervalFrame { r: 0.0, s: 1.0 }
    }

    /// The first point r.
    #[inline]
    pub fn r(&self) -> f64 {
        self.r
    }
    /// The second point s.
    #[inline]
    pub fn s(&self) -> f64 {
        self.s
    }

    /// Barycentric coordinates `(λ, μ)` of `u = λ r + μ s`.
    #[inline]
    pub fn barycentric(&self, u: f64) -> [f64; 2] {
        let mu = (u - self.r) / (self.s - self.r);
        [1.0 - mu, mu]
    }

    /// Barycentric coordinates of the vector `du` (they sum to 0).
    #[inline]
    pub fn barycentric_direction(&self, du: f64) -> [f64; 2] {
        let mu = du / (self.s - self.r);
        [-mu, mu]
    }

    /// The point `λ r + μ s`.
    #[inline]
    pub fn point(&self, bary: [f64; 2]) -> f64 {
        self.r * bary[0] + self.s * bary[1]
    }

    /// The image frame `(a r + b, a s + b)` under the affine map `u ↦ a u + b`.
    pub fn transformed(&self, a: f64, b: f64) -> Result<Self, PolarError> {
        Self::new(a * self.r + b, a * self.s + b)
    }
}
