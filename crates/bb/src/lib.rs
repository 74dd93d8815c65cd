//! Bernstein–Bézier (BB) polynomials on simplices: the algebra under every algesurf surface.
//!
//! ```
//! use algesurf_bb::{BbPoly, Tetrahedron};
//! use glam::DVec3;
//!
//! // A trivariate cubic on a tetrahedron, coefficients b_λ = λ_3 − 1 (so F = 3τ_3 − 1 and F = 0
//! // is the plane τ_3 = 1/3 parallel to the face opposite the apex).
//! let tet = Tetrahedron::new([DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z]).unwrap();
//! let f = BbPoly::<f64, 4>::from_fn(3, |l| l[3] as f64 - 1.0);
//! let p = DVec3::new(0.2, 0.1, 1.0 / 3.0);
//! assert!(f.value_at(&tet, p).abs() < 1e-15);
//! assert!((f.gradient_at(&tet, p) - DVec3::new(0.0, 0.0, 3.0)).length() < 1e-14);
//!
//! // The shooting polynomial from the face point q = (1/3, 1/3, 1/3, 0) to the apex (4.8):
//! let shoot = f.restrict_to_segment([1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0, 0.0], [0.0, 0.0, 0.0, 1.0]);
//! assert!((shoot.eval_t(1.0 / 3.0)).abs() < 1e-15);
//! ```
//!
//! # Contents
//! * [`multi_index`]: multi-indices, their storage order, rank/unrank, layers.
//! * [`BbPoly`]: BB polynomials of any degree in 2, 3 or 4 barycentric variables with `f64`,
//!   point ([`glam::DVec3`]) or homogeneous ([`Weighted`]) coefficients: de Casteljau and fast
//!   evaluation, blossoms, derivatives, degree elevation, subdivision, restriction, layers,
//!   products; Cartesian gradient and Hessian on a [`Tetrahedron`].
//! * [`continuity`]: C^r conditions across a shared facet (Farin), residuals, vertex formulas.
//! * [`monomial`]: conversion to and from the power basis ([`PowerPoly`]), Cartesian on
//!   tetrahedra.
//! * [`roots`]: real roots on [0, 1]: closed-form cubic with the A-patch branch rule, Bernstein
//!   subdivision for any degree.
//! * [`sheet`]: single-sheet conditions (Lemma 2.3 of Xu–Huang–Bajaj 2001, Theorem 2.1 of
//!   Bajaj–Chen–Xu 1994).
//! * [`tensor`], [`bspline`]: tensor-product and mixed triangle × interval bases, B-spline bases.
//!
//! Papers are cited by their files in `shared/papers`; equation numbers refer to them.
#![forbid(unsafe_code)]
#![warn(missing_docs)]
// Index loops over barycentric components (τ_k, ∇τ_k, λ_k with one k) read like the
// formulas they implement; iterator chains over zipped arrays would hide that.
#![allow(clippy::needless_range_loop)]

pub mod coeff;
pub mod error;
pub mod multi_index;
pub mod poly;
pub mod simplex;

pub use coeff::{Coeff, Weighted};
pub use error::BbError;
pub use multi_index::MultiIndex;
pub use poly::{BbCurve, BbEvaluator, BbPoly, BbTetra, BbTriangle};
pub use simplex::{Segment, Simplex, Tetrahedron, Triangle};
pub mod bspline;
pub mod continuity;
pub mod extremes;
pub mod monomial;
pub mod roots;
pub mod sheet;
pub mod tensor;
pub use monomial::PowerPoly;
