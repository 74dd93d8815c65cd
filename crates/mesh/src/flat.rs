//! Flat regions of a triangle mesh, and the remeshing of those with skinny faces.
//!
//! CAD exporters triangulate a planar face (a cylinder's cap, a plate with holes) as a fan
//! from one corner or as a strip, and repair's ear clipping triangulates an OBJ n-gon the same
//! way: a 48-gon becomes 46 needles with an angle of 3.75° at the fan's corner. Such *skinny*
//! faces ([`DEFAULT_SKINNY_ANGLE_DEGREES`]) are harmless for rendering but not for the
//! simplicial hull of an A-patch surface (Xu–Huang–Bajaj 2001, §3): a face's tetrahedra
//! inherit its shape, and the local Butterfly refinement that separates overlapping
//! tetrahedra folds skinny faces instead (a puck of height 0.3 with 48-segment fan caps does
//! not build with any normals; with 24 segments, 7.5°, it builds).
//!
//! [`remesh_flat_regions`] replaces each flat region that holds a skinny face by a
//! constrained Delaunay triangulation of the same polygon, refined (Steiner points inside the
//! region only) until no angle is below [`FlatRemeshOptions::min_angle_degrees`] where the
//! boundary allows it. What it keeps, by construction and checked for every region before the
//! region is replaced:
//!
//! * every vertex and its position (new vertices are appended, so vertex ids do not change);
//! * the region's boundary, edge for edge and in the same direction, so the faces around it
//!   join the new faces exactly as they joined the old ones — unless asked to split *narrow
//!   strips* ([`FlatRemeshOptions::split_narrow_strips`]; the side wall of a thin plate: no
//!   triangulation of a 1 × 0.02 rectangle with its four corners alone has an angle above
//!   1.2°): then a strip's long edges between it and another flat region are split at evenly
//!   spaced points on the edge, which lie in both regions' planes, and both regions are
//!   retriangulated with them on their boundaries (`narrow`: [`NARROW_RATIO`],
//!   [`MAX_PIECES`]). The mesh's own boundary and edges between a flat region and a curved
//!   neighbour are never split;
//! * the region's area and orientation, and its plane: new vertices lie on the plane fitted to
//!   the region, within [`FlatRemeshOptions::tolerance`] of every old vertex.
//!
//! ```
//! use algesurf_mesh::flat::{remesh_flat_regions, FlatRemeshOptions};
//! use algesurf_mesh::geometry::triangle_min_angle;
//! use algesurf_mesh::TriMesh;
//! use glam::DVec3;
//!
//! // A regular 32-gon triangulated as a fan from its first corner: 30 needles of 5.6°.
//! let n = 32;
//! let positions: Vec<DVec3> = (0..n)
//!     .map(|i| {
//!         let a = std::f64::consts::TAU * i as f64 / n as f64;
//!         DVec3::new(a.cos(), a.sin(), 0.0)
//!     })
//!     .collect();
//! let triangles: Vec<[u32; 3]> = (1..n - 1).map(|i| [0, i, i + 1]).collect();
//! let fan = TriMesh::new(positions, triangles).unwrap();
//!
//! let out = remesh_flat_regions(&fan, &FlatRemeshOptions::default()).unwrap();
//! let region = &out.report.remeshed[0];
//! assert_eq!(region.faces.len(), 30);
//! assert_eq!(region.skinny_before, 30);
//! assert!(region.added_vertices > 0 && region.skinny_after == 0);
//! // The 32 corners keep their ids and positions; the new vertices come after them.
//! assert_eq!(&out.mesh.positions()[..32], fan.positions());
//! let p = out.mesh.positions();
//! assert!(out.mesh.triangles().iter().all(|t| {
//!     triangle_min_angle(p[t[0] as usize], p[t[1] as usize], p[t[2] as usize]).to_degrees() > 20.0
//! }));
//! ```

mod grid;
mod narrow;
mod remesh;
mod rim;

pub use narrow::{MAX_PIECES, NARROW_RATIO};

use crate::geometry::{triangle_min_angle, triangle_normal};
use crate::union_find::{find, union};
use crate::{MeshError, TriMesh};
use glam::DVec3;

/// Default [`FlatRemeshOptions::tolerance`]: `1e-6` of the mesh's [`coordinate_scale`].
///
/// Why `1e-6`: coordinates written as float32 (STL is float32 by definition; most CAD
/// exporters write float32 OBJ too) are rounded by up to `6e-8` of their magnitude, which is
/// at most the coordinate scale, so the corners of a planar CAD face lie within about
/// `1e-7` of it from its plane; `1e-6` accepts them with a margin of ten. A curved surface is
/// flat to this tolerance only where its faces are tiny against its radius of curvature (a
/// sagitta of `l²/8r < 1e-6` of the scale), and there the new vertices, on the fitted plane,
/// lie within that distance of the surface.
pub const DEFAULT_FLAT_TOLERANCE: f64 = 1e-6;

/// Default [`FlatRemeshOptions::skinny_angle_degrees`]: 10°.
///
/// Why 10°: on the fan caps of a puck of height 0.3 (`shapes::puck`), whose needles have an
/// angle of `180° / n` at the fan's corner, the hull builds without refinement at 24 segments
/// (7.5°), needs angle-weighted normals at 32 (5.6°) and fails at 48 (3.75°); 10° leaves a
/// margin above the first failures. Flat regions whose faces all have angles of 10° or more
/// are left as they are.
pub const DEFAULT_SKINNY_ANGLE_DEGREES: f64 = 10.0;

/// Default [`FlatRemeshOptions::min_angle_degrees`]: 25°.
///
/// Delaunay refinement terminates for angle bounds up to about 20.7° (Ruppert's bound) and in
/// practice up to about 30°, beyond which it over-refines; 25°, two and a half times the
/// skinny limit, adds few vertices (a 48-segment fan cap gets about two per boundary vertex).
/// Near the region's boundary, which is kept, faces can stay below it (no point is inserted
/// closer to a boundary edge than half its length).
pub const DEFAULT_REMESH_MIN_ANGLE_DEGREES: f64 = 25.0;

/// How [`flat_regions`] and [`remesh_flat_regions`] work.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlatRemeshOptions {
    /// Two faces across an edge are coplanar when the far corner of each lies within
    /// `tolerance *` [`coordinate_scale`] of the other's plane (and their normals point the
    /// same way); a region (the faces joined by coplanar edges) is flat when all its vertices
    /// lie within that distance of the plane fitted to it. Default
    /// [`DEFAULT_FLAT_TOLERANCE`].
    pub tolerance: f64,
    /// Regions with a face whose smallest angle is below this many degrees are remeshed.
    /// Default [`DEFAULT_SKINNY_ANGLE_DEGREES`].
    pub skinny_angle_degrees: f64,
    /// The angle Delaunay refinement raises every angle to, where the region's boundary
    /// (which is kept) allows it. Must lie in `(0, 30]`. Default
    /// [`DEFAULT_REMESH_MIN_ANGLE_DEGREES`].
    pub min_angle_degrees: f64,
    /// Whether narrow strips get their long edges split (see [`NARROW_RATIO`]): `None`, the
    /// default, keeps every region's boundary; `Some(a)` splits a strip's long edge where it
    /// meets another flat region whose normal differs by more than `a` degrees (`Some(90.0)`:
    /// at right-angled creases and sharper; `Some(0.0)`: between any two flat regions, as a
    /// thin-walled tube's wall quads need, which meet each other at a few degrees). `a` must
    /// lie in `[0, 180]`.
    pub split_narrow_strips: Option<f64>,
}

impl Default for FlatRemeshOptions {
    fn default() -> Self {
        FlatRemeshOptions {
            tolerance: DEFAULT_FLAT_TOLERANCE,
            skinny_angle_degrees: DEFAULT_SKINNY_ANGLE_DEGREES,
            min_angle_degrees: DEFAULT_REMESH_MIN_ANGLE_DEGREES,
            split_narrow_strips: None,
        }
    }
}

impl FlatRemeshOptions {
    /// Checks the ranges: `tolerance` finite and `≥ 0`, `skinny_angle_degrees` in `[0, 60]`,
    /// `min_angle_degrees` in `(0, 30]` (beyond 30° Delaunay refinement need not terminate),
    /// the angle of `split_narrow_strips` in `[0, 180]`.
    ///
    /// # Errors
    /// [`MeshError::InvalidOption`] naming the option.
    pub fn validate(&self) -> Result<(), MeshError> {
        let t = self.tolerance;
        if !(t >= 0.0 && t.is_finite()) {
            return Err(MeshError::InvalidOption(format!(
                "tolerance = {t} must be finite and ≥ 0"
            )));
        }
        let s = self.skinny_angle_degrees;
        if !(0.0..=60.0).contains(&s) {
            return Err(MeshError::InvalidOption(format!(
                "skinny_angle_degrees = {s} must lie in [0, 60]"
            )));
        }
        let a = self.min_angle_degrees;
        if !(a > 0.0 && a <= 30.0) {
            return Err(MeshError::InvalidOption(format!(
                "min_angle_degrees = {a} must lie in (0, 30]"
            )));
        }
        if let Some(c) = self.split_narrow_strips
            && !(0.0..=180.0).contains(&c)
        {
            return Err(MeshError::InvalidOption(format!(
                "split_narrow_strips = {c}° must lie in [0, 180]"
            )));
        }
        Ok(())
    }
}

/// The scale [`FlatRemeshOptions::tolerance`] is relative to: the larger of the bounding
/// box's diagonal and its largest coordinate's magnitude. Why not the diagonal alone: the
/// rounding of a file's coordinates is relative to their magnitude, so a part of 2 mm placed
/// at 100 mm carries noise of `6e-8 × 100 mm` (float32), 50 times what its diagonal would
/// suggest; for parts about the origin the two agree within a factor of two.
pub fn coordinate_scale(mesh: &TriMesh) -> f64 {
    let b = mesh.bounding_box();
    if b.is_empty() {
        return 0.0;
    }
    b.diagonal()
        .max(b.min.abs().max_element())
        .max(b.max.abs().max_element())
}

/// A flat region: faces joined across edges by coplanar neighbours, all of whose vertices lie
/// within the tolerance of one plane.
#[derive(Clone, Debug, PartialEq)]
pub struct FlatRegion {
    /// Its faces, in increasing order (at least two).
    pub faces: Vec<u32>,
    /// The unit normal of the plane fitted to it (the direction of the sum of its faces'
    /// area vectors, so on the side its faces face).
    pub normal: DVec3,
    /// A point of the plane: the area-weighted centroid of its faces.
    pub origin: DVec3,
    /// The largest distance of one of its vertices from that plane.
    pub deviation: f64,
}

/// The flat regions of `mesh` with at least two faces, ordered by their least face (faces
/// compared by their corner ids, each face rotated to start at its lowest).
///
/// Faces are joined across an edge with exactly two faces that traverse it in opposite
/// directions when the far corner of each lies within `tolerance` (an absolute distance) of
/// the other's plane and their normals point the same way; a connected set of joined faces is
/// a region when all its vertices lie within `tolerance` of the plane fitted to it (a chain of
/// nearly coplanar faces that bends away, such as a finely tessellated cylinder, is not).
/// Degenerate faces (zero area) join nothing. The result depends on the mesh, not on the
/// order of its faces: the joins are pairwise and the regions their connected components.
pub fn flat_regions(mesh: &TriMesh, tolerance: f64) -> Vec<FlatRegion> {
    let p = mesh.positions();
    let tris = mesh.triangles();
    let topo = mesh.topology();
    let area_vectors: Vec<DVec3> = tris
        .iter()
        .map(|t| triangle_normal(p[t[0] as usize], p[t[1] as usize], p[t[2] as usize]))
        .collect();
    let mut parent: Vec<u32> = (0..tris.len() as u32).collect();
    for e in 0..topo.edge_count() as u32 {
        let he = topo.edge_half_edges(e);
        if he.len() != 2 {
            continue;
        }
        let (f, g) = (topo.corner_face(he[0]), topo.corner_face(he[1]));
        if f == g || !opposite_directions(topo, he[0], he[1]) {
            continue;
        }
        let [a, b] = topo.edge(e);
        if coplanar(p, tris, &area_vectors, f, g, [a, b], tolerance) {
            union(&mut parent, f, g);
        }
    }
    let mut members: Vec<Vec<u32>> = vec![Vec::new(); tris.len()];
    for f in 0..tris.len() as u32 {
        let r = find(&mut parent, f);
        members[r as usize].push(f);
    }
    let mut regions: Vec<FlatRegion> = members
        .into_iter()
        .filter(|m| m.len() >= 2)
        .filter_map(|faces| fitted_region(p, tris, faces, tolerance))
        .collect();
    // By corners, not face ids: the new vertices are numbered region by region, and their
    // numbers should not depend on the order of the faces.
    regions.sort_by_cached_key(|r| r.faces.iter().map(|&f| canonical(tris[f as usize])).min());
    regions
}

/// True when the corners `c0` and `c1` (on the same edge) traverse it in opposite directions.
fn opposite_directions(topo: &crate::Topology, c0: u32, c1: u32) -> bool {
    let from = |c: u32| topo.corner_vertex(c);
    let to = |c: u32| topo.corner_vertex(topo.next(c));
    from(c0) == to(c1) && to(c0) == from(c1)
}

/// The coplanarity test of [`flat_regions`] for faces `f` and `g` across the edge `ab`.
fn coplanar(
    p: &[DVec3],
    tris: &[[u32; 3]],
    area_vectors: &[DVec3],
    f: u32,
    g: u32,
    ab: [u32; 2],
    tolerance: f64,
) -> bool {
    let (nf, ng) = (area_vectors[f as usize], area_vectors[g as usize]);
    let (lf, lg) = (nf.length(), ng.length());
    if !(lf > 0.0 && lg > 0.0 && nf.dot(ng) > 0.0) {
        return false;
    }
    let far = |t: u32| {
        let t = tris[t as usize];
        t.into_iter().find(|v| !ab.contains(v)).unwrap_or(t[0])
    };
    let a = p[ab[0] as usize];
    let off_f = (p[far(g) as usize] - a).dot(nf / lf).abs();
    let off_g = (p[far(f) as usize] - a).dot(ng / lg).abs();
    off_f <= tolerance && off_g <= tolerance
}

/// The plane fitted to `faces`, or `None` when one of their vertices lies beyond `tolerance`.
///
/// The sums run over the faces in the order of their sorted corner ids, each face's area
/// vector taken from its lowest corner, so that the plane (and the remeshing in its frame)
/// is the same bits whatever the order of the faces and the rotation of their corners.
fn fitted_region(
    p: &[DVec3],
    tris: &[[u32; 3]],
    faces: Vec<u32>,
    tolerance: f64,
) -> Option<FlatRegion> {
    let mut order: Vec<[u32; 3]> = faces.iter().map(|&f| canonical(tris[f as usize])).collect();
    order.sort_unstable();
    let mut sum = DVec3::ZERO;
    let mut weighted = DVec3::ZERO;
    let mut area = 0.0;
    // Relative to the region's lowest vertex, so that the centroid does not cancel far from
    // the origin.
    let base = p[order[0][0] as usize];
    for &[a, b, c] in &order {
        let (pa, pb, pc) = (p[a as usize], p[b as usize], p[c as usize]);
        let n = triangle_normal(pa, pb, pc);
        let l = n.length();
        sum += n;
        area += l;
        weighted += ((pa - base) + (pb - base) + (pc - base)) * (l / 3.0);
    }
    let normal = sum.normalize_or_zero();
    if normal == DVec3::ZERO || area.is_nan() || area <= 0.0 {
        return None;
    }
    let origin = base + weighted / area;
    let mut deviation: f64 = 0.0;
    for t in &order {
        for &v in t {
            deviation = deviation.max((p[v as usize] - origin).dot(normal).abs());
        }
    }
    (deviation <= tolerance).then_some(FlatRegion {
        faces,
        normal,
        origin,
        deviation,
    })
}

/// The triangle's corners rotated to start at the lowest id (the same cycle).
fn canonical([a, b, c]: [u32; 3]) -> [u32; 3] {
    if a < b && a < c {
        [a, b, c]
    } else if b < c {
        [b, c, a]
    } else {
        [c, a, b]
    }
}

/// A flat region [`remesh_flat_regions`] replaced.
#[derive(Clone, Debug, PartialEq)]
pub struct RemeshedRegion {
    /// Its faces in the input mesh, in increasing order.
    pub faces: Vec<u32>,
    /// How many faces replace them.
    pub new_faces: u32,
    /// How many vertices were added inside it.
    pub added_vertices: u32,
    /// How many vertices were put on its boundary: points of its edges split because the
    /// region or a neighbouring flat region is a narrow strip (see [`NARROW_RATIO`]). Each is
    /// counted by both regions it lies between.
    pub boundary_vertices: u32,
    /// Skinny faces (an angle below [`FlatRemeshOptions::skinny_angle_degrees`]) before and
    /// after.
    pub skinny_before: u32,
    /// See [`RemeshedRegion::skinny_before`].
    pub skinny_after: u32,
    /// The smallest angle of its faces before and after, in degrees.
    pub min_angle_before: f64,
    /// See [`RemeshedRegion::min_angle_before`].
    pub min_angle_after: f64,
}

/// Why [`remesh_flat_regions`] left a flat region with skinny faces as it was.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum SkipReason {
    /// Two of its vertices fall on one point of its plane, or two of its boundary edges
    /// cross there: it overlaps itself (a flat fold).
    Overlapping,
    /// A boundary edge passes through another of its vertices in its plane, so the edge
    /// cannot be kept as one edge.
    VertexOnBoundary,
    /// The triangulation did not reproduce its boundary or its area (checked before any
    /// region is replaced).
    Mismatch,
    /// Its skinny faces are the boundary's (a strip narrower than its edges are long, a tiny
    /// corner angle): the new triangulation has as many skinny faces or more.
    NoImprovement,
    /// The triangulator failed on it.
    Triangulator,
}

impl std::fmt::Display for SkipReason {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            SkipReason::Overlapping => "it overlaps itself in its plane",
            SkipReason::VertexOnBoundary => "a vertex lies on one of its boundary edges",
            SkipReason::Mismatch => "the new triangulation did not reproduce its boundary",
            SkipReason::NoImprovement => "its boundary forces its skinny faces",
            SkipReason::Triangulator => "the triangulator failed on it",
        })
    }
}

/// A flat region with skinny faces [`remesh_flat_regions`] left as it was.
#[derive(Clone, Debug, PartialEq)]
pub struct SkippedRegion {
    /// Its faces, in increasing order.
    pub faces: Vec<u32>,
    /// Why.
    pub reason: SkipReason,
}

/// What [`remesh_flat_regions`] did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FlatRemeshReport {
    /// The regions replaced, in the order of [`flat_regions`].
    pub remeshed: Vec<RemeshedRegion>,
    /// The regions with skinny faces left as they were.
    pub skipped: Vec<SkippedRegion>,
    /// For each output face, the input face it lies in. Faces outside the remeshed regions
    /// come first, in their input order; each remeshed region's new faces follow, region by
    /// region.
    pub face_map: Vec<u32>,
    /// How many vertices were added (after the input's, which keep their ids): the split
    /// points first, then each remeshed region's inner ones.
    pub added_vertices: u32,
    /// How many edges between two flat regions were split because a region along them is a
    /// narrow strip ([`NARROW_RATIO`]); 0 unless [`FlatRemeshOptions::split_narrow_strips`]
    /// asks for it.
    pub split_edges: u32,
}

impl FlatRemeshReport {
    /// True when some region was replaced.
    pub fn changed(&self) -> bool {
        !self.remeshed.is_empty()
    }
}

/// The output of [`remesh_flat_regions`].
#[derive(Clone, Debug)]
pub struct FlatRemesh {
    /// The remeshed mesh. Its source faces ([`TriMesh::source_faces`]) are those of the input
    /// faces it maps to; its file normals, where the input has them, are the input's, and the
    /// region's unit normal at new vertices.
    pub mesh: TriMesh,
    /// What changed.
    pub report: FlatRemeshReport,
}

/// Replaces every flat region of `mesh` ([`flat_regions`]) that holds a skinny face by a
/// refined constrained Delaunay triangulation of the same polygon, keeping every vertex, the
/// region's boundary edges and its plane (see the [module docs](self)). Regions without
/// skinny faces, and regions the new triangulation would not improve, are left as they are; the
/// report says which and why. Deterministic: the same mesh gives the same output.
///
/// With [`FlatRemeshOptions::split_narrow_strips`], where skinny faces are left that a
/// region's boundary forces (a narrow strip) and the strip's long edges lie between it and
/// another flat region, those edges are split and the regions on both sides remeshed again
/// with the new points ([`FlatRemeshReport::split_edges`],
/// [`RemeshedRegion::boundary_vertices`]); if that fails for one of them, or leaves as many
/// skinny faces, the remeshing without splits is the result.
///
/// ```
/// use algesurf_mesh::flat::{remesh_flat_regions, FlatRemeshOptions};
/// use algesurf_mesh::shapes::plate;
///
/// // A 2 × 2 × 0.02 plate: its thin sides are strips of 1 × 0.02 rectangles.
/// let options = FlatRemeshOptions {
///     split_narrow_strips: Some(0.0),
///     ..FlatRemeshOptions::default()
/// };
/// let out = remesh_flat_regions(&plate(2, 2.0, 0.02), &options).unwrap();
/// assert_eq!(out.report.split_edges, 16); // the thin sides' long edges
/// assert!(out.report.remeshed.iter().all(|r| r.skinny_after == 0));
/// assert_eq!(out.mesh.euler_characteristic(), 2); // still closed
/// ```
///
/// # Errors
/// [`MeshError::InvalidOption`] when [`FlatRemeshOptions::validate`] refuses the options;
/// [`MeshError::TooLarge`] when the new mesh exceeds 32-bit indices.
pub fn remesh_flat_regions(
    mesh: &TriMesh,
    options: &FlatRemeshOptions,
) -> Result<FlatRemesh, MeshError> {
    options.validate()?;
    let tolerance = options.tolerance * coordinate_scale(mesh);
    let regions = flat_regions(mesh, tolerance);
    let skinny = options.skinny_angle_degrees.to_radians();
    let angle = |f: u32| face_min_angle(mesh, f);
    let skinny_before: Vec<u32> = regions
        .iter()
        .map(|r| r.faces.iter().filter(|&&f| angle(f) < skinny).count() as u32)
        .collect();
    let base = mesh.vertex_count() as u32;
    let none = narrow::EdgeSplits::none(base, regions.len());
    let plain = remesh_with(mesh, &regions, &skinny_before, &none, options)?
        .expect("without splits every region is optional");
    let Some(crease) = options.split_narrow_strips else {
        return Ok(plain);
    };
    let left = plain.report.skipped.len() as u32
        + plain
            .report
            .remeshed
            .iter()
            .map(|r| r.skinny_after)
            .sum::<u32>();
    if left == 0 {
        return Ok(plain);
    }
    // Skinny faces are left: those a region's boundary forces. Where the region is a narrow
    // strip next to another flat region, points on its long edges let it be triangulated well
    // ([`narrow::splits`]).
    let boundaries: Vec<Vec<[u32; 2]>> = regions
        .iter()
        .map(|r| remesh::region_boundary(mesh, r).unwrap_or_default())
        .collect();
    let splits = narrow::splits(
        mesh,
        &plain.mesh,
        &plain.report.face_map,
        &regions,
        &boundaries,
        skinny,
        crease,
    );
    if splits.is_empty() {
        return Ok(plain);
    }
    Ok(remesh_with(mesh, &regions, &skinny_before, &splits, options)?.unwrap_or(plain))
}

/// The smallest angle of face `f` of `mesh`, in radians.
fn face_min_angle(mesh: &TriMesh, f: u32) -> f64 {
    let p = mesh.positions();
    let t = mesh.triangles()[f as usize];
    triangle_min_angle(p[t[0] as usize], p[t[1] as usize], p[t[2] as usize])
}

/// [`remesh_flat_regions`] with the boundary edges `splits` splits. The regions those touch
/// must all be replaced for the mesh to stay conforming: if one of them cannot be, or they
/// have as many skinny faces after as before, the answer is `None` (the caller remeshes
/// without splits). Other regions are replaced where that removes skinny faces, as without
/// splits.
fn remesh_with(
    mesh: &TriMesh,
    regions: &[FlatRegion],
    skinny_before: &[u32],
    splits: &narrow::EdgeSplits,
    options: &FlatRemeshOptions,
) -> Result<Option<FlatRemesh>, MeshError> {
    let p = mesh.positions();
    let tris = mesh.triangles();
    let skinny = options.skinny_angle_degrees.to_radians();
    let angle = |f: u32| face_min_angle(mesh, f);
    let mut report = FlatRemeshReport {
        split_edges: splits.edge_count() as u32,
        ..FlatRemeshReport::default()
    };
    let mut replaced: Vec<(Vec<[u32; 3]>, Vec<u32>)> = Vec::new();
    let mut new_positions: Vec<DVec3> = splits.positions.clone();
    let mut new_normals: Vec<DVec3> = Vec::new();
    // Skinny faces of the touched regions, before and after.
    let (mut touched_before, mut touched_after) = (0u32, 0u32);
    for (r, region) in regions.iter().enumerate() {
        let skinny_before = skinny_before[r];
        let touched = splits.touched[r];
        if skinny_before == 0 && !touched {
            continue;
        }
        let first_new = mesh.vertex_count() + new_positions.len();
        let result = remesh::region_boundary(mesh, region).and_then(|boundary| {
            remesh::retriangulate(
                mesh,
                region,
                &boundary,
                splits,
                options.min_angle_degrees,
                first_new,
            )
            .map(|done| (done, splits.points_on(&boundary)))
        });
        let (done, boundary_vertices) = match result {
            Ok(done) => done,
            Err(_) if touched => return Ok(None),
            Err(reason) => {
                report.skipped.push(SkippedRegion {
                    faces: region.faces.clone(),
                    reason,
                });
                continue;
            }
        };
        // The region's triangles use the input's vertices, the split points and its own new
        // ones only.
        let at = |v: u32| match (v as usize).checked_sub(first_new) {
            Some(i) => done.positions[i],
            None => splits.position(p, v),
        };
        let new_angle = |t: &[u32; 3]| triangle_min_angle(at(t[0]), at(t[1]), at(t[2]));
        let skinny_after = done
            .triangles
            .iter()
            .filter(|t| new_angle(t) < skinny)
            .count() as u32;
        if touched {
            touched_before += skinny_before;
            touched_after += skinny_after;
        } else if skinny_after >= skinny_before {
            report.skipped.push(SkippedRegion {
                faces: region.faces.clone(),
                reason: SkipReason::NoImprovement,
            });
            continue;
        }
        let min_of =
            |it: &mut dyn Iterator<Item = f64>| it.fold(f64::INFINITY, f64::min).to_degrees();
        report.remeshed.push(RemeshedRegion {
            min_angle_before: min_of(&mut region.faces.iter().map(|&f| angle(f))),
            min_angle_after: min_of(&mut done.triangles.iter().map(new_angle)),
            faces: region.faces.clone(),
            new_faces: done.triangles.len() as u32,
            added_vertices: done.positions.len() as u32,
            boundary_vertices,
            skinny_before,
            skinny_after,
        });
        new_normals.extend(std::iter::repeat_n(region.normal, done.positions.len()));
        new_positions.extend(done.positions);
        replaced.push((done.triangles, done.source));
    }
    if !splits.is_empty() && touched_after >= touched_before {
        return Ok(None);
    }
    if report.remeshed.is_empty() {
        report.face_map = (0..tris.len() as u32).collect();
        return Ok(Some(FlatRemesh {
            mesh: mesh.clone(),
            report,
        }));
    }
    let total = mesh.vertex_count() + new_positions.len();
    if total >= u32::MAX as usize {
        return Err(MeshError::TooLarge(total));
    }
    report.added_vertices = new_positions.len() as u32;
    let mut gone = vec![false; tris.len()];
    for r in &report.remeshed {
        for &f in &r.faces {
            gone[f as usize] = true;
        }
    }
    let mut triangles = Vec::with_capacity(tris.len());
    for (f, t) in tris.iter().enumerate() {
        if !gone[f] {
            triangles.push(*t);
            report.face_map.push(f as u32);
        }
    }
    for (t, source) in replaced {
        triangles.extend(t);
        report.face_map.extend(source);
    }
    if triangles.len() >= u32::MAX as usize {
        return Err(MeshError::TooLarge(triangles.len()));
    }
    let source_faces = report
        .face_map
        .iter()
        .map(|&f| mesh.source_faces()[f as usize])
        .collect();
    let positions = p.iter().copied().chain(new_positions).collect();
    let mut out = TriMesh::with_source_faces(positions, triangles, source_faces)?;
    if let Some(n) = mesh.file_normals() {
        // A split point's normal: interpolated between its edge's ends' (it lies between two
        // regions, where neither region's own normal is the surface's).
        let split_normals = split_point_normals(splits, n);
        out.set_file_normals(Some(
            n.iter()
                .copied()
                .chain(split_normals)
                .chain(new_normals)
                .collect(),
        ))?;
    }
    Ok(Some(FlatRemesh { mesh: out, report }))
}

/// File normals for the split points of `splits`, in their order: the normalised
/// interpolation of the normals at the ends of their edge.
fn split_point_normals(splits: &narrow::EdgeSplits, n: &[DVec3]) -> Vec<DVec3> {
    let mut out = vec![DVec3::ZERO; splits.positions.len()];
    for (key, first, pieces) in splits.edges() {
        let (a, b) = (n[key[0] as usize], n[key[1] as usize]);
        for i in 1..pieces {
            let t = f64::from(i) / f64::from(pieces);
            out[(first - splits.base + i - 1) as usize] = a.lerp(b, t).normalize_or(a);
        }
    }
    out
}

#[cfg(test)]
mod tests;
