//! [`PolarCurve`]: a Bézier curve in R^3 given by its polar form over an interval frame
//! (thesis §2.3–2.5).

use crate::patch::bbox_diagonal;
use crate::{CurveLabel, IntervalFrame, PolarError};
use algesurf_bb::BbPoly;
use glam::DVec3;

/// A polynomial curve `F: A → A³` of degree n given by the control points
/// `b_j = f(r^{n−j} s^j)` of its polar form `f` over the interval frame (r, s).
///
/// ```
/// use algesurf_polar::{IntervalFrame, PolarCurve};
/// use glam::DVec3;
/// // The cubic (u, u², u³) over the frame (−1, 3): f(u1,u2,u3) = (mean, mean of pair products, product).
/// let frame = IntervalFrame::new(-1.0, 3.0).unwrap();
/// let f = |a: [f64; 3]| DVec3::new(
///     (a[0] + a[1] + a[2]) / 3.0,
///     (a[0] * a[1] + a[0] * a[2] + a[1] * a[2]) / 3.0,
///     a[0] * a[1] * a[2],
/// );
/// let curve = PolarCurve::from_fn(frame, 3, |l| {
///     let mut a = [3.0; 3];
///     a[..l.i].fill(-1.0);
///     f(a)
/// });
/// assert!((curve.eval(0.5) - DVec3::new(0.5, 0.25, 0.125)).length() < 1e-14);
/// assert!((curve.blossom(&[0.0, 1.0, 2.0]).unwrap() - f([0.0, 1.0, 2.0])).length() < 1e-14);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct PolarCurve {
    frame: IntervalFrame,
    net: BbPoly<DVec3, 2>,
}

impl PolarCurve {
    /// A curve from its control points `f(r^n), f(r^{n−1}s), …, f(s^n)`.
    pub fn new(
        frame: IntervalFrame,
        degree: usize,
        points: Vec<DVec3>,
    ) -> Result<Self, PolarError> {
        Ok(PolarCurve {
            frame,
            net: BbPoly::new(degree, points)?,
        })
    }

    /// A curve whose control point `f(r^i s^j)` is `f(label)`.
    pub fn from_fn(
        frame: IntervalFrame,
        degree: usize,
        mut f: impl FnMut(CurveLabel) -> DVec3,
    ) -> Self {
        PolarCurve {
            frame,
            net: BbPoly::from_fn(degree, |m| f(CurveLabel::new(m[0], m[1]))),
        }
    }

    /// A curve from a univariate Bernstein–Bézier polynomial in the barycentric coordinates of
    /// `frame`.
    pub fn from_bb(frame: IntervalFrame, net: BbPoly<DVec3, 2>) -> Self {
        PolarCurve { frame, net }
    }

    /// The degree n.
    #[inline]
    pub fn degree(&self) -> usize {
        self.net.degree()
    }

    /// The interval frame (r, s).
    #[inline]
    pub fn frame(&self) -> &IntervalFrame {
        &self.frame
    }

    /// The control net as a Bernstein–Bézier polynomial.
    #[inline]
    pub fn bb(&self) -> &BbPoly<DVec3, 2> {
        &self.net
    }

    /// The control points `f(r^n), …, f(s^n)`.
    #[inline]
    pub fn control_points(&self) -> &[DVec3] {
        self.net.coeffs()
    }

    /// The control point `f(r^i s^j)`, or `None` when `i + j ≠ n`.
    #[inline]
    pub fn control_point(&self, label: CurveLabel) -> Option<DVec3> {
        self.net.get([label.i, label.j])
    }

    /// The diagonal of the control polygon's bounding box (scale of relative tolerances).
    pub fn net_size(&self) -> f64 {
        bbox_diagonal(self.net.coeffs())
    }

    /// The polar form `f(u_1, …, u_n)` at n parameters, not necessarily distinct (thesis §2.3).
    pub fn blossom(&self, args: &[f64]) -> Result<DVec3, PolarError> {
        if args.len() != self.degree() {
            return Err(PolarError::ArgumentCount {
                degree: self.degree(),
                found: args.len(),
            });
        }
        if args.iter().any(|a| !a.is_finite()) {
            return Err(PolarError::NonFinite {
                what: "blossom argument",
            });
        }
        let bary: Vec<[f64; 2]> = args.iter().map(|u| self.frame.barycentric(*u)).collect();
        Ok(self.net.blossom(&bary)?)
    }

    /// The curve point `F(u) = f(u, …, u)` by de Casteljau's algorithm.
    #[inline]
    pub fn eval(&self, u: f64) -> DVec3 {
        self.net.eval(self.frame.barycentric(u))
    }

    /// The derivative of order `order` at `u`: `F^{(k)}(u) = n!/(n−k)! f(1̂^k, u^{n−k})` with 1̂
    /// the unit vector of the line (zero when k > n).
    pub fn derivative(&self, u: f64, order: usize) -> DVec3 {
        let d = self.frame.barycentric_direction(1.0);
        self.net
            .directional_derivative(self.frame.barycentric(u), &vec![d; order])
    }

    /// The control points of the same curve with respect to another frame (r', s'):
    /// `f(r'^i s'^j)`.
    pub fn reparametrize(&self, frame: IntervalFrame) -> PolarCurve {
        let verts = [
            self.frame.barycentric(frame.r()),
            self.frame.barycentric(frame.s()),
        ];
        PolarCurve {
            frame,
            net: self.net.reparametrize(&verts),
        }
    }

    /// The curve `F ∘ ρ⁻¹` for the affine map `ρ(u) = a u + b`: the same control points over the
    /// frame `(ρ(r), ρ(s))` (the curve case of Lemma 5.3.3). Fails when `a` is 0.
    pub fn transform_domain(&self, a: f64, b: f64) -> Result<PolarCurve, PolarError> {
        Ok(PolarCurve {
            frame: self.frame.transformed(a, b)?,
            net: self.net.clone(),
        })
    }

    /// Subdivision at `u` by de Casteljau's algorithm: the nets over (r, u) and (u, s).
    pub fn subdivide_at(&self, u: f64) -> Result<[PolarCurve; 2], PolarError> {
        let left = IntervalFrame::new(self.frame.r(), u)?;
        let right = IntervalFrame::new(u, self.frame.s())?;
        let mut nets = self.net.subdivide(self.frame.barycentric(u));
        // subdivide()[i] replaces vertex i: [0] is over (u, s), [1] over (r, u).
        let l = nets.pop().expect("two nets");
        let r = nets.pop().expect("two nets");
        Ok([
            PolarCurve {
                frame: left,
                net: l,
            },
            PolarCurve {
                frame: right,
                net: r,
            },
        ])
    }

    /// Degree elevation by `k` through the polar form (see [`crate::PolarPatch::elevate`]).
    pub fn elevate(&self, k: usize) -> PolarCurve {
        PolarCurve {
            frame: self.frame,
            net: self.net.elevate(k),
        }
    }
}
