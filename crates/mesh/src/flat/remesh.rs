//! The new triangulation of one flat region: a constrained Delaunay triangulation of its
//! vertices with its boundary edges as constraints, refined inside it (`spade`), checked
//! against the region before it is used.

use super::grid::{FaceGrid, signed_area2};
use super::narrow::EdgeSplits;
use super::{FlatRegion, SkipReason};
use crate::TriMesh;
use crate::fasthash::{FastMap, FastSet};
use glam::{DVec2, DVec3};
use spade::handles::FixedVertexHandle;
use spade::{
    AngleLimit, ConstrainedDelaunayTriangulation, Point2, RefinementParameters, Triangulation,
};

/// A region's new triangulation.
pub(super) struct Retriangulated {
    /// Triangles in the mesh's vertex ids: the input's, and new ones from `first_new` on.
    pub triangles: Vec<[u32; 3]>,
    /// For each triangle, the region face it lies in.
    pub source: Vec<u32>,
    /// The positions of the new vertices `first_new..`.
    pub positions: Vec<DVec3>,
}

/// The region's plane as the triangulator sees it: `(p - origin)` in the orthonormal basis
/// `(u, v)` with `u × v` the region's normal, scaled by `1 / scale` and moved by `(2, 2)`,
/// so that every vertex lies in `[1, 3]²`. Why the offset: every point the refinement
/// inserts lies in the convex hull of the vertices, so its coordinates stay within `[1, 3]`
/// too, away from the subnormal range below which `spade` refuses a coordinate (`2^-142`);
/// the price is a bit of absolute precision (`2^-51` instead of `2^-53` of the region's
/// size), far below any tolerance here.
struct Frame {
    origin: DVec3,
    u: DVec3,
    v: DVec3,
    scale: f64,
}

impl Frame {
    fn new(region: &FlatRegion, points: impl Iterator<Item = DVec3> + Clone) -> Frame {
        let u = region.normal.any_orthonormal_vector();
        let v = region.normal.cross(u);
        let origin = region.origin;
        let scale = points
            .map(|p| {
                let d = p - origin;
                d.dot(u).abs().max(d.dot(v).abs())
            })
            .fold(0.0, f64::max);
        Frame {
            origin,
            u,
            v,
            scale,
        }
    }

    fn to_plane(&self, p: DVec3) -> DVec2 {
        let d = p - self.origin;
        DVec2::new(
            2.0 + d.dot(self.u) / self.scale,
            2.0 + d.dot(self.v) / self.scale,
        )
    }

    fn to_space(&self, q: DVec2) -> DVec3 {
        self.origin + self.u * ((q.x - 2.0) * self.scale) + self.v * ((q.y - 2.0) * self.scale)
    }
}

/// The region's directed boundary edges, sorted, or [`SkipReason::Overlapping`] when a directed
/// edge is there twice (two of its faces overlap along it).
pub(super) fn region_boundary(
    mesh: &TriMesh,
    region: &FlatRegion,
) -> Result<Vec<[u32; 2]>, SkipReason> {
    let tris = mesh.triangles();
    directed_boundary(region.faces.iter().map(|&f| tris[f as usize])).ok_or(SkipReason::Overlapping)
}

/// The region's new triangulation, with new vertices numbered from `first_new`, or why there
/// is none. Its boundary is `boundary` ([`region_boundary`]) with the edges `splits` splits
/// replaced by their chains of split points.
pub(super) fn retriangulate(
    mesh: &TriMesh,
    region: &FlatRegion,
    boundary: &[[u32; 2]],
    splits: &EdgeSplits,
    min_angle_degrees: f64,
    first_new: usize,
) -> Result<Retriangulated, SkipReason> {
    let p = mesh.positions();
    let tris = mesh.triangles();
    let boundary: Vec<[u32; 2]> = if splits.is_empty() {
        boundary.to_vec()
    } else {
        let mut chained: Vec<[u32; 2]> = boundary
            .iter()
            .flat_map(|&[a, b]| {
                let chain = splits.chain(a, b);
                chain.windows(2).map(|w| [w[0], w[1]]).collect::<Vec<_>>()
            })
            .collect();
        chained.sort_unstable();
        chained
    };
    // The region's vertices (and the split points on its boundary) in increasing order, and
    // their local ids.
    let mut vertices: Vec<u32> = region
        .faces
        .iter()
        .flat_map(|&f| tris[f as usize])
        .chain(boundary.iter().map(|e| e[0]))
        .collect();
    vertices.sort_unstable();
    vertices.dedup();
    let local: FastMap<u32, usize> = vertices.iter().enumerate().map(|(i, &v)| (v, i)).collect();
    let at = |v: u32| splits.position(p, v);

    let frame = Frame::new(region, vertices.iter().map(|&v| at(v)));
    if !(frame.scale > 0.0 && frame.scale.is_finite()) {
        return Err(SkipReason::Overlapping);
    }
    let q: Vec<DVec2> = vertices.iter().map(|&v| frame.to_plane(at(v))).collect();
    let old = FaceGrid::new(
        region
            .faces
            .iter()
            .map(|&f| tris[f as usize].map(|v| q[local[&v]]))
            .collect(),
    );
    let boundary_local: Vec<[usize; 2]> = boundary.iter().map(|e| e.map(|v| local[&v])).collect();
    let rim = super::rim::rim_points(&q, &boundary_local, &old);
    let refined = std::panic::catch_unwind(|| refine(&q, &rim, &boundary_local, min_angle_degrees));
    let (points, faces) = match refined {
        Ok(r) => r?,
        // `spade` asserts where its own arithmetic fails (an inserted circumcentre it cannot
        // place); the region is then left as it was.
        Err(_) => return Err(SkipReason::Triangulator),
    };

    // New ids: region vertices keep theirs, the triangulator's own points used by a region
    // triangle are numbered from `first_new` in the triangulator's order.
    let mut id: Vec<u32> = vertices.clone();
    id.resize(points.len(), u32::MAX);
    let mut positions = Vec::new();
    let mut triangles = Vec::with_capacity(faces.len());
    for f in &faces {
        let mut t = [0u32; 3];
        for (k, &h) in f.iter().enumerate() {
            if id[h] == u32::MAX {
                id[h] = (first_new + positions.len()) as u32;
                positions.push(frame.to_space(points[h]));
            }
            t[k] = id[h];
        }
        triangles.push(t);
    }
    check(
        &triangles,
        &faces,
        &points,
        &boundary,
        vertices.len(),
        region,
        tris,
        &q,
        &local,
    )?;
    let source = faces
        .iter()
        .map(|f| {
            let c = (points[f[0]] + points[f[1]] + points[f[2]]) / 3.0;
            // Every centroid lies in the region, whose faces' boxes cover it.
            let (i, _) = old.locate(c).unwrap_or((0, 0.0));
            region.faces[i as usize]
        })
        .collect();
    Ok(Retriangulated {
        triangles,
        source,
        positions,
    })
}

/// The refined constrained Delaunay triangulation of the points `q` with the `boundary`
/// edges (indices into `q`) as constraints and the `rim` points inserted before refinement:
/// all its points (the first `q.len()` are `q`) and the triangles inside the boundary,
/// counter-clockwise, as point indices.
#[allow(clippy::type_complexity)]
fn refine(
    q: &[DVec2],
    rim: &[DVec2],
    boundary: &[[usize; 2]],
    min_angle_degrees: f64,
) -> Result<(Vec<DVec2>, Vec<[usize; 3]>), SkipReason> {
    let mut cdt: ConstrainedDelaunayTriangulation<Point2<f64>> =
        ConstrainedDelaunayTriangulation::new();
    let mut handles: Vec<FixedVertexHandle> = Vec::with_capacity(q.len());
    for (i, x) in q.iter().enumerate() {
        let h = cdt
            .insert(Point2::new(x.x, x.y))
            .map_err(|_| SkipReason::Triangulator)?;
        if h.index() != i {
            // The point was there already: two vertices at one point of the plane.
            return Err(SkipReason::Overlapping);
        }
        handles.push(h);
    }
    let mut shortest = f64::INFINITY;
    for &[a, b] in boundary {
        let (ha, hb) = (handles[a], handles[b]);
        shortest = shortest.min(q[a].distance_squared(q[b]));
        if cdt.exists_constraint(ha, hb) {
            continue;
        }
        if cdt.try_add_constraint(ha, hb).is_empty() {
            return Err(SkipReason::Overlapping);
        }
        if !cdt.exists_constraint(ha, hb) {
            return Err(SkipReason::VertexOnBoundary);
        }
    }
    for x in rim {
        // Inside the region and off its edges (`rim_points`): never on a constraint.
        cdt.insert(Point2::new(x.x, x.y))
            .map_err(|_| SkipReason::Triangulator)?;
    }
    // Triangles far smaller than the boundary's shortest edge are left alone: refining them
    // cannot help the region's shape (the boundary is kept) and would cascade near a small
    // corner angle. The vertex budget bounds the work whatever happens (a fan cap of n
    // segments takes about 2n).
    let params = RefinementParameters::<f64>::new()
        .with_angle_limit(AngleLimit::from_deg(min_angle_degrees))
        .exclude_outer_faces(true)
        .keep_constraint_edges()
        .with_min_required_area(1e-2 * shortest)
        .with_max_additional_vertices(16 * q.len() + rim.len() + 64);
    let result = cdt.refine(params);
    let excluded: FastSet<usize> = result.excluded_faces.iter().map(|f| f.index()).collect();
    let points: Vec<DVec2> = cdt
        .vertices()
        .map(|v| DVec2::new(v.position().x, v.position().y))
        .collect();
    let mut faces = Vec::new();
    for f in cdt.inner_faces() {
        if excluded.contains(&f.fix().index()) {
            continue;
        }
        let [a, b, c] = f.vertices().map(|v| v.fix().index());
        // Counter-clockwise in the frame, so that the triangle faces the region's normal.
        faces.push(if signed_area2(points[a], points[b], points[c]) >= 0.0 {
            [a, b, c]
        } else {
            [a, c, b]
        });
    }
    Ok((points, faces))
}

/// The boundary of `triangles`: their directed edges whose reverse is not one of them,
/// sorted; `None` when a directed edge is there twice (two faces overlap along it).
fn directed_boundary(triangles: impl Iterator<Item = [u32; 3]>) -> Option<Vec<[u32; 2]>> {
    let directed: Vec<[u32; 2]> = triangles
        .flat_map(|[a, b, c]| [[a, b], [b, c], [c, a]])
        .collect();
    let set: FastSet<[u32; 2]> = directed.iter().copied().collect();
    if set.len() != directed.len() {
        return None;
    }
    let mut boundary: Vec<[u32; 2]> = directed
        .into_iter()
        .filter(|&[a, b]| !set.contains(&[b, a]))
        .collect();
    boundary.sort_unstable();
    Some(boundary)
}

/// Checks the new triangulation against the region: every triangle of positive area, every
/// region vertex used, no directed edge twice, the same boundary edge for edge and direction,
/// and the same area within `1e-9` (relative; the sums differ by rounding only, ~`n` ulps).
#[allow(clippy::too_many_arguments)]
fn check(
    triangles: &[[u32; 3]],
    faces: &[[usize; 3]],
    points: &[DVec2],
    boundary: &[[u32; 2]],
    region_vertices: usize,
    region: &FlatRegion,
    tris: &[[u32; 3]],
    q: &[DVec2],
    local: &FastMap<u32, usize>,
) -> Result<(), SkipReason> {
    let mut used = vec![false; region_vertices];
    let mut area = 0.0;
    for f in faces {
        let a = signed_area2(points[f[0]], points[f[1]], points[f[2]]);
        // NaN counts as not positive.
        if a.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return Err(SkipReason::Mismatch);
        }
        area += a;
        for &h in f {
            if h < region_vertices {
                used[h] = true;
            }
        }
    }
    if used.iter().any(|u| !u) {
        return Err(SkipReason::Mismatch);
    }
    if directed_boundary(triangles.iter().copied()).as_deref() != Some(boundary) {
        return Err(SkipReason::Mismatch);
    }
    let old_area: f64 = region
        .faces
        .iter()
        .map(|&f| {
            let [a, b, c] = tris[f as usize].map(|v| q[local[&v]]);
            signed_area2(a, b, c)
        })
        .sum();
    let gap = (area - old_area).abs();
    if gap.is_nan() || gap > 1e-9 * old_area.abs() {
        return Err(SkipReason::Mismatch);
    }
    Ok(())
}
