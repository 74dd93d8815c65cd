//! One step of Loop and of modified Butterfly subdivision, for the whole mesh or locally
//! around one edge (as §3.1 of Xu–Huang–Bajaj 2001 needs when two face tetrahedra intersect).
//!
//! Both schemes split every triangle `(a, b, c)` into `(a, ab, ca)`, `(b, bc, ab)`,
//! `(ab, bc, ca)`, `(bc, c, ca)`, where `ab` is the new vertex ("odd" vertex, edge point) of
//! edge `ab`. New vertices are numbered after the old ones in the order in which their edges
//! first appear when the faces are scanned with edges `ab, bc, ca` (libigl's `igl::loop` order).
//! Subdivision needs a manifold mesh (every edge at most two faces, every vertex one fan).

use crate::butterfly_ring::ButterflyRing;
use crate::topology::{Fan, Topology};
use crate::{MeshError, TriMesh};
use glam::DVec3;
use std::f64::consts::PI;

/// Where a vertex of a subdivided mesh comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VertexOrigin {
    /// An old ("even") vertex, by id.
    Vertex(u32),
    /// The edge point of the old edge with these endpoints (smaller id first).
    Edge([u32; 2]),
}

/// The result of a whole-mesh subdivision step.
#[derive(Clone, Debug)]
pub struct Subdivided {
    /// The refined mesh. Its [`TriMesh::source_faces`] are the old mesh's, through
    /// `face_parent`.
    pub mesh: TriMesh,
    /// For each new face, the old face it lies in.
    pub face_parent: Vec<u32>,
    /// For each new vertex, where it comes from.
    pub vertex_origin: Vec<VertexOrigin>,
}

/// The result of a local (one-edge) refinement.
#[derive(Clone, Debug)]
pub struct LocalRefinement {
    /// The refined mesh: the faces of the split edge are replaced by two faces each, all
    /// others keep their ids. Face `f` of a split pair keeps id `f`, its second half is
    /// appended at the end.
    pub mesh: TriMesh,
    /// The id of the inserted vertex (the old vertex count).
    pub new_vertex: u32,
    /// For each new face, the old face it lies in.
    pub face_parent: Vec<u32>,
}

/// The weights of Loop's even (vertex) rule for interior vertices of valence `n`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LoopWeights {
    /// Warren's simplification: `β = 3/(8n)` for `n > 3`, `3/16` for `n = 3` (what libigl's
    /// `igl::loop` uses; the default).
    #[default]
    Warren,
    /// Loop's original `β = (5/8 − (3/8 + cos(2π/n)/4)²) / n`.
    Loop,
}

impl LoopWeights {
    /// The weight `β` of each ring neighbour for valence `n` (the vertex keeps `1 − nβ`).
    pub fn beta(self, n: usize) -> f64 {
        let nf = n as f64;
        match self {
            LoopWeights::Warren if n == 3 => 3.0 / 16.0,
            LoopWeights::Warren => 3.0 / (8.0 * nf),
            LoopWeights::Loop => {
                let c = 3.0 / 8.0 + 0.25 * (2.0 * PI / nf).cos();
                (5.0 / 8.0 - c * c) / nf
            }
        }
    }
}

/// Checks that every edge has at most two faces and every used vertex one fan.
pub(crate) fn require_manifold(t: &Topology) -> Result<(), MeshError> {
    for e in 0..t.edge_count() as u32 {
        if t.edge_face_count(e) > 2 {
            let [a, b] = t.edge(e);
            return Err(MeshError::NonManifoldEdge(a, b));
        }
    }
    for v in 0..t.vertex_count() as u32 {
        if t.vertex_corners(v).len() > 1 && t.fan_count(v) > 1 {
            return Err(MeshError::NonManifoldVertex(v));
        }
    }
    Ok(())
}

/// The third vertex of triangle `f` besides `a` and `b`.
pub(crate) fn third(mesh: &TriMesh, f: u32, a: u32, b: u32) -> u32 {
    let t = mesh.triangles()[f as usize];
    t.into_iter().find(|&x| x != a && x != b).unwrap_or(t[0])
}

/// The edge id of `a`–`b`, or an error naming the missing edge.
pub(crate) fn edge_id(mesh: &TriMesh, a: u32, b: u32) -> Result<u32, MeshError> {
    mesh.topology()
        .find_edge(a, b)
        .ok_or(MeshError::NoSuchEdge(a, b))
}

/// Loop's edge point of edge `e`: `3/8 (a + b) + 1/8 (c + d)` for an interior edge with
/// opposite vertices `c`, `d`; the midpoint for a boundary edge.
pub fn loop_edge_point(mesh: &TriMesh, e: u32) -> DVec3 {
    let t = mesh.topology();
    let [a, b] = t.edge(e);
    let p = mesh.positions();
    let (pa, pb) = (p[a as usize], p[b as usize]);
    let faces: Vec<u32> = t.edge_faces(e).collect();
    if faces.len() == 2 {
        let c = third(mesh, faces[0], a, b);
        let d = third(mesh, faces[1], a, b);
        0.375 * (pa + pb) + 0.125 * (p[c as usize] + p[d as usize])
    } else {
        0.5 * (pa + pb)
    }
}

/// Loop's vertex point of `v`: `(1 − nβ) v + β Σ p_i` inside, `3/4 v + 1/8 (p_0 + p_k)` on
/// the boundary (the cubic B-spline rule along the boundary curve).
pub fn loop_vertex_point(mesh: &TriMesh, v: u32, weights: LoopWeights) -> DVec3 {
    let p = mesh.positions();
    let x = p[v as usize];
    match mesh.one_ring(v) {
        Some(r) if r.closed => {
            let n = r.neighbors.len();
            let beta = weights.beta(n);
            let s: DVec3 = r.neighbors.iter().map(|&u| p[u as usize]).sum();
            (1.0 - n as f64 * beta) * x + beta * s
        }
        Some(r) => {
            let (a, b) = (r.neighbors[0], r.neighbors[r.neighbors.len() - 1]);
            0.75 * x + 0.125 * (p[a as usize] + p[b as usize])
        }
        None => x,
    }
}

/// Splits all faces at the given edge points (indexed by edge id) and even positions.
fn split_all(
    mesh: &TriMesh,
    even: Vec<DVec3>,
    edge_points: &[DVec3],
) -> Result<Subdivided, MeshError> {
    let t = mesh.topology();
    let nv = mesh.vertex_count();
    let (positions, tris, new_id) = split_triangles(mesh, even, edge_points);
    let mut edge_of = vec![0u32; positions.len() - nv];
    for (e, &id) in new_id.iter().enumerate() {
        if id != u32::MAX {
            edge_of[id as usize - nv] = e as u32;
        }
    }
    let origin: Vec<VertexOrigin> = (0..nv as u32)
        .map(VertexOrigin::Vertex)
        .chain(edge_of.iter().map(|&e| VertexOrigin::Edge(t.edge(e))))
        .collect();
    let parent: Vec<u32> = (0..mesh.face_count() as u32).flat_map(|f| [f; 4]).collect();
    let src = parent
        .iter()
        .map(|&f| mesh.source_faces()[f as usize])
        .collect();
    let refined = TriMesh::with_source_faces(positions, tris, src)?;
    Ok(Subdivided {
        mesh: refined,
        face_parent: parent,
        vertex_origin: origin,
    })
}

/// The 1-to-4 split of every triangle of `mesh`: the positions (`even`, then each edge's
/// point, numbered where a corner of the faces in order first meets the edge), the four
/// triangles of each face in face order, and each edge's new vertex id (`u32::MAX` for an
/// edge of no face). The parts of [`Subdivided::mesh`] without its topology, for a caller
/// that only cuts a piece out of it (`butterfly_limit_normal`).
pub(crate) fn split_triangles(
    mesh: &TriMesh,
    even: Vec<DVec3>,
    edge_points: &[DVec3],
) -> (Vec<DVec3>, Vec<[u32; 3]>, Vec<u32>) {
    let t = mesh.topology();
    let mut new_id = vec![u32::MAX; t.edge_count()];
    let mut positions = even;
    let mut tris = Vec::with_capacity(4 * mesh.face_count());
    for (f, tri) in mesh.triangles().iter().enumerate() {
        let mut m = [0u32; 3];
        for (k, mk) in m.iter_mut().enumerate() {
            let e = t.corner_edge(3 * f as u32 + k as u32) as usize;
            if new_id[e] == u32::MAX {
                new_id[e] = positions.len() as u32;
                positions.push(edge_points[e]);
            }
            *mk = new_id[e];
        }
        let [a, b, c] = *tri;
        let [ab, bc, ca] = m;
        tris.extend([[a, ab, ca], [b, bc, ab], [ab, bc, ca], [bc, c, ca]]);
    }
    (positions, tris, new_id)
}

/// One step of Loop subdivision with boundary rules (boundary curves are cubic B-splines).
///
/// # Errors
/// [`MeshError::NonManifoldEdge`] / [`MeshError::NonManifoldVertex`] on non-manifold input.
pub fn loop_subdivide(mesh: &TriMesh, weights: LoopWeights) -> Result<Subdivided, MeshError> {
    require_manifold(mesh.topology())?;
    let even = (0..mesh.vertex_count() as u32)
        .map(|v| loop_vertex_point(mesh, v, weights))
        .collect();
    let edges: Vec<DVec3> = (0..mesh.topology().edge_count() as u32)
        .map(|e| loop_edge_point(mesh, e))
        .collect();
    split_all(mesh, even, &edges)
}

/// One step of the modified Butterfly scheme (Zorin, Schröder, Sweldens 1996): old vertices
/// stay where they are, edge points follow [`butterfly_edge_point`].
///
/// # Errors
/// [`MeshError::NonManifoldEdge`] / [`MeshError::NonManifoldVertex`] on non-manifold input.
pub fn butterfly_subdivide(mesh: &TriMesh) -> Result<Subdivided, MeshError> {
    split_all(
        mesh,
        mesh.positions().to_vec(),
        &butterfly_edge_points(mesh)?,
    )
}

/// The modified Butterfly points of every edge of `mesh`, in topology order: the new vertices
/// of [`butterfly_subdivide`].
pub(crate) fn butterfly_edge_points(mesh: &TriMesh) -> Result<Vec<DVec3>, MeshError> {
    require_manifold(mesh.topology())?;
    // Each vertex's ring once, not once for each of its edges: an edge point reads both its
    // ends' rings, and building a ring (`Topology::fans`) was most of an edge point's cost
    // (~6.5 k instructions each on the Butterfly normals' cut-outs, `callgrind`).
    let rings: Vec<ButterflyRing> = (0..mesh.vertex_count() as u32)
        .map(|v| ButterflyRing::of(mesh, v))
        .collect();
    let t = mesh.topology();
    let edges: Vec<DVec3> = (0..t.edge_count() as u32)
        .map(|e| {
            let [a, b] = t.edge(e);
            edge_point_with_rings(mesh, e, &rings[a as usize], &rings[b as usize])
        })
        .collect();
    Ok(edges)
}

/// The vertex across edge `x`–`y` from face `f`, or the parallelogram reflection
/// `x + y − third(f)` when that edge is on the boundary (a "virtual" vertex that keeps
/// the stencil exact on planes).
fn wing(mesh: &TriMesh, f: u32, x: u32, y: u32) -> DVec3 {
    let p = mesh.positions();
    let t = mesh.topology();
    let z = third(mesh, f, x, y);
    if let Some(g) = t
        .find_edge(x, y)
        .and_then(|e| t.edge_faces(e).find(|&g| g != f))
    {
        return p[third(mesh, g, x, y) as usize];
    }
    p[x as usize] + p[y as usize] - p[z as usize]
}

/// Zorin et al.'s stencil around an interior vertex `v` of valence `k` for the edge to `to`:
/// `3/4 v + Σ s_j p_j`, with `p_0 = to` and the ring in cyclic order, where
/// `s_j = (1/4 + cos(2πj/k) + 1/2 cos(4πj/k)) / k` for `k ≥ 5`, `(5/12, −1/12, −1/12)` for
/// `k = 3` and `(3/8, 0, −1/8, 0)` for `k = 4`.
fn extraordinary(mesh: &TriMesh, v: u32, to: u32, ring: &ButterflyRing) -> DVec3 {
    let p = mesh.positions();
    // Valence ≥ 33: through the ring's sums, O(1) per edge (`butterfly_ring`).
    if let Some(point) = ring
        .fourier
        .as_ref()
        .and_then(|f| f.edge_point(p[v as usize], to))
    {
        return point;
    }
    let ring = ring.neighbors();
    let k = ring.len();
    let start = ring.iter().position(|&u| u == to).unwrap_or(0);
    let mut s = 0.75 * p[v as usize];
    let table = extraordinary_weights();
    for j in 0..k {
        let w = match k {
            3 => [5.0 / 12.0, -1.0 / 12.0, -1.0 / 12.0][j],
            4 => [3.0 / 8.0, 0.0, -1.0 / 8.0, 0.0][j],
            _ if k < table.len() => table[k][j],
            _ => extraordinary_weight(k, j),
        };
        s += w * p[ring[(start + j) % k] as usize];
    }
    s
}

/// `s_j` of [`extraordinary`] for valence `k ≥ 5`.
fn extraordinary_weight(k: usize, j: usize) -> f64 {
    let a = 2.0 * PI * j as f64 / k as f64;
    (0.25 + a.cos() + 0.5 * (2.0 * a).cos()) / k as f64
}

/// [`extraordinary_weight`] for every `j` of every valence `k < 33` (empty rows for
/// `k < 5`), computed once: the two cosines per weight were a tenth of the Butterfly
/// normals' work, which runs thousands of steps on the same few valences. The same
/// function, so the same values, as computing them each time.
fn extraordinary_weights() -> &'static [Vec<f64>] {
    static TABLE: std::sync::OnceLock<Vec<Vec<f64>>> = std::sync::OnceLock::new();
    TABLE.get_or_init(|| {
        (0..33)
            .map(|k| match k {
                0..5 => Vec::new(),
                _ => (0..k).map(|j| extraordinary_weight(k, j)).collect(),
            })
            .collect()
    })
}

/// The modified Butterfly edge point of edge `e` (Zorin, Schröder, Sweldens 1996).
///
/// * Boundary edge `ab` with boundary neighbours `a'` (before `a`) and `b'` (after `b`): the
///   four-point rule `9/16 (a + b) − 1/16 (a' + b')`, so boundary curves depend only on the
///   boundary.
/// * Interior edge, both ends interior: if both have valence 6, the regular 8-point butterfly
///   (`1/2` on `a, b`, `1/8` on the two opposite vertices, `−1/16` on the four wings; Zorin's
///   10-point stencil with tension `w = 0`); if exactly one end is extraordinary, that end's
///   stencil `3/4 v + Σ s_j p_j` over its ring (`p_0` the other end) with
///   `s_j = (1/4 + cos(2πj/k) + 1/2 cos(4πj/k)) / k` for valence `k ≥ 5`,
///   `(5/12, −1/12, −1/12)` for `k = 3`, `(3/8, 0, −1/8, 0)` for `k = 4`; if both are, the
///   average of the two stencils.
/// * Interior edge with one end on the boundary: the stencil of the interior end (valid for
///   any valence).
/// * Interior edge with both ends on the boundary: the 8-point butterfly, a wing missing
///   across a boundary edge being replaced by its parallelogram reflection.
///
/// Every rule's weights sum to one and reproduce planes, so a flat mesh stays flat.
pub fn butterfly_edge_point(mesh: &TriMesh, e: u32) -> DVec3 {
    let [a, b] = mesh.topology().edge(e);
    edge_point_with_rings(
        mesh,
        e,
        &ButterflyRing::of(mesh, a),
        &ButterflyRing::of(mesh, b),
    )
}

/// [`butterfly_edge_point`] of edge `e = [a, b]` given `a`'s and `b`'s rings
/// ([`ButterflyRing::of`]).
fn edge_point_with_rings(
    mesh: &TriMesh,
    e: u32,
    ring_a: &ButterflyRing,
    ring_b: &ButterflyRing,
) -> DVec3 {
    let (ra, rb) = (&ring_a.fan, &ring_b.fan);
    let t = mesh.topology();
    let [a, b] = t.edge(e);
    let p = mesh.positions();
    let (pa, pb) = (p[a as usize], p[b as usize]);
    let faces: Vec<u32> = t.edge_faces(e).collect();
    if faces.len() != 2 {
        // Boundary edge: four-point rule along the boundary.
        let other_end = |r: &Option<Fan>, x: u32, not: u32| -> DVec3 {
            match r {
                Some(r) if !r.closed => {
                    let (f, l) = (r.neighbors[0], r.neighbors[r.neighbors.len() - 1]);
                    let o = if f == not { l } else { f };
                    p[o as usize]
                }
                // Not on a simple boundary: extrapolate linearly (keeps the midpoint).
                _ => 2.0 * p[x as usize] - p[not as usize],
            }
        };
        let ap = other_end(ra, a, b);
        let bp = other_end(rb, b, a);
        return 9.0 / 16.0 * (pa + pb) - 1.0 / 16.0 * (ap + bp);
    }
    let closed = |r: &Option<crate::Fan>| r.as_ref().is_some_and(|r| r.closed);
    let butterfly = || {
        let (f, g) = (faces[0], faces[1]);
        let c = third(mesh, f, a, b);
        let d = third(mesh, g, a, b);
        let wings =
            wing(mesh, f, a, c) + wing(mesh, f, b, c) + wing(mesh, g, a, d) + wing(mesh, g, b, d);
        0.5 * (pa + pb) + 0.125 * (p[c as usize] + p[d as usize]) - wings / 16.0
    };
    match (closed(ra), closed(rb)) {
        (true, true) => {
            let (na, nb) = (
                ra.as_ref().map_or(0, |r| r.neighbors.len()),
                rb.as_ref().map_or(0, |r| r.neighbors.len()),
            );
            let sa = || extraordinary(mesh, a, b, ring_a);
            let sb = || extraordinary(mesh, b, a, ring_b);
            match (na == 6, nb == 6) {
                (true, true) => butterfly(),
                (false, true) => sa(),
                (true, false) => sb(),
                (false, false) => 0.5 * (sa() + sb()),
            }
        }
        (true, false) => extraordinary(mesh, a, b, ring_a),
        (false, true) => extraordinary(mesh, b, a, ring_b),
        (false, false) => butterfly(),
    }
}

/// Splits edge `a`–`b` at `point`: each face on the edge, `(u, v, w)` with `u → v` the edge
/// in the face's order, becomes `(u, m, w)` (keeping the face id) and `(m, v, w)` (appended).
/// The result is conforming (no T-junction: the edge is split in all its faces) and keeps
/// the orientation.
///
/// # Errors
/// [`MeshError::NoSuchEdge`] when there is no such edge; [`MeshError::NonFinite`] for a
/// non-finite point.
pub fn split_edge(
    mesh: &TriMesh,
    a: u32,
    b: u32,
    point: DVec3,
) -> Result<LocalRefinement, MeshError> {
    if !point.is_finite() {
        return Err(MeshError::NonFinite(format!("edge point {point}")));
    }
    let e = edge_id(mesh, a, b)?;
    let m = mesh.vertex_count() as u32;
    let mut positions = mesh.positions().to_vec();
    positions.push(point);
    let mut tris = mesh.triangles().to_vec();
    let mut parent: Vec<u32> = (0..tris.len() as u32).collect();
    let faces: Vec<u32> = mesh.topology().edge_faces(e).collect();
    for f in faces {
        let t = tris[f as usize];
        let k = (0..3).find(|&k| {
            let (u, v) = (t[k], t[(k + 1) % 3]);
            (u == a && v == b) || (u == b && v == a)
        });
        let Some(k) = k else { continue };
        let (u, v, w) = (t[k], t[(k + 1) % 3], t[(k + 2) % 3]);
        tris[f as usize] = [u, m, w];
        tris.push([m, v, w]);
        parent.push(f);
    }
    let src = parent
        .iter()
        .map(|&f| mesh.source_faces()[f as usize])
        .collect();
    let refined = TriMesh::with_source_faces(positions, tris, src)?;
    Ok(LocalRefinement {
        mesh: refined,
        new_vertex: m,
        face_parent: parent,
    })
}

/// Local modified-Butterfly refinement of edge `a`–`b` (Xu–Huang–Bajaj 2001, §3.1): inserts
/// the Butterfly edge point and splits the edge's faces, leaving every other vertex and
/// face unchanged. Repeat on the new edges for several local steps.
///
/// # Errors
/// As [`split_edge`], plus the manifold requirement of the scheme around the edge.
pub fn butterfly_refine_edge(mesh: &TriMesh, a: u32, b: u32) -> Result<LocalRefinement, MeshError> {
    let e = edge_id(mesh, a, b)?;
    require_local_manifold(mesh, e)?;
    split_edge(mesh, a, b, butterfly_edge_point(mesh, e))
}

/// Local Loop refinement of edge `a`–`b`: inserts Loop's edge point and splits the edge's
/// faces. Old vertices are not moved (moving them would change faces outside the edge's
/// neighbourhood), so this is the odd half of a Loop step only.
///
/// # Errors
/// As [`split_edge`].
pub fn loop_refine_edge(mesh: &TriMesh, a: u32, b: u32) -> Result<LocalRefinement, MeshError> {
    let e = edge_id(mesh, a, b)?;
    require_local_manifold(mesh, e)?;
    split_edge(mesh, a, b, loop_edge_point(mesh, e))
}

fn require_local_manifold(mesh: &TriMesh, e: u32) -> Result<(), MeshError> {
    let t = mesh.topology();
    let [a, b] = t.edge(e);
    if t.edge_face_count(e) > 2 {
        return Err(MeshError::NonManifoldEdge(a, b));
    }
    for v in [a, b] {
        if t.fan_count(v) > 1 {
            return Err(MeshError::NonManifoldVertex(v));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The table holds, bit for bit, the weights the formula gives, for every valence it
    /// covers (and nothing for those below 5, which have stencils of their own); the weights
    /// of a valence sum to 1/4, so that with the 3/4 of the vertex an edge point is an affine
    /// combination.
    #[test]
    fn extraordinary_weights_table_is_the_formula() {
        let table = extraordinary_weights();
        assert_eq!(table.len(), 33);
        for (k, row) in table.iter().enumerate() {
            if k < 5 {
                assert!(row.is_empty(), "valence {k}");
                continue;
            }
            assert_eq!(row.len(), k);
            for (j, w) in row.iter().enumerate() {
                assert_eq!(w.to_bits(), extraordinary_weight(k, j).to_bits(), "{k} {j}");
            }
            assert!(
                (row.iter().sum::<f64>() - 0.25).abs() < 1e-15,
                "valence {k}"
            );
        }
    }
}
