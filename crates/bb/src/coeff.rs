//! The coefficient types a BB polynomial can carry.
//!
//! A Bernstein–Bézier polynomial is a linear combination of Bernstein basis polynomials, so its
//! coefficients only need to form a real vector space: scalars (`f64`, implicit functions),
//! points (`DVec2`/`DVec3`, parametric curves and patches) and homogeneous points
//! ([`Weighted`], rational curves and patches).

use glam::{DVec2, DVec3, DVec4};
use std::fmt::Debug;
use std::ops::{Add, Mul, Neg, Sub};

/// A coefficient of a BB polynomial: an element of a real vector space with a norm.
///
/// The norm is used only to scale tolerances (for example in continuity residuals), so any
/// norm equivalent to the Euclidean one is fine; we use the Euclidean norm.
pub trait Coeff:
    Copy
    + Debug
    + PartialEq
    + Send
    + Sync
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Neg<Output = Self>
    + Mul<f64, Output = Self>
{
    /// The additive identity.
    const ZERO: Self;
    /// Euclidean norm, used to scale relative tolerances.
    fn norm(&self) -> f64;
    /// `self + other * s`, the axpy of every de Casteljau step.
    #[inline]
    fn add_scaled(self, other: Self, s: f64) -> Self {
        self + other * s
    }
}

impl Coeff for f64 {
    const ZERO: Self = 0.0;
    #[inline]
    fn norm(&self) -> f64 {
        self.abs()
    }
    // Not `mul_add`: on baseline x86-64 (no FMA target feature) it is a libm call that made
    // every de Casteljau step several times slower, and the fused rounding buys nothing for
    // the convex combinations evaluated here.
}

impl Coeff for DVec2 {
    const ZERO: Self = DVec2::ZERO;
    #[inline]
    fn norm(&self) -> f64 {
        self.length()
    }
}

impl Coeff for DVec3 {
    const ZERO: Self = DVec3::ZERO;
    #[inline]
    fn norm(&self) -> f64 {
        self.length()
    }
}

impl Coeff for DVec4 {
    const ZERO: Self = DVec4::ZERO;
    #[inline]
    fn norm(&self) -> f64 {
        self.length()
    }
}

/// A homogeneous (weighted) coefficient `(w·c, w)`: BB polynomials with `Weighted` coefficients
/// are rational BB forms. Evaluate the polynomial, then [`Weighted::project`] the result.
///
/// ```
/// use algesurf_bb::{BbPoly, Weighted};
/// use glam::DVec2;
/// // A quarter circle as a rational quadratic: control points (1,0), (1,1), (0,1), weights 1, 1/√2, 1.
/// let w = std::f64::consts::FRAC_1_SQRT_2;
/// let arc = BbPoly::<Weighted<DVec2>, 2>::new(2, vec![
///     Weighted::from_point(DVec2::new(1.0, 0.0), 1.0),
///     Weighted::from_point(DVec2::new(1.0, 1.0), w),
///     Weighted::from_point(DVec2::new(0.0, 1.0), 1.0),
/// ]).unwrap();
/// let p = arc.eval([0.3, 0.7]).project();
/// assert!((p.length() - 1.0).abs() < 1e-15);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Weighted<C> {
    /// The weighted point `w · c`.
    pub weighted: C,
    /// The weight `w`.
    pub weight: f64,
}

impl<C: Coeff> Weighted<C> {
    /// The homogeneous form of the point `c` with weight `w`.
    pub fn from_point(c: C, w: f64) -> Self {
        Weighted {
            weighted: c * w,
            weight: w,
        }
    }
    /// The affine point `weighted / weight` (non-finite when the weight is zero: a point at
    /// infinity).
    pub fn project(self) -> C {
        self.weighted * (1.0 / self.weight)
    }
}

impl<C: Coeff> Add for Weighted<C> {
    type Output = Self;
    #[inline]
    fn add(self, o: Self) -> Self {
        Weighted {
            weighted: self.weighted + o.weighted,
            weight: self.weight + o.weight,
        }
    }
}
impl<C: Coeff> Sub for Weighted<C> {
    type Output = Self;
    #[inline]
    fn sub(self, o: Self) -> Self {
        Weighted {
            weighted: self.weighted - o.weighted,
            weight: self.weight - o.weight,
        }
    }
}
impl<C: Coeff> Neg for Weighted<C> {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        Weighted {
            weighted: -self.weighted,
            weight: -self.weight,
        }
    }
}
impl<C: Coeff> Mul<f64> for Weighted<C> {
    type Output = Self;
    #[inline]
    fn mul(self, s: f64) -> Self {
        Weighted {
            weighted: self.weighted * s,
            weight: self.weight * s,
        }
    }
}
impl<C: Coeff> Coeff for Weighted<C> {
    const ZERO: Self = Weighted {
        weighted: C::ZERO,
        weight: 0.0,
    };
    fn norm(&self) -> f64 {
        self.weighted.norm().hypot(self.weight)
    }
}
