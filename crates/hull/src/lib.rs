//! The outer simplicial hull Σ of Xu, Huang and Bajaj, *C¹ modeling with A-patches from
//! rational trivariate functions* (CAGD 2001), §3: convexity of edges and faces, face
//! tetrahedra (§3.1), edge tetrahedra (§3.2), detection of intersecting tetrahedra and their
//! resolution by local Butterfly refinement.
//!
//! ```
//! use algesurf_hull::{Convexity, HullOptions, SimplicialHull};
//! use glam::DVec3;
//!
//! // The two triangles of the paper's Fig. 6 (§6), oriented so that the normals point to the
//! // positive side (counter-clockwise seen from +z).
//! let p = [
//!     DVec3::new(-2.0, 0.0, 0.0),
//!     DVec3::new(2.0, 0.0, 0.0),
//!     DVec3::new(0.0, 4.0, -1.0),
//!     DVec3::new(0.0, -4.0, -1.0),
//! ];
//! let n = [
//!     DVec3::new(-1.0, 0.0, 1.0).normalize(),
//!     DVec3::new(1.0, 0.0, 1.0).normalize(),
//!     DVec3::new(0.0, 1.0, 1.0).normalize(),
//!     DVec3::new(0.0, -1.0, 1.0).normalize(),
//! ];
//! let hull = SimplicialHull::new(&p, &[[0, 1, 2], [1, 0, 3]], &n, &HullOptions::default())?;
//! assert!(hull.faces().iter().all(|f| f.convexity == Convexity::PositiveConvex));
//! let edge = hull.edge_between(0, 1).unwrap();
//! assert_eq!(edge.convexity, Convexity::PositiveConvex);
//! // Face tetrahedra [p_i p_j p_k u_ijk] and the edge tetrahedron [u_ijl p_i p_j u_ijk].
//! let u = hull.faces()[0].u().unwrap();
//! assert!(u.z > 0.0);
//! assert!(edge.positive.is_some() && edge.negative.is_none());
//! assert!(hull.intersections().is_empty());
//! # Ok::<(), algesurf_hull::HullError>(())
//! ```
//!
//! Conventions:
//! * The positive side is the side the vertex normals point to; triangles are oriented so their
//!   right-hand normal `n_ijk` points there (an error names any vertex whose normal has
//!   `n_ijkᵀ n_l ≤ 0`).
//! * Face tetrahedra are `[p_i, p_j, p_k, apex]` with the face's corners in mesh order and the
//!   apex **last** (the paper's `[p_k p_i p_j u_ijk]` is a cyclic rotation of the same).
//! * Edge tetrahedra are `[w_ijl, p_i, p_j, w_ijk]` as in (4.3), `[p_i p_j]` oriented as in
//!   the face `[p_i p_j p_k]`; the barycentric coordinates `μ`, `ν` of (4.15) come with them.
//! * Zero convex faces get no tetrahedra; zero convex and boundary edges get no edge
//!   tetrahedra. On an open mesh the hull (and the surface) ends at the boundary: a boundary
//!   edge is only the side of its face's tetrahedra.
#![forbid(unsafe_code)]
#![warn(missing_docs)]

mod apex;
mod classify;
mod crossing;
mod edge_point;
mod edit;
mod error;
mod hull;
mod overlap;
mod refine;
mod simplicial;

pub use classify::{
    ApexParameters, Convexity, Side, alpha, apex_parameters, classify_edge, classify_face,
    edge_slopes, mid_edge_coefficient,
};
pub use error::HullError;
pub use hull::{COORDINATE_EXPONENT_RANGE, EdgeTetrahedron, FaceTetrahedron, HullEdge, HullFace};
pub use overlap::{overlap_depth, tetrahedra_overlap};
pub use simplicial::{Element, HullTetrahedron, Intersection, Refinement, SimplicialHull};

/// The refined mesh may always have this many faces, whatever
/// [`HullOptions::max_refinement_growth`] allows for a small input: a hull of 4096 faces is
/// built and checked in a few milliseconds, so small meshes (a tetrahedron, the papers'
/// examples, a bicone) may refine as far as their sharp rims need before the growth bound
/// applies.
pub const REFINEMENT_FACE_FLOOR: usize = 4096;

/// Refinement may always leave this many overlapping pairs, whatever
/// [`HullOptions::max_overlap_growth`] allows for a mesh whose first round found few: a round
/// with a few thousand pairs bisects a few thousand faces and rebuilds their tetrahedra in
/// milliseconds, so a small mesh's sharp rims may take their rounds before the bound applies
/// (the successful refinements of the corpus and of the mesh crate's shapes never exceed
/// 3 484 pairs in a round).
pub const REFINEMENT_OVERLAP_FLOOR: usize = 4096;

/// Tolerances and parameters of the hull construction. All are relative (scale-invariant).
#[derive(Clone, Debug, PartialEq)]
pub struct HullOptions {
    /// Angle (radians) below which `a = (p_j − p_i)ᵀn_j` counts as zero in the edge
    /// classification: `|a| ≤ zero_tolerance · |p_j − p_i| · |n_j|`. Default `1e-9`.
    ///
    /// Why this scale: `a / (|p_j − p_i| |n_j|)` is the sine of the angle between the edge and
    /// the tangent plane at `p_j`, so the test is independent of the mesh's size. Computing it
    /// in f64 costs an error of about `1e-16 · |p| / |p_j − p_i|` (positions far from the
    /// origin relative to the edge), so `1e-9` leaves a margin of `10⁶` for that ratio and
    /// still classifies planar data whose normals were computed in floating point as zero
    /// convex. A curved surface sampled with edges of length `h` deviates by an angle of about
    /// `κh/2`, so only edges with `κh < 2·10⁻⁹` — flat for every practical purpose — are called
    /// zero convex.
    pub zero_tolerance: f64,
    /// `ε` of §3.1 as a fraction of the face's longest edge. Default `0.1`.
    ///
    /// `ε` is the margin by which the apex lies beyond each vertex's tangent plane: the Step 2
    /// coefficients `⅓ (u − p_l)ᵀn_l` are at least `⅓ ε n_ijkᵀn_l`. It must be a length, so it
    /// is taken relative to the face size (scale invariance). Larger values give better
    /// conditioned coefficients but taller tetrahedra, which collide with their neighbours
    /// more often; `0.1` keeps the apex height within about 10 % of what the tangent planes
    /// require (on a regular icosahedron with sphere normals `t_l ≈ 0.44 L`).
    pub epsilon: f64,
    /// The least `|t|` of an apex, as a fraction of the face's longest edge. Default `0.01`.
    /// The paper's `t_max = max{0, …}` can be 0 for a nonconvex face, which makes a flat
    /// tetrahedron; pushing the apex further out only increases the margins `t_max` is there
    /// for, so this floor is safe. For positive convex faces `t_max ≥ ε` anyway.
    pub min_apex_height: f64,
    /// Interiors overlapping by at most this fraction of the pair's size count as touching
    /// (see [`overlap_depth`]). Default `1e-9`: well above the rounding of shared faces
    /// (`~1e-15` for non-sliver tetrahedra) and far below any geometric overlap that matters.
    pub overlap_tolerance: f64,
    /// How many rounds of local Butterfly refinement (§3.1) to try before giving up with
    /// [`HullError::UnresolvedIntersection`]. A round bisects every face of every intersecting
    /// pair once (longest-edge bisection with Butterfly edge points, see
    /// [`SimplicialHull::new`]), so two rounds amount to about one local subdivision step and
    /// the default `24` to twelve: faces down to about 4⁻¹² of their area near the worst
    /// pair. Rounds cost in proportion to the faces they split, so the bound only matters
    /// where refinement converges slowly: at the sharp rims of Suzanne's ears and brow (17
    /// rounds with [`algesurf_mesh::NormalMethod::LoopButterfly`] normals) and the cow's
    /// horns (13). Intersections that survive it are caused by the normals at the input
    /// vertices (which refinement never changes; normals inconsistent with Butterfly
    /// refinement, such as Loop normals at sharp rims, make refinement diverge there) or by a
    /// mesh that undersamples its surface badly. `0` only detects.
    pub max_refinement_rounds: usize,
    /// The most faces refinement may make, per face of the input: once the refined mesh has
    /// more than `max_refinement_growth` times the input's faces (and more than
    /// [`REFINEMENT_FACE_FLOOR`]) while tetrahedra still overlap, refinement stops with
    /// [`HullError::UnresolvedIntersection`]. Default `64`; must be at least 1.
    ///
    /// Why a bound besides [`HullOptions::max_refinement_rounds`]: a round bisects every face
    /// of every overlapping pair, so where refinement diverges (normals that disagree with
    /// Butterfly refinement at a sharp rim) the pairs and faces multiply from round to round
    /// and the rounds alone bound nothing. A bicone of 48 faces
    /// ([`algesurf_mesh::shapes::bicone`]`(8, 0.05)`) with angle-weighted normals grew to
    /// 280 k faces and 1.6 M overlapping pairs in 16 rounds (×1.5 faces a round, 1.5 GB),
    /// on its way to millions of faces by the 24th; Suzanne with area-weighted normals grew
    /// from 968 to 383 k faces in 24 rounds (32 s) before failing. The refinements that
    /// succeed stay far below 64: Suzanne with the default normals grows 11.9× (to 11 490
    /// faces in 17 rounds), a bicone of 144 faces with Butterfly normals 13× (to 1 886), the
    /// cow 1.8×, the teapot 1.3×.
    pub max_refinement_growth: f64,
    /// The most overlapping pairs a refinement round may leave, per pair the first round
    /// found: once more than `max_overlap_growth` times as many pairs overlap as at the start
    /// (and more than [`REFINEMENT_OVERLAP_FLOOR`]), refinement stops with
    /// [`HullError::UnresolvedIntersection`]. Default `16`; must be at least 1.
    ///
    /// Why a bound besides [`HullOptions::max_refinement_growth`]: on a large input the face
    /// bound is far away (64 times 487 k faces) while diverging refinement multiplies the
    /// overlapping pairs, not the faces, from round to round. Meshes made mostly of thin
    /// faces do that: the bunny's own A-patch tessellation at `--resolution 2 --across 1`
    /// (487 k faces, a fifth of them thinner than 1 : 20) went from 561 overlapping pairs to
    /// 2.6 M in 15 rounds (×1.5–1.8 a round) while its faces grew only 2.2×, and failed after
    /// 61 s and 7.5 GB; with this bound it stops after five rounds. The refinements that
    /// succeed never approach it: at most 2.2 times their first round's pairs on the corpus
    /// (fandisk with the paper's apexes) under every normal and apex option, and at most 4.4
    /// times on the mesh crate's bicones and tori (`bicone(16, 0.2)` with Butterfly normals,
    /// 112 → 488 pairs, below the floor anyway), while the diverging refinements measured had
    /// 24 to 515 times their first count when the face bound stopped them.
    pub max_overlap_growth: f64,
    /// Whether to look for intersecting tetrahedra at all. Default `true`.
    pub check_intersections: bool,
    /// Where a face tetrahedron's apex goes. Default [`ApexPlacement::Nearest`].
    pub apex: ApexPlacement,
}

/// Where the apex `u_ijk` / `v_ijk` of a face tetrahedron goes (§3.1).
///
/// Both placements satisfy the conditions §3.1's `t_max` and `t_min` exist for — the apex
/// lies beyond each corner's tangent plane by the margin `ε` gives (the Step 2 coefficients
/// are positive) and makes the Step 4 coefficients nonnegative — and keep it at least
/// [`HullOptions::min_apex_height`] off the face.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ApexPlacement {
    /// The point nearest the face's centroid that satisfies them and stands at least
    /// `max(ε, min_apex_height)` times the face's longest edge off the face (a 3-variable
    /// quadratic program, solved exactly); for a nonconvex face, which has both apexes, the
    /// pair on one line through the centroid whose farther apex is nearest (so the three
    /// cubics of each side join C1 across the face). Never farther from the face's centroid
    /// than [`ApexPlacement::FaceNormal`]'s apex, and much nearer where a corner's normal
    /// makes an angle near 90° with the face: there the paper's apex stands several face
    /// widths high and crosses its neighbours' tetrahedra (the Stanford bunny starts with 361
    /// intersecting pairs, which refinement does not resolve, against 110, which four rounds
    /// do).
    ///
    /// The height floor `ε` (the paper's margin beyond the tangent planes, instead of the
    /// much smaller [`HullOptions::min_apex_height`]) is there because a leaning apex may
    /// otherwise sit just above the face: the edge tetrahedra's cubics are the face cubics'
    /// C1 continuations (4.15), whose blossom weights grow with the cube of the neighbouring
    /// apex's distance measured in this tetrahedron's size, so a flat face tetrahedron
    /// amplifies its coefficients into the edge tetrahedron. On the bunny a face tetrahedron
    /// 0.16 face widths high gave continuation weights near 20 and an edge patch whose rays
    /// the apex values could not make single-sheeted.
    #[default]
    Nearest,
    /// The paper's: on the face normal through the centroid, `c + t_max n_ijk` and
    /// `c + t_min n_ijk`.
    FaceNormal,
}

impl Default for HullOptions {
    fn default() -> Self {
        HullOptions {
            zero_tolerance: 1e-9,
            epsilon: 0.1,
            min_apex_height: 0.01,
            overlap_tolerance: 1e-9,
            max_refinement_rounds: 24,
            max_refinement_growth: 64.0,
            max_overlap_growth: 16.0,
            check_intersections: true,
            apex: ApexPlacement::Nearest,
        }
    }
}

impl HullOptions {
    /// Checks the ranges: tolerances finite and `≥ 0`, `epsilon` and `min_apex_height`
    /// finite and `> 0`, `max_refinement_growth` and `max_overlap_growth` at least 1.
    ///
    /// # Errors
    /// [`HullError::InvalidOption`] naming the option.
    pub fn validate(&self) -> Result<(), HullError> {
        let nonneg = [
            ("zero_tolerance", self.zero_tolerance),
            ("overlap_tolerance", self.overlap_tolerance),
        ];
        for (name, x) in nonneg {
            if !(x >= 0.0 && x.is_finite()) {
                return Err(HullError::InvalidOption(format!(
                    "{name} = {x} must be finite and ≥ 0"
                )));
            }
        }
        for (name, x) in [
            ("epsilon", self.epsilon),
            ("min_apex_height", self.min_apex_height),
        ] {
            if !(x > 0.0 && x.is_finite()) {
                return Err(HullError::InvalidOption(format!(
                    "{name} = {x} must be finite and > 0"
                )));
            }
        }
        for (name, growth) in [
            ("max_refinement_growth", self.max_refinement_growth),
            ("max_overlap_growth", self.max_overlap_growth),
        ] {
            // NaN fails too.
            if growth.is_nan() || growth < 1.0 {
                return Err(HullError::InvalidOption(format!(
                    "{name} = {growth} must be ≥ 1 (infinity: no bound)"
                )));
            }
        }
        Ok(())
    }
}
