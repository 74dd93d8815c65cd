//! Validation of a polygon mesh as read from a file. Every finding names the elements by their
//! ids in the input (file) order.

use crate::fasthash::{FaceKey, FastMap};
use crate::geometry::{Aabb, exact_scale_exponent, newell_normal, power_of_two};
use crate::topology::{Component, Topology};
use crate::{MeshError, PolygonMesh};
use glam::DVec3;
use std::fmt;

/// Default relative area below which a face is degenerate: `area <= 1e-14 * diagonal²`.
///
/// Why this scale: areas are computed from coordinate differences whose rounding error is
/// about `2^-53 * diagonal`, so the computed area of an exactly degenerate face is at most a
/// few `1e-16 * diagonal²`; a real face, even a sliver from a dense scan with edges
/// `1e-4 * diagonal` long, has area above `1e-9 * diagonal²`. `1e-14` sits between the two with
/// margins of ~100x and ~10^5x, and it is invariant under scaling the model.
pub const DEFAULT_DEGENERATE_AREA: f64 = 1e-14;

/// Options for [`validate_with`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ValidationOptions {
    /// A face is degenerate when its area is at most `degenerate_area * diagonal²`, where
    /// `diagonal` is the bounding-box diagonal of the finite vertices
    /// (default [`DEFAULT_DEGENERATE_AREA`]).
    pub degenerate_area: f64,
}

impl ValidationOptions {
    /// Checks the options: `degenerate_area` must be finite and ≥ 0 (a NaN or negative
    /// threshold would flag no face, an infinite one every face).
    ///
    /// ```
    /// use algesurf_mesh::ValidationOptions;
    /// assert!(ValidationOptions::default().validate().is_ok());
    /// let nan = ValidationOptions { degenerate_area: f64::NAN };
    /// assert!(nan.validate().unwrap_err().to_string().contains("degenerate_area"));
    /// ```
    pub fn validate(&self) -> Result<(), MeshError> {
        let x = self.degenerate_area;
        if x >= 0.0 && x.is_finite() {
            Ok(())
        } else {
            Err(MeshError::InvalidOption(format!(
                "degenerate_area = {x} must be finite and ≥ 0"
            )))
        }
    }
}

impl Default for ValidationOptions {
    fn default() -> Self {
        ValidationOptions {
            degenerate_area: DEFAULT_DEGENERATE_AREA,
        }
    }
}

/// One problem found by [`validate`], naming elements by their input ids.
#[derive(Clone, Debug, PartialEq)]
pub enum Finding {
    /// Face `face`'s corner `corner` refers to a vertex `index` that does not exist.
    IndexOutOfRange {
        /// Face id.
        face: u32,
        /// Corner within the face.
        corner: u32,
        /// The bad vertex index.
        index: u32,
    },
    /// A face with fewer than three corners.
    TooFewCorners {
        /// Face id.
        face: u32,
        /// Number of corners.
        corners: u32,
    },
    /// A face uses the same vertex at two corners.
    RepeatedVertex {
        /// Face id.
        face: u32,
        /// The repeated vertex.
        vertex: u32,
    },
    /// A vertex with a NaN or infinite coordinate.
    NonFiniteVertex {
        /// Vertex id.
        vertex: u32,
    },
    /// A face whose area is (relatively) zero.
    DegenerateFace {
        /// Face id.
        face: u32,
        /// Its area.
        area: f64,
    },
    /// A face with the same vertex set as an earlier face.
    DuplicateFace {
        /// Face id.
        face: u32,
        /// The earlier face with the same vertices.
        duplicate_of: u32,
    },
    /// A vertex no face uses.
    UnusedVertex {
        /// Vertex id.
        vertex: u32,
    },
    /// An edge shared by more than two faces.
    NonManifoldEdge {
        /// The edge's endpoints.
        vertices: [u32; 2],
        /// The faces on it.
        faces: Vec<u32>,
    },
    /// A vertex whose faces form more than one fan.
    NonManifoldVertex {
        /// Vertex id.
        vertex: u32,
        /// Number of fans.
        fans: u32,
    },
    /// Two faces traverse their shared edge in the same direction.
    InconsistentOrientation {
        /// The edge's endpoints.
        vertices: [u32; 2],
        /// The two faces.
        faces: [u32; 2],
    },
}

impl fmt::Display for Finding {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Finding::IndexOutOfRange {
                face,
                corner,
                index,
            } => {
                write!(
                    f,
                    "face {face}: corner {corner} refers to missing vertex {index}"
                )
            }
            Finding::TooFewCorners { face, corners } => {
                write!(f, "face {face} has only {corners} corners")
            }
            Finding::RepeatedVertex { face, vertex } => {
                write!(f, "face {face} uses vertex {vertex} twice")
            }
            Finding::NonFiniteVertex { vertex } => {
                write!(f, "vertex {vertex} has a non-finite coordinate")
            }
            Finding::DegenerateFace { face, area } => {
                write!(f, "face {face} is degenerate (area {area:e})")
            }
            Finding::DuplicateFace { face, duplicate_of } => {
                write!(f, "face {face} duplicates face {duplicate_of}")
            }
            Finding::UnusedVertex { vertex } => write!(f, "vertex {vertex} is unused"),
            Finding::NonManifoldEdge { vertices, faces } => write!(
                f,
                "edge ({}, {}) is shared by {} faces {:?}",
                vertices[0],
                vertices[1],
                faces.len(),
                faces
            ),
            Finding::NonManifoldVertex { vertex, fans } => {
                write!(f, "vertex {vertex} is non-manifold ({fans} fans)")
            }
            Finding::InconsistentOrientation { vertices, faces } => write!(
                f,
                "faces {} and {} traverse edge ({}, {}) in the same direction",
                faces[0], faces[1], vertices[0], vertices[1]
            ),
        }
    }
}

/// The result of [`validate`]: findings plus a topological summary of the well-formed faces.
#[derive(Clone, Debug, PartialEq)]
pub struct ValidationReport {
    /// Number of vertices in the input.
    pub vertex_count: usize,
    /// Number of faces in the input.
    pub face_count: usize,
    /// Histogram of polygon sizes: `(corners, count)`, ascending.
    pub polygon_sizes: Vec<(usize, usize)>,
    /// Bounding box of the finite vertices.
    pub bounding_box: Aabb,
    /// All findings, grouped by kind in the order of the [`Finding`] variants.
    pub findings: Vec<Finding>,
    /// Components of the well-formed faces (face ids are input ids).
    pub components: Vec<Component>,
    /// Boundary loops of the well-formed faces (vertex ids; see
    /// [`crate::Topology::boundary_loops`]).
    pub boundary_loops: Vec<Vec<u32>>,
    /// Euler characteristic V − E + F of the well-formed faces, V counting the vertices they
    /// use (each once, even where components touch; see
    /// [`crate::Topology::euler_characteristic`]).
    pub euler_characteristic: i64,
}

impl ValidationReport {
    /// True when there are no findings at all.
    pub fn is_valid(&self) -> bool {
        self.findings.is_empty()
    }
    /// Number of boundary edges.
    pub fn boundary_edge_count(&self) -> usize {
        self.components.iter().map(|c| c.boundary_edge_count).sum()
    }
    /// Counts per finding kind, as `(kind name, count)` for the kinds present.
    pub fn counts(&self) -> Vec<(&'static str, usize)> {
        let mut out: Vec<(&'static str, usize)> = Vec::new();
        for f in &self.findings {
            let k = finding_kind(f);
            match out.iter_mut().find(|(n, _)| *n == k) {
                Some((_, c)) => *c += 1,
                None => out.push((k, 1)),
            }
        }
        out
    }
}

/// A short machine-friendly name of a finding's kind (`"non_manifold_edge"`, ...).
pub fn finding_kind(f: &Finding) -> &'static str {
    match f {
        Finding::IndexOutOfRange { .. } => "index_out_of_range",
        Finding::TooFewCorners { .. } => "too_few_corners",
        Finding::RepeatedVertex { .. } => "repeated_vertex",
        Finding::NonFiniteVertex { .. } => "non_finite_vertex",
        Finding::DegenerateFace { .. } => "degenerate_face",
        Finding::DuplicateFace { .. } => "duplicate_face",
        Finding::UnusedVertex { .. } => "unused_vertex",
        Finding::NonManifoldEdge { .. } => "non_manifold_edge",
        Finding::NonManifoldVertex { .. } => "non_manifold_vertex",
        Finding::InconsistentOrientation { .. } => "inconsistent_orientation",
    }
}

impl fmt::Display for ValidationReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "{} vertices, {} faces, V-E+F = {}",
            self.vertex_count, self.face_count, self.euler_characteristic
        )?;
        for (i, c) in self.components.iter().enumerate() {
            write!(
                f,
                "component {i}: {} faces, V-E+F = {}, {} boundary loops",
                c.faces.len(),
                c.euler_characteristic,
                c.boundary_loop_count
            )?;
            match c.genus {
                Some(g) => writeln!(f, ", genus {g}")?,
                None => writeln!(f, ", not an orientable manifold")?,
            }
        }
        if self.findings.is_empty() {
            return writeln!(f, "valid");
        }
        for (k, n) in self.counts() {
            writeln!(f, "{n} x {k}")?;
        }
        for x in &self.findings {
            writeln!(f, "  {x}")?;
        }
        Ok(())
    }
}

/// Validates `mesh` with the default options.
pub fn validate(mesh: &PolygonMesh) -> ValidationReport {
    validate_checked(mesh, &ValidationOptions::default())
}

/// The faces of `mesh` that can enter a [`Topology`] (indices in range, at least three
/// distinct corners), as (input ids, offsets, corners), plus the findings for the others.
pub(crate) fn well_formed(
    mesh: &PolygonMesh,
    findings: &mut Vec<Finding>,
) -> (Vec<u32>, Vec<u32>, Vec<u32>) {
    let nv = mesh.vertex_count();
    let (mut ids, mut offsets, mut corners) = (Vec::new(), vec![0u32], Vec::new());
    for (f, face) in mesh.faces().enumerate() {
        let mut ok = true;
        if face.len() < 3 {
            findings.push(Finding::TooFewCorners {
                face: f as u32,
                corners: face.len() as u32,
            });
            ok = false;
        }
        for (i, &v) in face.iter().enumerate() {
            if v as usize >= nv {
                findings.push(Finding::IndexOutOfRange {
                    face: f as u32,
                    corner: i as u32,
                    index: v,
                });
                ok = false;
            } else if face[..i].contains(&v) {
                findings.push(Finding::RepeatedVertex {
                    face: f as u32,
                    vertex: v,
                });
                ok = false;
            }
        }
        if ok {
            ids.push(f as u32);
            corners.extend_from_slice(face);
            offsets.push(corners.len() as u32);
        }
    }
    (ids, offsets, corners)
}

/// Validates `mesh`: see [`Finding`] for what is checked. Topological checks (manifoldness,
/// orientation, components) consider only the well-formed faces. Fails only for options that
/// [`ValidationOptions::validate`] refuses.
///
/// ```
/// use algesurf_mesh::{Finding, PolygonMesh, ValidationOptions, validate_with};
/// use glam::DVec3;
/// let mut mesh = PolygonMesh::new();
/// mesh.positions = vec![DVec3::ZERO, DVec3::X, DVec3::new(2.0, 1e-9, 0.0), DVec3::Y];
/// mesh.push_face(&[0, 1, 2]); // a sliver: area 5e-10 against a diagonal² of 5
/// mesh.push_face(&[1, 0, 3]);
/// let degenerate = |options: &ValidationOptions| -> Result<Vec<u32>, algesurf_mesh::MeshError> {
///     let report = validate_with(&mesh, options)?;
///     Ok(report.findings.iter().filter_map(|f| match f {
///         Finding::DegenerateFace { face, .. } => Some(*face),
///         _ => None,
///     }).collect())
/// };
/// assert_eq!(degenerate(&ValidationOptions { degenerate_area: 1e-9 })?, vec![0]);
/// assert!(degenerate(&ValidationOptions::default())?.is_empty());
/// assert!(degenerate(&ValidationOptions { degenerate_area: -1.0 }).is_err());
/// # Ok::<(), algesurf_mesh::MeshError>(())
/// ```
pub fn validate_with(
    mesh: &PolygonMesh,
    options: &ValidationOptions,
) -> Result<ValidationReport, MeshError> {
    options.validate()?;
    Ok(validate_checked(mesh, options))
}

/// [`validate_with`] with options already checked.
fn validate_checked(mesh: &PolygonMesh, options: &ValidationOptions) -> ValidationReport {
    let mut findings = Vec::new();
    let (ids, offsets, corners) = well_formed(mesh, &mut findings);
    let nv = mesh.vertex_count();
    let bbox = Aabb::from_points(&mesh.positions);
    let mut sizes: Vec<(usize, usize)> = Vec::new();
    for face in mesh.faces() {
        match sizes.iter_mut().find(|(k, _)| *k == face.len()) {
            Some((_, c)) => *c += 1,
            None => sizes.push((face.len(), 1)),
        }
    }
    sizes.sort_unstable();
    for (v, p) in mesh.positions.iter().enumerate() {
        if !p.is_finite() {
            findings.push(Finding::NonFiniteVertex { vertex: v as u32 });
        }
    }
    // Areas of a mesh beyond 2^±64 are measured on its points scaled by a power of two
    // (`exact_scale_exponent`; exact), where they neither underflow nor overflow, and
    // reported at the mesh's scale: nothing changes for other meshes (`e = 0`).
    let e = exact_scale_exponent(&mesh.positions);
    let (down, up) = (power_of_two(-e), power_of_two(e));
    let scaled_diagonal = Aabb {
        min: bbox.min * down,
        max: bbox.max * down,
    }
    .diagonal();
    let threshold = options.degenerate_area * scaled_diagonal * scaled_diagonal;
    let mut pts: Vec<DVec3> = Vec::new();
    // Keys compare the sorted vertex ids exactly; see `fasthash` for why the fast hasher.
    let mut seen: FastMap<FaceKey, u32> = FastMap::default();
    for (k, &f) in ids.iter().enumerate() {
        let face = &corners[offsets[k] as usize..offsets[k + 1] as usize];
        pts.clear();
        pts.extend(face.iter().map(|&v| mesh.positions[v as usize] * down));
        let area = 0.5 * newell_normal(&pts).length();
        if area.is_finite() && area <= threshold {
            // Back at the mesh's scale: `up` twice, as `up²` can leave the range.
            let area = area * up * up;
            findings.push(Finding::DegenerateFace { face: f, area });
        }
        let key = FaceKey::new(face);
        match seen.get(&key) {
            Some(&g) => findings.push(Finding::DuplicateFace {
                face: f,
                duplicate_of: g,
            }),
            None => {
                seen.insert(key, f);
            }
        }
    }
    let topo = match Topology::new(nv, &offsets, &corners) {
        Ok(t) => t,
        Err(_) => {
            // Unreachable: `well_formed` filtered exactly what `Topology::new` rejects (or the
            // mesh exceeds 32-bit indices); report without topology rather than panic.
            return ValidationReport {
                vertex_count: nv,
                face_count: mesh.face_count(),
                polygon_sizes: sizes,
                bounding_box: bbox,
                findings,
                components: Vec::new(),
                boundary_loops: Vec::new(),
                euler_characteristic: 0,
            };
        }
    };
    for v in 0..nv as u32 {
        if !topo.is_used(v) {
            findings.push(Finding::UnusedVertex { vertex: v });
        }
    }
    for e in 0..topo.edge_count() as u32 {
        let hs = topo.edge_half_edges(e);
        if hs.len() > 2 {
            findings.push(Finding::NonManifoldEdge {
                vertices: topo.edge(e),
                faces: topo.edge_faces(e).map(|g| ids[g as usize]).collect(),
            });
        }
    }
    for v in 0..nv as u32 {
        if topo.vertex_corners(v).len() > 1 {
            let fans = topo.fan_count(v);
            if fans > 1 {
                findings.push(Finding::NonManifoldVertex {
                    vertex: v,
                    fans: fans as u32,
                });
            }
        }
    }
    for e in 0..topo.edge_count() as u32 {
        let hs = topo.edge_half_edges(e);
        if hs.len() == 2 && topo.corner_vertex(hs[0]) == topo.corner_vertex(hs[1]) {
            findings.push(Finding::InconsistentOrientation {
                vertices: topo.edge(e),
                faces: [
                    ids[topo.corner_face(hs[0]) as usize],
                    ids[topo.corner_face(hs[1]) as usize],
                ],
            });
        }
    }
    let mut components = topo.components();
    for c in &mut components {
        for f in &mut c.faces {
            *f = ids[*f as usize];
        }
    }
    // Group findings by kind, keeping element order inside each kind.
    findings.sort_by_key(kind_rank);
    ValidationReport {
        vertex_count: nv,
        face_count: mesh.face_count(),
        polygon_sizes: sizes,
        bounding_box: bbox,
        findings,
        components,
        boundary_loops: topo.boundary_loops(),
        euler_characteristic: topo.euler_characteristic(),
    }
}

fn kind_rank(f: &Finding) -> u8 {
    match f {
        Finding::IndexOutOfRange { .. } => 0,
        Finding::TooFewCorners { .. } => 1,
        Finding::RepeatedVertex { .. } => 2,
        Finding::NonFiniteVertex { .. } => 3,
        Finding::DegenerateFace { .. } => 4,
        Finding::DuplicateFace { .. } => 5,
        Finding::UnusedVertex { .. } => 6,
        Finding::NonManifoldEdge { .. } => 7,
        Finding::NonManifoldVertex { .. } => 8,
        Finding::InconsistentOrientation { .. } => 9,
    }
}
