//! The check battery: every property Theorem 4.1 of Xu–Huang–Bajaj 2001 claims for a C1
//! patch surface, measured, with the worst value, where it happened and a pass/fail verdict.
//!
//! The battery is generic over [`PatchSurface`]: a surface made of polynomial (or rational)
//! pieces on tetrahedra, grouped into patches, with interpolation targets, a tessellation and
//! free parameters. [`ApatchView`] implements it for the cubic A-patches of
//! [`algesurf_apatch::ApatchSurface`]; later surfaces (quintic A-patches, shells, splines)
//! implement the same trait and get the same report.
//!
//! ```
//! use algesurf_apatch::{ApatchSurface, SurfaceOptions};
//! use algesurf_inspect::check::{ApatchView, CheckOptions, check};
//! use algesurf_mesh::shapes::icosphere;
//!
//! // The icosahedron with radial normals: F is the unit sphere's quadric, exactly.
//! let mesh = icosphere(0);
//! let normals: Vec<_> = mesh.positions().iter().map(|p| p.normalize()).collect();
//! let surface = ApatchSurface::new(&mesh, &normals, &SurfaceOptions::default())?;
//! let report = check(&ApatchView::new(&surface), &CheckOptions::default())?;
//! assert!(report.passed(), "{report}");
//! println!("{report}"); // property, worst value, where, threshold, pass
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! # Thresholds
//!
//! Every tolerance is relative, so the verdict does not depend on the mesh's scale:
//!
//! | property | measured | threshold |
//! |---|---|---|
//! | interpolation | `\|F(p_i)\| / (\|∇F(p_i)\| · bbox diagonal)` over every piece containing `p_i` | ≤ 1e-12 |
//! | vertex normals | angle between `∇F(p_i)` and `n_i` | ≤ 1e-9 rad |
//! | C1 value | `\|F₁ − F₂\| / (\|∇F\| · facet diameter)` at ≥ 16 points of each interior facet | ≤ 1e-10 |
//! | C1 gradient | `\|∇F₁ − ∇F₂\| / max(\|∇F₁\|, \|∇F₂\|)` (≈ the angle) at the same points | ≤ 1e-8 rad |
//! | normal agreement | angle between the `∇F` of the pieces meeting at each patch-boundary vertex of the tessellation | ≤ 1e-8 rad |
//! | missed rays / multiple roots | rays whose shooting polynomial has no root in `[0, 1)` / whose root is not simple | 0 |
//! | watertight | tessellation edges not shared by exactly two oppositely oriented triangles (closed input), or by more than two (open input) | 0 |
//! | finite positions | tessellation vertices with a NaN or infinite coordinate | 0 |
//! | duplicate positions | tessellation vertices at the position of an earlier one of their connected component (coincident input vertices excepted) | 0 |
//! | Euler characteristic | `\|χ(output) − χ(input after repair)\|` | 0 |
//! | parameter margin | least `(value − bound) / scale` of the free parameters beyond their single-sheet bound (Lemma 2.3, Step 6) | > 0 |
//!
//! They are the thresholds the smooth issue set. Values sit about 10⁴ ulps above the rounding
//! of one evaluation of a cubic in Bernstein form (coefficients of size `|∇F| · edge`);
//! gradients and angles get more room (10⁻⁸, 10⁻⁹) because the rational blends of (4.1)/(4.7)
//! lose digits near the mesh edges where they are 0/0. A real defect — one coefficient off by
//! a millionth of its size — fails them by orders of magnitude (see the perturbation tests).

mod apatch;
mod measure;
mod report;
mod topology;

pub use apatch::ApatchView;
pub use measure::{
    ContinuityMeasure, FacetMeasure, InterpolationMeasure, NormalAgreement, Worst, continuity,
    interpolation, normal_agreement,
};
pub use report::{CheckReport, CheckRow, Comparison};
pub use topology::{TopologyMeasure, topology};

use crate::InspectError;
use algesurf_hull::Side;
use algesurf_mesh::progress::{NoProgress, Progress, check_cancelled};
use glam::DVec3;
use std::fmt;

/// `|F(p_i)| / (|∇F(p_i)| · bbox diagonal)` at most this: interpolation of the vertices.
pub const INTERPOLATION_VALUE: f64 = 1e-12;
/// Angle (radians) between `∇F(p_i)` and `n_i` at most this.
pub const INTERPOLATION_NORMAL: f64 = 1e-9;
/// `|F₁ − F₂| / (|∇F| · facet diameter)` at most this across every interior facet.
pub const C1_VALUE: f64 = 1e-10;
/// `|∇F₁ − ∇F₂| / max |∇F|` (the gradient angle, radians) at most this across every interior
/// facet.
pub const C1_GRADIENT: f64 = 1e-8;
/// Angle (radians) between the normals of the pieces meeting at a patch boundary at most this.
pub const NORMAL_AGREEMENT: f64 = 1e-8;
/// Least number of sample points per interior facet.
pub const MIN_FACET_SAMPLES: usize = 16;

/// A mesh element named as the papers name it: `vertex 5`, `face 12 (+)`, `edge 40 (−)`,
/// `face 5 (−) sub-tetrahedron 2`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Element {
    /// A vertex of the (hull's) mesh.
    Vertex(usize),
    /// A face of the mesh, with the side of its tetrahedra when the piece has one.
    Face(usize, Option<Side>),
    /// An edge of the mesh, with the side of its tetrahedron when the piece has one.
    Edge(usize, Option<Side>),
    /// Sub-tetrahedron `a` (opposite the face's vertex `a`, on the Clough–Tocher split at the
    /// centroid) of one side of a nonconvex face (§4.2, (4.6)).
    SplitFace(usize, Side, usize),
}

fn side_mark(side: Option<Side>) -> &'static str {
    match side {
        Some(Side::Positive) => " (+)",
        Some(Side::Negative) => " (−)",
        None => "",
    }
}

impl fmt::Display for Element {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Element::Vertex(v) => write!(f, "vertex {v}"),
            Element::Face(i, s) => write!(f, "face {i}{}", side_mark(s)),
            Element::Edge(i, s) => write!(f, "edge {i}{}", side_mark(s)),
            Element::SplitFace(i, s, a) => {
                write!(f, "face {i}{} sub-tetrahedron {a}", side_mark(Some(s)))
            }
        }
    }
}

/// Where a measured value happened.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Location {
    /// A mesh element (a vertex, the piece of a face or edge, a patch, a free parameter).
    Element(Element),
    /// The facet shared by the tetrahedra of two pieces.
    Facet(Element, Element),
    /// A vertex of the tessellation on the boundary between two patches.
    Boundary {
        /// Tessellation vertex.
        vertex: usize,
        /// The patches whose normals were compared.
        patches: (Element, Element),
    },
    /// A vertex of the tessellation.
    TessellationVertex(usize),
    /// An edge of the tessellation (its two vertices).
    TessellationEdge(u32, u32),
    /// Euler characteristics of input and output.
    Euler {
        /// χ of the input after repair (of the hull's mesh).
        input: i64,
        /// χ of the tessellation.
        output: i64,
    },
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Location::Element(e) => write!(f, "{e}"),
            Location::Facet(a, b) => write!(f, "facet between {a} and {b}"),
            Location::Boundary { vertex, patches } => write!(
                f,
                "tessellation vertex {vertex} between {} and {}",
                patches.0, patches.1
            ),
            Location::TessellationVertex(v) => write!(f, "tessellation vertex {v}"),
            Location::TessellationEdge(a, b) => write!(f, "tessellation edge ({a}, {b})"),
            Location::Euler { input, output } => write!(f, "χ input {input}, output {output}"),
        }
    }
}

/// A triangulation of the surface with the diagnostics of its rays.
#[derive(Clone, Debug, Default)]
pub struct Tessellated {
    /// Vertex positions; the first [`Tessellated::interpolated_vertices`] are the mesh's
    /// vertices in its order.
    pub positions: Vec<DVec3>,
    /// Triangles, oriented like the input.
    pub triangles: Vec<[u32; 3]>,
    /// Patch id of each triangle (see [`PatchSurface::patch_element`]).
    pub triangle_patch: Vec<u32>,
    /// Rays whose shooting polynomial had no root: `(patch, ray start)`.
    pub missed_rays: Vec<(u32, DVec3)>,
    /// Rays whose chosen root is not certified simple: `(patch, point)`.
    pub multiple_roots: Vec<(u32, DVec3)>,
    /// How many leading vertices are the interpolated mesh vertices. The normal agreement
    /// skips them: there the rational terms of (4.1)/(4.7) are 0/0 and the normal is the one
    /// the interpolation rows measure.
    pub interpolated_vertices: usize,
}

/// Topology of the input the surface interpolates (after repair and refinement).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct InputTopology {
    /// No boundary edges.
    pub closed: bool,
    /// `V − E + F`.
    pub euler_characteristic: i64,
}

/// A surface made of pieces (functions on tetrahedra) that the check battery measures.
///
/// Pieces are numbered `0..piece_count()`; patches are the ids of [`Tessellated`]. Pieces whose
/// tetrahedra share a facet (the same three vertices, bit for bit) are compared across it.
///
/// A minimal implementation — one piece, the plane `F = z` on one tetrahedron, interpolating
/// the three vertices of its base with normal `+z`, tessellated as that triangle:
///
/// ```
/// use algesurf_inspect::InspectError;
/// use algesurf_inspect::check::{
///     CheckOptions, Element, InputTopology, PatchSurface, Tessellated, check,
/// };
/// use glam::DVec3;
///
/// struct Plane {
///     base: [DVec3; 3],
///     normals: [DVec3; 3],
/// }
///
/// impl PatchSurface for Plane {
///     fn piece_count(&self) -> usize { 1 }
///     fn piece_element(&self, _: usize) -> Element { Element::Face(0, None) }
///     fn piece_simplex(&self, _: usize) -> [DVec3; 4] {
///         [self.base[0], self.base[1], self.base[2], DVec3::new(0.3, 0.3, 1.0)]
///     }
///     fn value_gradient(&self, _: usize, x: DVec3) -> (f64, DVec3) { (x.z, DVec3::Z) }
///     fn interpolation_targets(&self) -> (&[DVec3], &[DVec3]) { (&self.base, &self.normals) }
///     fn tessellate(&self, _: usize) -> Result<Tessellated, InspectError> {
///         Ok(Tessellated {
///             positions: self.base.to_vec(),
///             triangles: vec![[0, 1, 2]],
///             triangle_patch: vec![0],
///             interpolated_vertices: 3,
///             ..Tessellated::default()
///         })
///     }
///     fn patch_element(&self, _: u32) -> Element { Element::Face(0, None) }
///     fn patch_pieces(&self, _: u32) -> Vec<usize> { vec![0] }
///     fn parameter_margins(&self) -> Vec<(Element, f64)> { Vec::new() }
///     fn input_topology(&self) -> InputTopology {
///         InputTopology { closed: false, euler_characteristic: 1 }
///     }
/// }
///
/// let plane = Plane { base: [DVec3::ZERO, DVec3::X, DVec3::Y], normals: [DVec3::Z; 3] };
/// let report = check(&plane, &CheckOptions::default())?;
/// assert!(report.passed(), "{report}");
/// assert_eq!(report.row("interpolation").unwrap().samples, 3);
/// # Ok::<(), InspectError>(())
/// ```
pub trait PatchSurface: Sync {
    /// Number of pieces.
    fn piece_count(&self) -> usize;
    /// The mesh element piece `piece` belongs to (`face 3 (+)`, `edge 7 (−)`).
    fn piece_element(&self, piece: usize) -> Element;
    /// The vertices of the piece's tetrahedron.
    fn piece_simplex(&self, piece: usize) -> [DVec3; 4];
    /// F and ∇F of the piece at `x` (inside or on its tetrahedron).
    fn value_gradient(&self, piece: usize, x: DVec3) -> (f64, DVec3);
    /// F and ∇F of the piece at the point with barycentric coordinates `tau` (with respect to
    /// [`PatchSurface::piece_simplex`]). The measurements of continuity and interpolation
    /// give points on facets and at vertices this way, with exact zeros: a Cartesian point is
    /// rounded off a facet by ~ε·|x|, and on a thin tetrahedron (height ≪ |x|) F's second
    /// derivatives turn that offset into a change of ∇F that is no property of F on the facet.
    /// The default evaluates at the Cartesian point; implement it where the pieces can be
    /// evaluated in their own barycentric coordinates.
    fn value_gradient_barycentric(&self, piece: usize, tau: [f64; 4]) -> (f64, DVec3) {
        let v = self.piece_simplex(piece);
        self.value_gradient(
            piece,
            v[0] * tau[0] + v[1] * tau[1] + v[2] * tau[2] + v[3] * tau[3],
        )
    }
    /// The points F interpolates (`F(p_i) = 0`) and the normals there (`∇F(p_i) ∥ n_i`).
    fn interpolation_targets(&self) -> (&[DVec3], &[DVec3]);
    /// A tessellation at `resolution` (points per patch edge minus one).
    ///
    /// # Errors
    /// When the surface cannot be tessellated.
    fn tessellate(&self, resolution: usize) -> Result<Tessellated, InspectError>;
    /// The element a patch id of the tessellation stands for.
    fn patch_element(&self, patch: u32) -> Element;
    /// The pieces that make up a patch.
    fn patch_pieces(&self, patch: u32) -> Vec<usize>;
    /// Every free parameter's signed margin beyond its single-sheet bound (positive when
    /// valid), relative to its coefficient scale, with the element it belongs to.
    fn parameter_margins(&self) -> Vec<(Element, f64)>;
    /// The input's closedness and Euler characteristic.
    fn input_topology(&self) -> InputTopology;
}

/// Options of [`check`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CheckOptions {
    /// Tessellation resolution for the ray, normal-agreement and watertightness rows.
    /// Default 4.
    pub resolution: usize,
    /// Level of the barycentric grid sampled on each interior facet (`(l+1)(l+2)/2` points,
    /// less those on mesh edges). Default 6: at least 16 points on every facet with at most
    /// two mesh vertices.
    pub facet_level: usize,
}

impl Default for CheckOptions {
    fn default() -> Self {
        CheckOptions {
            resolution: 4,
            facet_level: 6,
        }
    }
}

/// Runs the whole battery on `surface`.
///
/// # Errors
/// [`InspectError::InvalidOption`] for a zero resolution or facet level,
/// [`InspectError::Measurement`] when the surface cannot be tessellated, a piece's
/// tetrahedron is degenerate, or the surface contradicts itself (interpolation targets of
/// two lengths, a tessellation triangle naming a missing vertex, a patch listing a piece
/// that does not exist).
pub fn check<S: PatchSurface + ?Sized>(
    surface: &S,
    options: &CheckOptions,
) -> Result<CheckReport, InspectError> {
    check_with_progress(surface, options, &NoProgress)
}

/// [`check`], naming each of its stages to `progress` as it starts ("tessellation",
/// "interpolation", "C1 across facets", "normal agreement", "topology"; not counted) and
/// stopping between them when `progress` asks ([`Progress::cancelled`]).
///
/// # Errors
/// As [`check`]; [`InspectError::Cancelled`] when `progress` asked to stop.
pub fn check_with_progress<S: PatchSurface + ?Sized>(
    surface: &S,
    options: &CheckOptions,
    progress: &dyn Progress,
) -> Result<CheckReport, InspectError> {
    if options.resolution == 0 || options.facet_level == 0 {
        return Err(InspectError::InvalidOption(
            "the resolution and the facet level must be at least 1".into(),
        ));
    }
    stage(progress, "tessellation")?;
    let t = surface.tessellate(options.resolution)?;
    measure_all(surface, &t, options.facet_level, progress)
}

/// Starts the battery's stage `name` on `progress`, unless it asks to stop.
fn stage(progress: &dyn Progress, name: &str) -> Result<(), InspectError> {
    check_cancelled(progress)?;
    progress.start(name, 0);
    Ok(())
}

/// [`check`] on a tessellation the caller already has (from
/// [`PatchSurface::tessellate`]); `facet_level` as in [`CheckOptions`].
///
/// # Errors
/// [`InspectError::InvalidOption`] for a zero facet level, [`InspectError::Measurement`] as
/// for [`check`].
pub fn check_tessellation<S: PatchSurface + ?Sized>(
    surface: &S,
    tessellation: &Tessellated,
    facet_level: usize,
) -> Result<CheckReport, InspectError> {
    if facet_level == 0 {
        return Err(InspectError::InvalidOption(
            "the facet level must be at least 1".into(),
        ));
    }
    measure_all(surface, tessellation, facet_level, &NoProgress)
}

fn measure_all<S: PatchSurface + ?Sized>(
    surface: &S,
    t: &Tessellated,
    facet_level: usize,
    progress: &dyn Progress,
) -> Result<CheckReport, InspectError> {
    let (points, normals) = surface.interpolation_targets();
    if points.len() != normals.len() {
        return Err(InspectError::Measurement(format!(
            "the surface's interpolation targets are {} points but {} normals",
            points.len(),
            normals.len()
        )));
    }
    stage(progress, "interpolation")?;
    let interp = interpolation(surface);
    stage(progress, "C1 across facets")?;
    let c1 = continuity(surface, facet_level);
    stage(progress, "normal agreement")?;
    let normals = normal_agreement(surface, t)?;
    stage(progress, "topology")?;
    let topo = topology(t, surface.input_topology());
    check_cancelled(progress)?;
    let margins = surface.parameter_margins();
    Ok(CheckReport::new(
        surface, &interp, &c1, &normals, t, &topo, &margins,
    ))
}
