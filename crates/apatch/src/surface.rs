//! The whole C1 function F over the simplicial hull of a mesh, and its free parameters.

use crate::sheet::certified_face_bound;
use crate::{ApatchError, EdgeCubic, EdgeNeighbour, FaceCubic, Quadric, SplitFace, VertexData};
use algesurf_hull::{Convexity, HullError, HullOptions, Side, SimplicialHull};
use algesurf_mesh::TriMesh;
use algesurf_mesh::parallel::collect_first_error_with_progress;
use algesurf_mesh::progress::{NoProgress, Progress};
use glam::DVec3;
use rayon::prelude::*;
use std::collections::HashMap;

mod edge_lift;
mod neighbourhood;
use edge_lift::edge_increments;
pub(crate) use edge_lift::edge_need;
use neighbourhood::neighbourhood;

/// How the free parameters `f_0003` (the value of F at each apex) are chosen.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum FreeParameterRule {
    /// The value at the apex of a quadric fitted to the face's neighbourhood (vertices and
    /// gradients): reproduces quadrics exactly (Theorem 4.2, Corollary 4.3). The default.
    #[default]
    Quadric,
    /// The value at the apex of the linear function fitted to the face's vertex data: the
    /// intent of Step 8 (the cubic approximates a linear function). Valid, but loses quadric
    /// precision.
    Linear,
}

/// Options of [`ApatchSurface::new`].
#[derive(Clone, Debug, PartialEq)]
pub struct SurfaceOptions {
    /// Rule for the free parameters.
    pub free_parameters: FreeParameterRule,
    /// Options of the simplicial hull.
    pub hull: HullOptions,
    /// Margin kept above each single-sheet lower bound, relative to the size of the face's
    /// layer-0/1 coefficients (`|∇F| · face size`). Default `1e-2`: Lemma 2.3 needs `b > b_min`
    /// strictly, and a margin of that size keeps the smallest root well separated from the
    /// double root that appears at `b = b_min`.
    pub sheet_margin: f64,
    /// Repair vertex normals the hull cannot use ([`algesurf_mesh::condition_normals`] with
    /// [`algesurf_mesh::DEFAULT_MIN_NORMAL_COSINE`]). Default `true`; the changed vertices are listed by
    /// [`ApatchSurface::adjusted_normals`].
    pub condition_normals: bool,
    /// What the lengths of the given normals mean. Default [`GradientMagnitudes::AsGiven`].
    pub gradient_magnitudes: GradientMagnitudes,
    /// Report every face's single-sheet bound ([`FreeParameter::bound`]) within
    /// [`crate::sheet::CERTIFIED_GAP`] of the true maximum. Default `false`: the certified
    /// search stops as soon as it proves the chosen value admissible with the margin, which
    /// gives the same F and the same values but, on such faces, a higher (still guaranteed)
    /// bound, so a smaller admissible range for [`ApatchSurface::set_free_parameter`]. Set it
    /// where values are to be moved close to their true bounds.
    pub tight_face_bounds: bool,
}

/// How the gradients of F at the vertices get their magnitudes (READING-NOTES: Theorem 4.2
/// reproduces a quadric only from its *gradients*; unit normals are gradients only on a
/// sphere).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum GradientMagnitudes {
    /// Recover them from the normals' directions: [`crate::gradient_scale::quadric_consistent_scales`]
    /// (local quadric fits made consistent along edges). Data on one quadric (ellipsoid,
    /// cylinder, paraboloid, …) then get its gradients up to one factor, so the default free
    /// parameters reproduce it from unit normals; elsewhere a smooth estimate.
    ///
    /// Not the default: the magnitudes enter the hull (the Step 4 heights `t_lm` of §3.1
    /// weigh the two end points' gradients), and on fandisk, whose creases the local fits
    /// straddle, the rescaled hull keeps tetrahedra intersecting through every refinement
    /// round, where the unit normals build.
    QuadricConsistent,
    /// Use the given vectors as they are (unit normals, or exact gradients of an implicit
    /// function): the paper's reading. The default.
    #[default]
    AsGiven,
}

impl SurfaceOptions {
    /// Checks the ranges: `sheet_margin` finite and `> 0` (Lemma 2.3 needs the apex values
    /// strictly beyond their bounds: at 0 the smallest root can be the double root of
    /// `b = b_min`, and a negative or NaN margin would let values below the bounds through),
    /// and the hull's ([`HullOptions::validate`]). [`ApatchSurface::new`] calls it first.
    ///
    /// ```
    /// use algesurf_apatch::SurfaceOptions;
    /// assert!(SurfaceOptions::default().validate().is_ok());
    /// let bad = SurfaceOptions { sheet_margin: -0.01, ..SurfaceOptions::default() };
    /// assert!(bad.validate().unwrap_err().to_string().contains("sheet_margin"));
    /// ```
    ///
    /// # Errors
    /// [`ApatchError::InvalidOption`] naming the option; [`ApatchError::Hull`] with
    /// [`algesurf_hull::HullError::InvalidOption`] for the hull's.
    pub fn validate(&self) -> Result<(), ApatchError> {
        let m = self.sheet_margin;
        if !(m > 0.0 && m.is_finite()) {
            return Err(ApatchError::InvalidOption(format!(
                "sheet_margin = {m} must be finite and > 0"
            )));
        }
        self.hull.validate()?;
        Ok(())
    }
}

impl Default for SurfaceOptions {
    fn default() -> Self {
        SurfaceOptions {
            free_parameters: FreeParameterRule::Quadric,
            hull: HullOptions::default(),
            sheet_margin: 1e-2,
            condition_normals: true,
            gradient_magnitudes: GradientMagnitudes::AsGiven,
            tight_face_bounds: false,
        }
    }
}

/// F on the tetrahedra of one mesh face.
#[derive(Clone, Debug)]
pub enum FaceFunction {
    /// A zero convex face: no tetrahedra, the surface is the face itself (plane recovery).
    Planar,
    /// A positive or negative convex face: one rational cubic (4.1)/(4.2).
    Convex {
        /// Which side the tetrahedron is on.
        side: Side,
        /// The cubic (boxed: it is large next to `Planar`).
        cubic: Box<FaceCubic>,
    },
    /// A nonconvex face: three cubics on each side (index 0 positive, 1 negative).
    Split(SplitFace),
}

impl FaceFunction {
    /// The [`EdgeNeighbour`] on `side` for the face edge `(pi, pj)`.
    pub fn edge_neighbour(
        &self,
        side: Side,
        pi: DVec3,
        pj: DVec3,
    ) -> Result<EdgeNeighbour, ApatchError> {
        let piece = self.edge_piece(side, pi, pj)?;
        Ok(EdgeNeighbour {
            tet: *piece.tet,
            poly: algesurf_bb::BbPoly::new(3, piece.coeffs().to_vec()).expect("20 coefficients"),
        })
    }
}

/// The error for an edge tetrahedron on `side` whose face has no tetrahedron there.
pub(crate) fn no_tetrahedron_on(side: Side) -> ApatchError {
    ApatchError::Inconsistent(format!(
        "an edge tetrahedron on the {} side borders a face with no tetrahedron there",
        side.name()
    ))
}

/// The free parameter of one face side, with its admissible range.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FreeParameter {
    /// Face index (of the hull's, possibly refined, mesh).
    pub face: usize,
    /// Side of the apex.
    pub side: Side,
    /// Current value of F at the apex.
    pub value: f64,
    /// Single-sheet bound: the value must stay above it on the positive side and below it on
    /// the negative side (Step 6).
    pub bound: f64,
    /// `|value − bound|` relative to the face's coefficient scale.
    pub relative_margin: f64,
    /// The face's coefficient scale `max |∇F| · longest edge` that margins are relative to.
    pub scale: f64,
}

/// The piecewise rational C1 function F of Xu–Huang–Bajaj 2001 on the hull of a mesh.
#[derive(Clone, Debug)]
pub struct ApatchSurface {
    pub(crate) hull: SimplicialHull,
    pub(crate) faces: Vec<FaceFunction>,
    /// Per hull edge: `[positive, negative]` edge cubics.
    pub(crate) edges: Vec<[Option<EdgeCubic>; 2]>,
    /// Sorted by face, then positive before negative.
    pub(crate) parameters: Vec<FreeParameter>,
    adjusted_normals: Vec<u32>,
    timings: ConstructionTimings,
}

/// Wall-clock time of the stages of [`ApatchSurface::new`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ConstructionTimings {
    /// Building the simplicial hull, refinement included (§3).
    pub hull: std::time::Duration,
    /// Building F and choosing the free parameters (§4).
    pub function: std::time::Duration,
}

/// The base (apex value 0) shooting coefficients `c − f·(0, 0, 1/3, 1)` of (4.14).
fn without_apex(c: [f64; 4], f: f64) -> [f64; 4] {
    [c[0], c[1], c[2] - f / 3.0, c[3] - f]
}

/// Scale of a face's coefficients: `max |∇F| · longest edge`.
fn coefficient_scale(p: [DVec3; 3], g: [DVec3; 3]) -> f64 {
    let edge = (0..3)
        .map(|a| p[a].distance(p[(a + 1) % 3]))
        .fold(0.0, f64::max);
    g.iter().map(|x| x.length()).fold(0.0, f64::max) * edge
}

impl ApatchSurface {
    /// Builds the hull of `mesh` with unit vertex `normals` (the gradients of F at the
    /// vertices) and the function F on it.
    ///
    /// Where an edge A-patch has a ray that no apex value makes single-sheeted (Step 6:
    /// raising the apex values lowers it, [`ApatchError::UnliftableEdgeRay`]), the hull's
    /// two faces at that edge are refined ([`SimplicialHull::refine_faces`]) and F is built
    /// again, at most [`MAX_UNLIFTABLE_EDGE_REFINEMENTS`] times.
    ///
    /// # A mesh far from the origin
    /// Everything is computed in the mesh's own coordinates, so a mesh of size `d` at
    /// distance `D ≫ d` from the origin works with coordinates rounded to `ε·D/d` of its size,
    /// and a split face's apexes and centroid stop being collinear to the ~1e-8 its C1
    /// constraints need: the corpus's cow and Suzanne moved by 1000, and a torus of radius 2
    /// moved by 10⁵, failed with [`ApatchError::Degenerate`] ("the split-face constraints are
    /// inconsistent"), and the C1 figures grew in proportion to `D` before that. Build such a
    /// mesh about an origin near it, moved to exactly, and move the results back, as
    /// `algesurf smooth` does:
    ///
    /// ```
    /// use algesurf_apatch::{ApatchSurface, SurfaceOptions};
    /// use algesurf_mesh::{NormalMethod, shapes, vertex_normals};
    /// use glam::DVec3;
    ///
    /// let mut mesh = shapes::torus(24, 12, 1.5, 0.6);
    /// for p in mesh.positions_mut() {
    ///     *p += DVec3::new(1e5, -1e5, 1e5); // where the mesh is in the user's file
    /// }
    /// // An origin near the mesh that the positions move to and back from without rounding.
    /// let origin = mesh.bounding_box().exact_local_origin();
    /// for p in mesh.positions_mut() {
    ///     *p -= origin;
    /// }
    /// let normals = vertex_normals(&mesh, NormalMethod::Loop)?;
    /// let surface = ApatchSurface::new(&mesh, &normals, &SurfaceOptions::default())?;
    /// let mut tess = surface.tessellate(3, 2)?;
    /// for p in &mut tess.positions {
    ///     *p += origin; // back in the user's coordinates
    /// }
    /// assert!(tess.positions.iter().all(|p| (p.x - 1e5).abs() < 3.0));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    ///
    /// # Extreme coordinates
    /// Every tolerance is relative to the mesh's size, so scaling the mesh by a power of two
    /// scales the surface and its tessellation by the same factor, bit for bit (tested). What
    /// does not scale is the range of `f64`: areas and normals are products of up to four
    /// lengths, so a mesh whose largest coordinate is beyond `2^±252` is refused
    /// ([`algesurf_hull::HullError::CoordinatesOutOfRange`]). Scale such a mesh by a power of
    /// two first (`2^-e` with `e` the exponent of its largest coordinate) and the tessellation
    /// back by `2^e`; both steps are exact, and `algesurf smooth` does so for coordinates
    /// beyond `2^±64`.
    ///
    /// # Errors
    /// [`ApatchError::InvalidOption`] (or the hull's, in [`ApatchError::Hull`]) for an option
    /// out of range ([`SurfaceOptions::validate`]);
    /// [`ApatchError::Hull`] when the hull cannot be built; [`ApatchError::UnliftableEdgeRay`]
    /// when an edge A-patch is still unliftable after the refinements; the other variants of
    /// [`ApatchError`] for degenerate configurations, each naming the face or edge.
    pub fn new(
        mesh: &TriMesh,
        normals: &[DVec3],
        options: &SurfaceOptions,
    ) -> Result<Self, ApatchError> {
        Self::with_progress(mesh, normals, options, &NoProgress)
    }

    /// [`ApatchSurface::new`], reporting its steps to `progress`: the hull's
    /// ([`SimplicialHull::from_mesh_with_progress`]), then the face functions and the edge
    /// cubics (each counted per face or edge of the hull), the edges' single-sheet bounds
    /// (per edge), and any refinement at edges whose A-patch cannot be made single-sheeted.
    /// The surface is the same, bit for bit, with any `progress`; when `progress` asks to
    /// stop ([`Progress::cancelled`], polled per batch of faces or edges and between steps),
    /// the build returns [`ApatchError::Cancelled`] soon after.
    ///
    /// ```
    /// use algesurf_apatch::{ApatchSurface, SurfaceOptions};
    /// use algesurf_mesh::progress::{Progress, ProgressCounter};
    /// use algesurf_mesh::{NormalMethod, shapes, vertex_normals};
    ///
    /// let mesh = shapes::icosphere(2);
    /// let normals = vertex_normals(&mesh, NormalMethod::Loop)?;
    /// // A user interface polls the counter from its own thread while this runs.
    /// let counter = ProgressCounter::new();
    /// let surface =
    ///     ApatchSurface::with_progress(&mesh, &normals, &SurfaceOptions::default(), &counter)?;
    /// let last = counter.snapshot();
    /// assert_eq!(last.step, "surface: edge single-sheet bounds");
    /// assert_eq!((last.done, last.total), (surface.edges().len() as u64, surface.edges().len() as u64));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    ///
    /// # Errors
    /// As [`ApatchSurface::new`]; [`ApatchError::Cancelled`] when `progress` asked to stop.
    pub fn with_progress(
        mesh: &TriMesh,
        normals: &[DVec3],
        options: &SurfaceOptions,
        progress: &dyn Progress,
    ) -> Result<Self, ApatchError> {
        options.validate()?;
        let (normals, adjusted_normals) = if options.condition_normals {
            algesurf_mesh::condition_normals(
                mesh,
                normals,
                algesurf_mesh::DEFAULT_MIN_NORMAL_COSINE,
            )
        } else {
            (normals.to_vec(), Vec::new())
        };
        let normals = match options.gradient_magnitudes {
            GradientMagnitudes::AsGiven => normals,
            GradientMagnitudes::QuadricConsistent => {
                let scales = crate::gradient_scale::quadric_consistent_scales(mesh, &normals)?;
                normals
                    .iter()
                    .zip(&scales)
                    .map(|(n, s)| n.normalize() * *s)
                    .collect()
            }
        };
        let start = std::time::Instant::now();
        // A cancelled hull is this crate's `Cancelled`, as everywhere else in the build.
        let cancelled = |e: HullError| match e {
            HullError::Cancelled => ApatchError::Cancelled,
            e => ApatchError::Hull(e),
        };
        let mut hull =
            SimplicialHull::from_mesh_with_progress(mesh, &normals, &options.hull, progress)
                .map_err(cancelled)?;
        let mut hull_time = start.elapsed();
        // An edge A-patch that no apex value makes single-sheeted is a local defect of the
        // hull there (a thin, skewed edge tetrahedron whose C1 continuation weights turn
        // negative): refine its two faces, as overlapping tetrahedra are refined, and build
        // again.
        let mut refined_edges = 0;
        let (faces, edges, parameters) = loop {
            match build_function(&hull, options, progress) {
                Ok(parts) => break parts,
                Err(BuildFailure::Unliftable { edges, .. })
                    if refined_edges < MAX_UNLIFTABLE_EDGE_REFINEMENTS =>
                {
                    let t = hull.mesh().topology();
                    let mut faces: Vec<u32> = edges
                        .iter()
                        .filter_map(|&[a, b]| t.find_edge(a, b))
                        .flat_map(|e| t.edge_faces(e))
                        .collect();
                    faces.sort_unstable();
                    faces.dedup();
                    let again = std::time::Instant::now();
                    progress.start(
                        &format!(
                            "surface: refining {} faces at {} edges no apex value makes \
                             single-sheeted",
                            faces.len(),
                            edges.len()
                        ),
                        0,
                    );
                    hull = hull
                        .refine_faces_with_progress(&faces, progress)
                        .map_err(cancelled)?;
                    hull_time += again.elapsed();
                    refined_edges += 1;
                }
                Err(BuildFailure::Unliftable { first, .. } | BuildFailure::Other(first)) => {
                    return Err(first);
                }
            }
        };
        let timings = ConstructionTimings {
            hull: hull_time,
            function: start.elapsed().saturating_sub(hull_time),
        };
        Ok(ApatchSurface {
            hull,
            faces,
            edges,
            parameters,
            adjusted_normals,
            timings,
        })
    }

    /// How long the stages of construction took.
    pub fn timings(&self) -> ConstructionTimings {
        self.timings
    }

    /// Vertices whose normals were changed so the hull could use them (see
    /// [`SurfaceOptions::condition_normals`]), in the hull mesh's numbering.
    pub fn adjusted_normals(&self) -> &[u32] {
        &self.adjusted_normals
    }

    /// The simplicial hull (with the possibly refined mesh F interpolates).
    pub fn hull(&self) -> &SimplicialHull {
        &self.hull
    }

    /// F on the tetrahedra of each face of the hull's mesh.
    pub fn faces(&self) -> &[FaceFunction] {
        &self.faces
    }

    /// `[positive, negative]` edge cubics of each hull edge.
    pub fn edges(&self) -> &[[Option<EdgeCubic>; 2]] {
        &self.edges
    }

    /// Every free parameter with its single-sheet bound.
    pub fn free_parameters(&self) -> &[FreeParameter] {
        &self.parameters
    }
}

fn build_face(
    hull: &SimplicialHull,
    f: usize,
    grads: &[DVec3],
    pos: &[DVec3],
    options: &SurfaceOptions,
) -> Result<(FaceFunction, Vec<FreeParameter>), ApatchError> {
    let m = hull.mesh();
    let hf = &hull.faces()[f];
    let tri = m.triangles()[f];
    let p = tri.map(|v| pos[v as usize]);
    let g = tri.map(|v| grads[v as usize]);
    let v = [0, 1, 2].map(|a| VertexData {
        position: p[a],
        gradient: g[a],
    });
    let mids = [0, 1, 2].map(|a| (g[(a + 1) % 3] + g[(a + 2) % 3]) * 0.5);
    let scale = coefficient_scale(p, g).max(f64::MIN_POSITIVE);
    let margin = options.sheet_margin * scale;
    // A zero-convex face is its own patch (the plane through it) and takes no free
    // parameter, so no fit: its neighbourhood is coplanar in a flat region, which sent every
    // fit there to the SVD (a flat 300 × 300 grid spent 1.4 s of its 1.5 s function stage in
    // fits whose result was not used).
    if hf.convexity == Convexity::ZeroConvex {
        return Ok((FaceFunction::Planar, Vec::new()));
    }
    let quadric = match options.free_parameters {
        FreeParameterRule::Quadric => Quadric::fit(&neighbourhood(m, grads, f))?,
        FreeParameterRule::Linear => {
            let n = (g[0] + g[1] + g[2]) / 3.0;
            let c = (p[0] + p[1] + p[2]) / 3.0;
            Quadric {
                a: glam::DMat3::ZERO,
                b: n,
                c: -n.dot(c),
            }
        }
    };
    // The level at which the certified face bound may stop (see `tight_face_bounds`).
    let early_stop = |enough: f64| {
        if options.tight_face_bounds {
            f64::NEG_INFINITY
        } else {
            enough
        }
    };
    let param = |side: Side, value: f64, bound: f64| FreeParameter {
        face: f,
        side,
        value,
        bound,
        relative_margin: (value - bound).abs() / scale,
        scale,
    };
    match hf.convexity {
        // Returned above, before the fit.
        Convexity::ZeroConvex => Ok((FaceFunction::Planar, Vec::new())),
        Convexity::PositiveConvex | Convexity::NegativeConvex => {
            let side = if hf.convexity == Convexity::PositiveConvex {
                Side::Positive
            } else {
                Side::Negative
            };
            let apex = hf
                .tetrahedron(side)
                .expect("convex faces carry their tetrahedron")
                .apex;
            let sign = if side == Side::Positive { 1.0 } else { -1.0 };
            let mut cubic = FaceCubic::new(v, apex, mids, quadric.value(apex))?;
            let f0 = cubic.f0003();
            let enough = early_stop(sign * f0 - margin);
            // Bound for sign·F: base coefficients of the ray polynomial of sign·F.
            // Certified over the whole face (not a grid): see `certified_face_bound`.
            let b = certified_face_bound(
                cubic.polynomial(),
                f0,
                sign,
                Some(cubic.rational()),
                scale,
                // A bound at most this keeps f0 (below): stop there (same value either way).
                enough,
                |q| without_apex(cubic.shooting_polynomial(q), f0).map(|x| sign * x),
            );
            // `b ≤ enough` keeps f0 exactly (tested first so that the rounding of
            // `enough + margin` cannot move it).
            let value = if b.is_finite() && b > enough {
                (sign * f0).max(b + margin) * sign
            } else {
                f0
            };
            cubic.set_f0003(value);
            Ok((
                FaceFunction::Convex {
                    side,
                    cubic: Box::new(cubic),
                },
                vec![param(side, value, sign * b)],
            ))
        }
        Convexity::Nonconvex => {
            let apexes = [hf.u().expect("nonconvex: u"), hf.v().expect("nonconvex: v")];
            let mut values = apexes.map(|a| quadric.value(a));
            let mut split = SplitFace::new(v, &apexes, mids, &quadric, &values)?;
            if split.constraint_residual > 1e-8 {
                return Err(ApatchError::Degenerate(format!(
                    "the split-face constraints are inconsistent (residual {:e})",
                    split.constraint_residual
                )));
            }
            let mut bounds = [f64::NEG_INFINITY; 2];
            for (s, sign) in [(0usize, 1.0), (1usize, -1.0)] {
                let side = &split.sides[s];
                let mut worst = f64::NEG_INFINITY;
                // A bound at most `enough` on all three sub-triangles keeps the value.
                let enough = early_stop(sign * values[s] - margin);
                // Rays from each sub-triangle [p_b p_c c] to this side's apex.
                for a in 0..3 {
                    let poly = crate::cubic::coeffs_of(&side.polys[a]);
                    let bound = certified_face_bound(
                        &side.polys[a],
                        values[s],
                        sign,
                        None,
                        scale,
                        enough,
                        |q| {
                            let c = crate::cubic::segment(
                                &poly,
                                [q[0], q[1], q[2], 0.0],
                                [0.0, 0.0, 0.0, 1.0],
                            );
                            without_apex(c, values[s]).map(|x| sign * x)
                        },
                    );
                    worst = worst.max(bound);
                }
                bounds[s] = worst;
                if worst.is_finite() && worst > enough && sign * values[s] < worst + margin {
                    // Raise the apex value (no second solve: `SplitSide::raise_apex`).
                    let delta = worst + margin - sign * values[s];
                    values[s] += sign * delta;
                    split.sides[s].raise_apex(sign * delta);
                }
            }
            let params = vec![
                param(Side::Positive, values[0], bounds[0]),
                param(Side::Negative, values[1], -bounds[1]),
            ];
            Ok((FaceFunction::Split(split), params))
        }
    }
}

fn build_edges(
    hull: &SimplicialHull,
    faces: &[FaceFunction],
    progress: &dyn Progress,
) -> Result<Vec<[Option<EdgeCubic>; 2]>, ApatchError> {
    // The first error in edge order, whatever the thread count.
    progress.start("surface: edge cubics", hull.edges().len() as u64);
    collect_first_error_with_progress(
        hull.edges().len(),
        |i| -> Result<[Option<EdgeCubic>; 2], ApatchError> {
            let e = &hull.edges()[i];
            if e.face_l.is_none() {
                return Ok([None, None]);
            }
            let cubic = |present: bool, side| {
                present
                    .then(|| edge_cubic(hull, faces, i, side).map_err(|err| err.at_edge(hull, i)))
                    .transpose()
            };
            Ok([
                cubic(e.positive.is_some(), Side::Positive)?,
                cubic(e.negative.is_some(), Side::Negative)?,
            ])
        },
        || [None, None],
        progress,
    )
}

/// The edge cubic on `side` of hull edge `e`, from the pieces of its two faces on that side
/// (Steps 7 and 9, [`EdgeCubic::between`]).
///
/// # Errors
/// [`ApatchError::Inconsistent`] for a boundary edge, an edge without a tetrahedron on `side`
/// or a face with no piece on `side`.
pub(crate) fn edge_cubic(
    hull: &SimplicialHull,
    faces: &[FaceFunction],
    e: usize,
    side: Side,
) -> Result<EdgeCubic, ApatchError> {
    let he = &hull.edges()[e];
    let fl = he
        .face_l
        .ok_or_else(|| ApatchError::Inconsistent(format!("edge {e} is a boundary edge")))?;
    let tet = he.tetrahedron(side).ok_or_else(|| {
        ApatchError::Inconsistent(format!("edge {e} has no {} tetrahedron", side.name()))
    })?;
    EdgeCubic::between(
        &faces[he.face_k as usize],
        &faces[fl as usize],
        side,
        &tet.tetrahedron,
    )
}

/// [`build_edges`] after the face sides in `raise` changed: only the edge cubics on a raised
/// side of one of their two faces are rebuilt. The others are kept; rebuilding them would give
/// the same bits (an edge cubic is a deterministic function of its two faces' pieces on its
/// side, and those did not change).
fn rebuild_raised_edges(
    hull: &SimplicialHull,
    faces: &[FaceFunction],
    mut edges: Vec<[Option<EdgeCubic>; 2]>,
    raise: &HashMap<(usize, Side), f64>,
) -> Result<Vec<[Option<EdgeCubic>; 2]>, ApatchError> {
    edges
        .par_iter_mut()
        .enumerate()
        .map(|(i, slots)| -> Result<(), ApatchError> {
            let e = &hull.edges()[i];
            let Some(fl) = e.face_l else {
                return Ok(());
            };
            for (slot, side) in [(0usize, Side::Positive), (1usize, Side::Negative)] {
                let raised = raise.contains_key(&(e.face_k as usize, side))
                    || raise.contains_key(&(fl as usize, side));
                if raised && slots[slot].is_some() {
                    slots[slot] =
                        Some(edge_cubic(hull, faces, i, side).map_err(|err| err.at_edge(hull, i))?);
                }
            }
            Ok(())
        })
        .collect::<Vec<_>>()
        .into_iter()
        .collect::<Result<(), _>>()?;
    Ok(edges)
}

/// How many times [`ApatchSurface::new`] refines the two faces of an edge whose A-patch has a
/// ray no apex value makes single-sheeted ([`ApatchError::UnliftableEdgeRay`]) before it
/// reports the error: 8. Each refinement rebuilds F, so the bound keeps a mesh with many
/// such edges from rebuilding without end; the corpus needs at most one (the cow).
pub const MAX_UNLIFTABLE_EDGE_REFINEMENTS: usize = 8;

/// F on a hull: the face functions, the edge cubics (positive, negative) and the free
/// parameters.
type FunctionParts = (
    Vec<FaceFunction>,
    Vec<[Option<EdgeCubic>; 2]>,
    Vec<FreeParameter>,
);

/// Why [`build_function`] failed.
enum BuildFailure {
    /// Edge A-patches with a ray no apex value makes single-sheeted: the first error in edge
    /// order, and the vertices of every such edge.
    Unliftable {
        first: ApatchError,
        edges: Vec<[u32; 2]>,
    },
    /// Anything else.
    Other(ApatchError),
}

impl From<ApatchError> for BuildFailure {
    fn from(e: ApatchError) -> Self {
        BuildFailure::Other(e)
    }
}

/// The face functions, edge cubics and free parameters of F on `hull` (§4.2, Steps 1–10).
fn build_function(
    hull: &SimplicialHull,
    options: &SurfaceOptions,
    progress: &dyn Progress,
) -> Result<FunctionParts, BuildFailure> {
    let m = hull.mesh();
    let grads = hull.normals();
    let pos = m.positions();
    // The first error in face order, whatever the thread count.
    progress.start("surface: face functions", m.face_count() as u64);
    let built = collect_first_error_with_progress(
        m.face_count(),
        |f| build_face(hull, f, grads, pos, options).map_err(|e| e.at_face(hull, f)),
        || (FaceFunction::Planar, Vec::new()),
        progress,
    )?;
    let (mut faces, parameters): (Vec<FaceFunction>, Vec<Vec<FreeParameter>>) =
        built.into_par_iter().unzip();
    let mut parameters: Vec<FreeParameter> = parameters.into_iter().flatten().collect();
    debug_assert!(parameters.is_sorted_by_key(|p| p.face));
    let edges = build_edges(hull, &faces, progress)?;
    // Step 6, second part: the edge A-patches need their own lower bound B_ijkl on a common
    // increment of the two faces' apex values; raise each face side by the largest
    // increment its edges need (raising only helps every other ray, Lemma 2.3).
    let raise = edge_increments(hull, &faces, &edges, options, progress)?;
    for (&(f, side), &delta) in &raise {
        let sign = if side == Side::Positive { 1.0 } else { -1.0 };
        match &mut faces[f] {
            FaceFunction::Convex { cubic, .. } => cubic.set_f0003(cubic.f0003() + sign * delta),
            FaceFunction::Split(split) => {
                let s = if side == Side::Positive { 0 } else { 1 };
                split.sides[s].raise_apex(sign * delta);
            }
            FaceFunction::Planar => {}
        }
        // The face's parameters by binary search: they are in face order (collected face
        // after face). A scan of all of them per raised side was 20–30 ms of one thread on
        // the bunny (124 k parameters), the whole function stage waiting on it.
        let first = parameters.partition_point(|p| p.face < f);
        let count = parameters[first..].partition_point(|p| p.face == f);
        for p in parameters[first..first + count]
            .iter_mut()
            .filter(|p| p.side == side)
        {
            p.value += sign * delta;
            p.relative_margin = (p.value - p.bound).abs() / p.scale;
        }
    }
    // The edge cubics depend on the raised faces: rebuild those next to a raised side.
    let edges = if raise.is_empty() {
        edges
    } else {
        rebuild_raised_edges(hull, &faces, edges, &raise)?
    };
    Ok((faces, edges, parameters))
}
