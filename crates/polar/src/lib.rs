//! Polar forms (blossoms) of parametric Bézier curves and triangular Bézier patches in R^3:
//! affine frames, control nets over any frame, de Casteljau subdivision and C^k conditions
//! between patches, in the language of Dianna Xu's thesis (2002), chapters 2–3 and §5.3.
//!
//! ```
//! use algesurf_polar::{AffineFrame, PolarLabel, PolarPatch, continuity};
//! use glam::{DVec2, DVec3};
//!
//! // A cubic patch over the frame Δrst, control points f(r^i s^j t^k).
//! let frame = AffineFrame::new(DVec2::ZERO, DVec2::new(2.0, 0.0), DVec2::new(0.5, 1.5))?;
//! let patch = PolarPatch::from_fn(frame, 3, |l: PolarLabel| {
//!     DVec3::new(l.j as f64, l.k as f64, (l.i * l.j) as f64 / 3.0)
//! });
//! let a = DVec2::new(0.7, 0.4);
//!
//! // The diagonal of the polar form is the surface.
//! let fa = patch.blossom(&[a, a, a])?;
//! assert!((fa - patch.eval(a)).length() < 1e-12);
//!
//! // The same surface written over another frame (the polar form is frame independent).
//! let other = AffineFrame::new(DVec2::new(-1.0, 0.0), DVec2::new(3.0, 1.0), DVec2::new(0.0, 4.0))?;
//! assert!((patch.reparametrize(other).eval(a) - patch.eval(a)).length() < 1e-12);
//!
//! // A neighbour on the triangle across the edge (s, t), made C^1 by conditions (3.4)–(3.5).
//! let q = DVec2::new(2.5, 2.0);
//! let nb_frame = AffineFrame::new(q, frame.t(), frame.s())?;
//! let neighbour = PolarPatch::from_fn(nb_frame, 3, |_| DVec3::ZERO);
//! let joined = continuity::impose_continuity(&patch, &neighbour, 1)?;
//! assert!(continuity::c1_residual(&patch, &joined)? < 1e-12);
//! assert!(continuity::c2_residual(&patch, &joined)? > 1e-3);
//!
//! // A watertight triangle mesh for display.
//! let (vertices, triangles) = patch.tessellate(3);
//! assert_eq!((vertices.len(), triangles.len()), (45, 64));
//! # Ok::<(), algesurf_polar::PolarError>(())
//! ```
//!
//! # Contents
//! - [`AffineFrame`] (Δrst, Definition 2.2.5) and [`IntervalFrame`] (r, s); polar labels
//!   [`PolarLabel`] `f(r^i s^j t^k)` and [`CurveLabel`] `f(r^i s^j)`.
//! - [`PolarPatch`] and [`PolarCurve`]: polar form evaluation at distinct points (Lemma 2.7.1),
//!   de Casteljau evaluation, derivatives, normals, change of frame, the affine
//!   reparameterisation of Lemma 5.3.3, subdivision at a point and the midpoint 4-split
//!   (§2.7.4), display tessellation, degree elevation.
//! - [`continuity`]: Lemma 3.1.4 and conditions (3.4)–(3.5) — residuals, imposition, measured
//!   derivative jumps, the diamond rule.
//! - [`star`]: the corner star and its three degrees of freedom (Lemma 3.3.2).
//!
//! All the Bernstein–Bézier arithmetic (de Casteljau, blossoms, subdivision) is
//! [`algesurf_bb::BbPoly`]'s; this crate adds the frame-based, polar-form view.
#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod continuity;
pub mod curve;
pub mod error;
pub mod frame;
pub mod label;
pub mod patch;
pub mod star;

pub use continuity::{
    SharedEdge, affine_propagate, c0_residual, c1_diamonds, c1_residual, c2_residual,
    continuity_residual, derivative_jump, diamond_apex, diamond_residual, impose_continuity,
    normal_jump,
};
pub use curve::PolarCurve;
pub use error::PolarError;
pub use frame::{AffineFrame, IntervalFrame};
pub use label::{CurveLabel, PolarLabel};
pub use patch::PolarPatch;
pub use star::{CornerStar, corner_star_residual};
