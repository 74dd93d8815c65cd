//! Adjacency of a polygon or triangle mesh, stored as a corner table with an undirected edge
//! list.
//!
//! Every face corner `c` is also the half-edge from `c`'s vertex to the next corner's vertex in
//! the same face. Undirected edges are numbered in lexicographic order of their (smaller,
//! larger) endpoint pair, so edge ids are deterministic. Non-manifold input is representable:
//! an edge may carry any number of half-edges and a vertex any number of fans; the queries
//! report those situations instead of failing.

use crate::MeshError;
use rayon::prelude::*;

/// Marker for "no element".
pub const NONE: u32 = u32::MAX;

/// One fan of faces around a vertex, in cyclic order.
///
/// Face `faces[i]` lies between `neighbors[i]` and `neighbors[(i + 1) % n]`. For an open fan
/// (the vertex lies on the boundary) there is one more neighbour than faces and the walk goes
/// from one boundary edge to the other; for a closed fan the counts are equal. The order is
/// counter-clockwise seen from the side the first face's normal points to.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Fan {
    /// Neighbouring vertices in cyclic order.
    pub neighbors: Vec<u32>,
    /// Faces in cyclic order.
    pub faces: Vec<u32>,
    /// True when the fan closes (an interior vertex).
    pub closed: bool,
}

/// A connected component of faces (faces are connected when they share an edge).
///
/// Components that touch only at a vertex are separate components; that vertex counts in
/// each of them (so the components' Euler characteristics need not add up to
/// [`Topology::euler_characteristic`]), and it is a non-manifold vertex of the mesh (reported
/// by validation) while each component can still be manifold on its own.
#[derive(Clone, Debug, PartialEq)]
pub struct Component {
    /// Faces of the component, ascending.
    pub faces: Vec<u32>,
    /// Number of vertices used by the component.
    pub vertex_count: usize,
    /// Number of edges of the component.
    pub edge_count: usize,
    /// Number of boundary edges (edges with exactly one face).
    pub boundary_edge_count: usize,
    /// Number of boundary loops (traced fan by fan, see [`Topology::boundary_loops`]).
    pub boundary_loop_count: usize,
    /// Euler characteristic V - E + F.
    pub euler_characteristic: i64,
    /// True when every edge of the component has at most two faces and every vertex has a
    /// single fan of the component's faces.
    pub manifold: bool,
    /// True when all faces can be oriented consistently (always false when not manifold).
    pub orientable: bool,
    /// True when every interior edge is traversed in opposite directions by its two faces.
    pub consistently_oriented: bool,
    /// Genus of an orientable manifold component: `(2 - χ - b) / 2`; `None` when the component
    /// is not an orientable manifold (the formula would not mean anything).
    pub genus: Option<u32>,
}

/// Corner-table adjacency of a mesh with polygonal faces. Two topologies are equal when
/// every table is (the same faces in the same order give the same tables).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Topology {
    vertex_count: usize,
    face_offsets: Vec<u32>,
    corners: Vec<u32>,
    corner_face: Vec<u32>,
    corner_edge: Vec<u32>,
    edges: Vec<[u32; 2]>,
    edge_offsets: Vec<u32>,
    edge_corners: Vec<u32>,
    vertex_offsets: Vec<u32>,
    vertex_corners: Vec<u32>,
    vertex_edge_offsets: Vec<u32>,
    vertex_edges: Vec<u32>,
}

/// Compressed rows: for `items` `(row, value)` over rows `0..count`, the row offsets and the
/// values, each row's in the order `items` gives them.
pub(crate) fn csr(
    count: usize,
    items: impl Iterator<Item = (u32, u32)> + Clone,
) -> (Vec<u32>, Vec<u32>) {
    let mut offsets = vec![0u32; count + 1];
    for (k, _) in items.clone() {
        offsets[k as usize + 1] += 1;
    }
    for i in 0..count {
        offsets[i + 1] += offsets[i];
    }
    let mut fill = offsets.clone();
    let mut out = vec![0u32; offsets[count] as usize];
    for (k, v) in items {
        out[fill[k as usize] as usize] = v;
        fill[k as usize] += 1;
    }
    (offsets, out)
}

impl Topology {
    /// Builds the adjacency of faces given in compressed form: face `f` has the corners
    /// `corners[offsets[f]..offsets[f + 1]]`.
    ///
    /// # Errors
    /// [`MeshError::IndexOutOfRange`] for a corner outside `0..vertex_count`,
    /// [`MeshError::TooFewCorners`] for a face with fewer than three corners, and
    /// [`MeshError::RepeatedVertex`] for a face using a vertex twice; the error names the face.
    pub fn new(
        vertex_count: usize,
        offsets: &[u32],
        corners: &[u32],
    ) -> Result<Topology, MeshError> {
        if corners.len() >= NONE as usize || vertex_count >= NONE as usize {
            return Err(MeshError::TooLarge(corners.len().max(vertex_count)));
        }
        let face_count = offsets.len().saturating_sub(1);
        let mut face_offsets = Vec::with_capacity(face_count + 1);
        face_offsets.push(0u32);
        let mut corner_face = Vec::with_capacity(corners.len());
        let mut cs = Vec::with_capacity(corners.len());
        for f in 0..face_count {
            let (s, e) = (offsets[f] as usize, offsets[f + 1] as usize);
            if e < s || e > corners.len() {
                return Err(MeshError::LengthMismatch {
                    what: "face offsets",
                    expected: corners.len(),
                    found: e,
                });
            }
            let face = &corners[s..e];
            if face.len() < 3 {
                return Err(MeshError::TooFewCorners {
                    face: f,
                    corners: face.len(),
                });
            }
            for (i, &v) in face.iter().enumerate() {
                if v as usize >= vertex_count {
                    return Err(MeshError::IndexOutOfRange {
                        face: f,
                        corner: i,
                        index: v,
                        vertex_count,
                    });
                }
                if face[..i].contains(&v) {
                    let mut c = [face[0], face[1], face[2]];
                    if face.len() > 3 {
                        c = [face[0], face[1], v];
                    }
                    return Err(MeshError::RepeatedVertex {
                        face: f,
                        corners: c,
                    });
                }
            }
            cs.extend_from_slice(face);
            corner_face.extend(std::iter::repeat_n(f as u32, face.len()));
            face_offsets.push(cs.len() as u32);
        }
        let mut t = Topology {
            vertex_count,
            face_offsets,
            corners: cs,
            corner_face,
            corner_edge: Vec::new(),
            edges: Vec::new(),
            edge_offsets: Vec::new(),
            edge_corners: Vec::new(),
            vertex_offsets: Vec::new(),
            vertex_corners: Vec::new(),
            vertex_edge_offsets: Vec::new(),
            vertex_edges: Vec::new(),
        };
        t.build_edges();
        Ok(t)
    }

    /// Builds the adjacency of a triangle list (see [`Topology::new`] for the errors).
    pub fn from_triangles(
        vertex_count: usize,
        triangles: &[[u32; 3]],
    ) -> Result<Topology, MeshError> {
        let offsets: Vec<u32> = (0..=triangles.len() as u32).map(|i| 3 * i).collect();
        let corners: Vec<u32> = triangles.iter().flatten().copied().collect();
        Topology::new(vertex_count, &offsets, &corners)
    }

    fn build_edges(&mut self) {
        let n = self.corners.len();
        // The sort was most of the build (6 ms of the bunny's 208 k corners on one core, by
        // comparisons); the radix sort gives the same order, the pairs being numbered by
        // corner (corner ids break ties). The key is `lo · 2^bits + hi` with `bits` the width
        // of the largest vertex id, which orders as `(lo, hi)` does (`hi < 2^bits`) and
        // leaves the radix sort the fewest digits: 32 bits, three passes, for the bunny's
        // 35 k vertices, where `lo · 2^32 + hi` took five.
        let bits = u64::BITS - (self.vertex_count.max(2) as u64 - 1).leading_zeros();
        let key = |c: usize| {
            let a = self.corners[c];
            let b = self.corners[self.next(c as u32) as usize];
            let (lo, hi) = if a < b { (a, b) } else { (b, a) };
            (((lo as u64) << bits) | hi as u64, c as u32)
        };
        let mut keys: Vec<(u64, u32)>;
        if n < crate::parallel::SERIAL_BELOW {
            keys = (0..n).map(key).collect();
        } else {
            keys = (0..n).into_par_iter().map(key).collect();
        }
        crate::radix::sort_pairs(&mut keys);
        self.corner_edge = vec![NONE; n];
        self.edge_offsets = Vec::with_capacity(n / 2 + 1);
        self.edge_offsets.push(0);
        self.edge_corners = Vec::with_capacity(n);
        let mut i = 0;
        while i < keys.len() {
            let key = keys[i].0;
            let e = self.edges.len() as u32;
            self.edges
                .push([(key >> bits) as u32, (key & ((1 << bits) - 1)) as u32]);
            while i < keys.len() && keys[i].0 == key {
                self.corner_edge[keys[i].1 as usize] = e;
                self.edge_corners.push(keys[i].1);
                i += 1;
            }
            self.edge_offsets.push(self.edge_corners.len() as u32);
        }
        let corners = &self.corners;
        let (vo, vc) = csr(
            self.vertex_count,
            (0..n as u32).map(|c| (corners[c as usize], c)),
        );
        self.vertex_offsets = vo;
        self.vertex_corners = vc;
        let edges = &self.edges;
        let (eo, ev) = csr(
            self.vertex_count,
            (0..edges.len() as u32)
                .flat_map(|e| [(edges[e as usize][0], e), (edges[e as usize][1], e)]),
        );
        self.vertex_edge_offsets = eo;
        self.vertex_edges = ev;
    }

    /// Number of vertices (including unused ones).
    pub fn vertex_count(&self) -> usize {
        self.vertex_count
    }
    /// Number of faces.
    pub fn face_count(&self) -> usize {
        self.face_offsets.len() - 1
    }
    /// Number of undirected edges.
    pub fn edge_count(&self) -> usize {
        self.edges.len()
    }
    /// Number of corners (= half-edges).
    pub fn corner_count(&self) -> usize {
        self.corners.len()
    }
    /// The vertices of face `f` in order.
    pub fn face(&self, f: usize) -> &[u32] {
        &self.corners[self.face_offsets[f] as usize..self.face_offsets[f + 1] as usize]
    }
    /// The corner ids of face `f`.
    pub fn face_corners(&self, f: usize) -> std::ops::Range<u32> {
        self.face_offsets[f]..self.face_offsets[f + 1]
    }
    /// The vertex at corner `c`.
    pub fn corner_vertex(&self, c: u32) -> u32 {
        self.corners[c as usize]
    }
    /// The face of corner `c`.
    pub fn corner_face(&self, c: u32) -> u32 {
        self.corner_face[c as usize]
    }
    /// The next corner of the same face (the half-edge from `c` ends there).
    pub fn next(&self, c: u32) -> u32 {
        let f = self.corner_face[c as usize] as usize;
        if c + 1 < self.face_offsets[f + 1] {
            c + 1
        } else {
            self.face_offsets[f]
        }
    }
    /// The previous corner of the same face.
    pub fn prev(&self, c: u32) -> u32 {
        let f = self.corner_face[c as usize] as usize;
        if c > self.face_offsets[f] {
            c - 1
        } else {
            self.face_offsets[f + 1] - 1
        }
    }
    /// The undirected edge of the half-edge leaving corner `c`.
    pub fn corner_edge(&self, c: u32) -> u32 {
        self.corner_edge[c as usize]
    }
    /// The endpoints of edge `e`, smaller id first.
    pub fn edge(&self, e: u32) -> [u32; 2] {
        self.edges[e as usize]
    }
    /// All edges as endpoint pairs (smaller id first), indexed by edge id.
    pub fn edges(&self) -> &[[u32; 2]] {
        &self.edges
    }
    /// The half-edges (corners) lying on edge `e`: one per incident face side.
    pub fn edge_half_edges(&self, e: u32) -> &[u32] {
        &self.edge_corners
            [self.edge_offsets[e as usize] as usize..self.edge_offsets[e as usize + 1] as usize]
    }
    /// The faces incident to edge `e` (a face appears once per side it contributes).
    pub fn edge_faces(&self, e: u32) -> impl ExactSizeIterator<Item = u32> + '_ {
        self.edge_half_edges(e)
            .iter()
            .map(|&c| self.corner_face[c as usize])
    }
    /// Number of face sides on edge `e` (1: boundary, 2: interior manifold, >2: non-manifold).
    pub fn edge_face_count(&self, e: u32) -> usize {
        (self.edge_offsets[e as usize + 1] - self.edge_offsets[e as usize]) as usize
    }
    /// True when edge `e` has exactly one face.
    pub fn is_boundary_edge(&self, e: u32) -> bool {
        self.edge_face_count(e) == 1
    }
    /// The edge joining `a` and `b`, if any.
    pub fn find_edge(&self, a: u32, b: u32) -> Option<u32> {
        if a as usize >= self.vertex_count || b as usize >= self.vertex_count {
            return None;
        }
        let key = if a < b { [a, b] } else { [b, a] };
        self.vertex_edges(a)
            .iter()
            .copied()
            .find(|&e| self.edges[e as usize] == key)
    }
    /// The corners at vertex `v` (one per incident face side).
    pub fn vertex_corners(&self, v: u32) -> &[u32] {
        &self.vertex_corners
            [self.vertex_offsets[v as usize] as usize..self.vertex_offsets[v as usize + 1] as usize]
    }
    /// The faces incident to vertex `v` (unordered; see [`Topology::fans`] for cyclic order).
    pub fn vertex_faces(&self, v: u32) -> impl ExactSizeIterator<Item = u32> + '_ {
        self.vertex_corners(v)
            .iter()
            .map(|&c| self.corner_face[c as usize])
    }
    /// The edges incident to vertex `v` (unordered).
    pub fn vertex_edges(&self, v: u32) -> &[u32] {
        &self.vertex_edges[self.vertex_edge_offsets[v as usize] as usize
            ..self.vertex_edge_offsets[v as usize + 1] as usize]
    }
    /// Number of edges at vertex `v`.
    pub fn valence(&self, v: u32) -> usize {
        self.vertex_edges(v).len()
    }
    /// The other endpoint of edge `e` seen from `v`.
    pub fn opposite_vertex(&self, e: u32, v: u32) -> u32 {
        let [a, b] = self.edges[e as usize];
        if a == v { b } else { a }
    }
    /// True when vertex `v` is used by at least one face.
    pub fn is_used(&self, v: u32) -> bool {
        !self.vertex_corners(v).is_empty()
    }
    /// True when `v` lies on a boundary edge.
    pub fn is_boundary_vertex(&self, v: u32) -> bool {
        self.vertex_edges(v)
            .iter()
            .any(|&e| self.is_boundary_edge(e))
    }

    /// The other half-edge of a manifold edge (exactly two face sides), else [`NONE`].
    pub fn twin(&self, c: u32) -> u32 {
        let hs = self.edge_half_edges(self.corner_edge[c as usize]);
        match hs {
            [a, b] if *a == c => *b,
            [a, b] if *b == c => *a,
            _ => NONE,
        }
    }

    /// The corner of the face of half-edge `h` that sits at vertex `v` (an endpoint of `h`).
    fn corner_at(&self, h: u32, v: u32) -> u32 {
        if self.corners[h as usize] == v {
            h
        } else {
            self.next(h)
        }
    }

    /// The two edges at corner `c`'s vertex within its face: (incoming, outgoing).
    fn corner_edges(&self, c: u32) -> (u32, u32) {
        (
            self.corner_edge[self.prev(c) as usize],
            self.corner_edge[c as usize],
        )
    }

    /// Walks from corner `c0` leaving through edge `exit0`; appends the faces and neighbours
    /// visited after `c0` to `out` (when given) and returns whether the walk came back to
    /// `stop`. Corners visited are appended to `seen` (whose last entry, or `c0`, is the
    /// corner being left).
    ///
    /// Writing into caller-owned vectors instead of returning fresh ones: `fans` runs once
    /// per vertex in validation, repair and normals, and the per-walk allocations were a
    /// large part of its cost.
    fn walk(
        &self,
        v: u32,
        c0: u32,
        exit0: u32,
        stop: u32,
        seen: &mut Vec<u32>,
        mut out: Option<(&mut Vec<u32>, &mut Vec<u32>)>,
    ) -> bool {
        let (mut exit, mut guard) = (exit0, 0usize);
        let limit = self.vertex_corners(v).len() + 1;
        loop {
            guard += 1;
            if guard > limit {
                return false;
            }
            let hs = self.edge_half_edges(exit);
            if hs.len() != 2 {
                return false;
            }
            // The half-edge on `exit` that does not belong to the corner we leave.
            let from = *seen.last().unwrap_or(&c0);
            let h = if self.corner_at(hs[0], v) == from {
                hs[1]
            } else {
                hs[0]
            };
            let c = self.corner_at(h, v);
            if c == stop {
                return true;
            }
            if seen.contains(&c) {
                return false;
            }
            seen.push(c);
            let (ein, eout) = self.corner_edges(c);
            exit = if ein == exit { eout } else { ein };
            if let Some((faces, nbrs)) = out.as_mut() {
                faces.push(self.corner_face[c as usize]);
                nbrs.push(self.opposite_vertex(exit, v));
            }
        }
    }

    /// The corners of the fan that contains corner `c0` of vertex `v`, appended to `done`
    /// (`c0` first), and, when `out` is given, the fan itself. `fwd` and `bwd` are scratch
    /// vectors for the two walks' visited corners (each walk sees only its own, starting at
    /// `c0`); passing them in lets [`Topology::fan_count`] reuse them across fans.
    fn fan_from(
        &self,
        v: u32,
        c0: u32,
        done: &mut Vec<u32>,
        fwd: &mut Vec<u32>,
        bwd: &mut Vec<u32>,
        out: Option<&mut Vec<Fan>>,
    ) {
        let (ein, eout) = self.corner_edges(c0);
        fwd.clear();
        fwd.push(c0);
        let Some(out) = out else {
            // The same walks as below, collecting only the corners visited.
            if !self.walk(v, c0, ein, c0, fwd, None) {
                bwd.clear();
                bwd.push(c0);
                self.walk(v, c0, eout, c0, bwd, None);
                fwd.extend_from_slice(&bwd[1..]);
            }
            done.extend_from_slice(fwd);
            return;
        };
        let first = self.opposite_vertex(eout, v);
        let second = self.opposite_vertex(ein, v);
        // Forward walk appends after `first, second` and the first face: the layout the
        // closed case needs, and the tail of the open case's.
        let mut neighbors = vec![first, second];
        let mut faces = vec![self.corner_face[c0 as usize]];
        let closed = self.walk(v, c0, ein, c0, fwd, Some((&mut faces, &mut neighbors)));
        let fan = if closed {
            neighbors.pop();
            Fan {
                neighbors,
                faces,
                closed: true,
            }
        } else {
            bwd.clear();
            bwd.push(c0);
            let (mut bf, mut bn) = (Vec::new(), Vec::new());
            self.walk(v, c0, eout, c0, bwd, Some((&mut bf, &mut bn)));
            fwd.extend_from_slice(&bwd[1..]);
            bn.reverse();
            bn.extend_from_slice(&neighbors);
            bf.reverse();
            bf.extend_from_slice(&faces);
            Fan {
                neighbors: bn,
                faces: bf,
                closed: false,
            }
        };
        done.extend_from_slice(fwd);
        out.push(fan);
    }

    /// The fans of faces around vertex `v`: usually one; none for an unused vertex, several
    /// for a non-manifold vertex. Faces are joined into a fan across edges that have exactly
    /// two faces, so a vertex on a non-manifold edge has more than one fan.
    pub fn fans(&self, v: u32) -> Vec<Fan> {
        let corners = self.vertex_corners(v);
        let mut done: Vec<u32> = Vec::with_capacity(corners.len());
        let (mut fwd, mut bwd) = (Vec::with_capacity(corners.len()), Vec::new());
        let mut out = Vec::new();
        for &c0 in corners {
            if done.contains(&c0) {
                continue;
            }
            self.fan_from(v, c0, &mut done, &mut fwd, &mut bwd, Some(&mut out));
        }
        out
    }

    /// `self.fans(v).len()`, without building the fans: the same walks, collecting only the
    /// corners visited. Validation, repair and the component summary need only the count
    /// (and the fans themselves only where it exceeds one).
    pub fn fan_count(&self, v: u32) -> usize {
        let corners = self.vertex_corners(v);
        let mut done: Vec<u32> = Vec::with_capacity(corners.len());
        let (mut fwd, mut bwd) = (Vec::with_capacity(corners.len()), Vec::new());
        let mut n = 0;
        for &c0 in corners {
            if done.contains(&c0) {
                continue;
            }
            self.fan_from(v, c0, &mut done, &mut fwd, &mut bwd, None);
            n += 1;
        }
        n
    }

    /// The one-ring of a manifold vertex in cyclic order, or `None` when `v` is unused or
    /// has more than one fan.
    pub fn one_ring(&self, v: u32) -> Option<Fan> {
        let mut fans = self.fans(v);
        if fans.len() == 1 { fans.pop() } else { None }
    }

    /// The boundary edge that continues a boundary loop through vertex `v`, arriving there
    /// along boundary edge `e` (whose only half-edge is `h`): the other boundary edge of the
    /// fan of `h`'s face at `v`, found by rotating around `v` across edges with exactly two
    /// faces. `None` when the rotation meets a non-manifold edge (more than two faces).
    fn next_boundary_edge(&self, v: u32, e: u32, h: u32) -> Option<u32> {
        let mut c = self.corner_at(h, v);
        let mut enter = e;
        for _ in 0..=self.vertex_corners(v).len() {
            let (ein, eout) = self.corner_edges(c);
            let exit = if ein == enter { eout } else { ein };
            match self.edge_half_edges(exit) {
                [_] => return Some(exit),
                &[a, b] => {
                    let h2 = if self.corner_at(a, v) == c { b } else { a };
                    c = self.corner_at(h2, v);
                    enter = exit;
                }
                _ => return None,
            }
        }
        None
    }

    /// Boundary loops as sequences of edge ids, each with the vertex it starts at.
    ///
    /// A loop is traced fan by fan: at each vertex it leaves along the other boundary edge of
    /// the fan it arrived in, so it never jumps to another fan (or another component) at a
    /// non-manifold vertex where several boundary loops touch. Only where a fan ends at a
    /// non-manifold edge (more than two faces), which has no well-defined continuation, does
    /// the walk take the lowest-numbered unused boundary edge at the vertex; if there is none
    /// the loop is left open (its last vertex differs from its first).
    fn boundary_loop_edges(&self) -> Vec<(u32, Vec<u32>)> {
        let mut used = vec![false; self.edges.len()];
        let mut loops = Vec::new();
        for e0 in 0..self.edges.len() as u32 {
            if used[e0 as usize] || !self.is_boundary_edge(e0) {
                continue;
            }
            used[e0 as usize] = true;
            let h0 = self.edge_half_edges(e0)[0];
            let start = self.corners[h0 as usize];
            let mut cur = self.corners[self.next(h0) as usize];
            let (mut e, mut h) = (e0, h0);
            let mut lp = vec![e0];
            loop {
                let nxt = self.next_boundary_edge(cur, e, h).or_else(|| {
                    self.vertex_edges(cur)
                        .iter()
                        .copied()
                        .find(|&x| !used[x as usize] && self.is_boundary_edge(x))
                });
                match nxt {
                    Some(x) if x == e0 => break,
                    Some(x) if !used[x as usize] => {
                        used[x as usize] = true;
                        lp.push(x);
                        cur = self.opposite_vertex(x, cur);
                        e = x;
                        h = self.edge_half_edges(x)[0];
                    }
                    _ => break,
                }
            }
            loops.push((start, lp));
        }
        loops
    }

    /// Boundary loops as vertex sequences (the closing vertex is not repeated), following the
    /// half-edge direction of the first edge of each loop. Loops are traced per fan, so two
    /// loops touching at a vertex (a non-manifold vertex) stay two loops, and a loop never
    /// crosses from one component into another at a shared vertex.
    pub fn boundary_loops(&self) -> Vec<Vec<u32>> {
        self.boundary_loop_edges()
            .into_iter()
            .map(|(start, edges)| {
                let mut cur = start;
                let mut lp = Vec::with_capacity(edges.len());
                for e in edges {
                    lp.push(cur);
                    cur = self.opposite_vertex(e, cur);
                }
                lp
            })
            .collect()
    }

    /// Euler characteristic V - E + F of the whole mesh, with V the number of vertices used by
    /// some face (unused vertices are not part of the surface). This is not the sum of the
    /// components' characteristics when components share a vertex (that vertex counts once
    /// here and once in each component).
    pub fn euler_characteristic(&self) -> i64 {
        let used = (0..self.vertex_count as u32)
            .filter(|&v| self.is_used(v))
            .count();
        used as i64 - self.edges.len() as i64 + self.face_count() as i64
    }

    /// For each face, the id of its component in [`Topology::components`] order (faces joined
    /// across shared edges; components numbered in the order of their lowest face), without
    /// the orientation and the summary (genus, boundary loops) `components` works out.
    ///
    /// A union–find over the edges in their order, then one pass over the faces that numbers
    /// each component when its lowest face comes up. A search from face to face gave the same
    /// ids in the same few million instructions on the Stanford bunny but took 8.7–35 ms on
    /// one core there (2.6–5.9 ms now; five runs of both, alternately), its reads of the corner
    /// and edge tables scattered over the mesh in the order the search reached the faces; the
    /// edges' order reads those tables sequentially, and the sets (one `u32` a face) stay in
    /// cache.
    ///
    /// ```
    /// use algesurf_mesh::Topology;
    /// // Two triangles sharing an edge, and a third apart.
    /// let t = Topology::from_triangles(7, &[[0, 1, 2], [2, 1, 3], [4, 5, 6]]).unwrap();
    /// assert_eq!(t.face_components(), vec![0, 0, 1]);
    /// ```
    pub fn face_components(&self) -> Vec<u32> {
        let nf = self.face_count();
        // `parent[f] ≤ f` always (the larger root is hung under the smaller), so a set's root
        // is its lowest face, and the walk halves its path as it goes.
        let mut parent: Vec<u32> = (0..nf as u32).collect();
        for e in 0..self.edges.len() {
            let sides = &self.edge_corners
                [self.edge_offsets[e] as usize..self.edge_offsets[e + 1] as usize];
            let Some((&first, rest)) = sides.split_first() else {
                continue;
            };
            let a = self.corner_face[first as usize];
            for &h in rest {
                crate::union_find::union(&mut parent, a, self.corner_face[h as usize]);
            }
        }
        // Faces in order, each replaced by its component's number: `parent[f] ≤ f`, and a
        // lower face has its number already, which is its root's (by induction on `f`); a
        // root (`parent[f] = f`, the lowest face of its set) takes the next number.
        let mut count = 0u32;
        for f in 0..nf {
            let p = parent[f] as usize;
            parent[f] = if p == f {
                count += 1;
                count - 1
            } else {
                parent[p]
            };
        }
        parent
    }

    /// Face components (faces sharing an edge are connected) with their Euler characteristic,
    /// boundary, manifoldness, orientability and genus. Unused vertices belong to no component.
    pub fn components(&self) -> Vec<Component> {
        let (comp, _flip, comps, orientable) = self.propagate_orientation();
        self.summarise(comp, comps, orientable)
    }

    /// A consistent orientation per component: `flips[f]` says whether face `f` must be
    /// reversed so that every interior manifold edge is traversed in opposite directions
    /// (relative to the first face of its component, which is never flipped). Also returns the
    /// component id of each face and whether each component is orientable; in a
    /// non-orientable component the flips are consistent along a spanning tree only.
    pub fn orientation_flips(&self) -> (Vec<bool>, Vec<u32>, Vec<bool>) {
        let (comp, flip, _, orientable) = self.propagate_orientation();
        (flip, comp, orientable)
    }

    #[allow(clippy::type_complexity)]
    fn propagate_orientation(&self) -> (Vec<u32>, Vec<bool>, Vec<Vec<u32>>, Vec<bool>) {
        let nf = self.face_count();
        let mut comp = vec![NONE; nf];
        let mut flip = vec![false; nf];
        let mut comps: Vec<Vec<u32>> = Vec::new();
        let mut orientable = Vec::new();
        for s in 0..nf {
            if comp[s] != NONE {
                continue;
            }
            let id = comps.len() as u32;
            comp[s] = id;
            let mut stack = vec![s as u32];
            let mut faces = vec![];
            let mut ok = true;
            while let Some(f) = stack.pop() {
                faces.push(f);
                for c in self.face_corners(f as usize) {
                    let e = self.corner_edge[c as usize];
                    let hs = self.edge_half_edges(e);
                    for &h in hs {
                        let g = self.corner_face[h as usize];
                        if h == c {
                            continue;
                        }
                        // Same direction on a shared edge means one of the two must flip.
                        let same = self.corners[h as usize] == self.corners[c as usize];
                        let want = flip[f as usize] ^ same;
                        if comp[g as usize] == NONE {
                            comp[g as usize] = id;
                            flip[g as usize] = want;
                            stack.push(g);
                        } else if hs.len() == 2 && flip[g as usize] != want {
                            ok = false;
                        }
                    }
                }
            }
            faces.sort_unstable();
            comps.push(faces);
            orientable.push(ok);
        }
        (comp, flip, comps, orientable)
    }

    fn summarise(
        &self,
        comp: Vec<u32>,
        comps: Vec<Vec<u32>>,
        orientable: Vec<bool>,
    ) -> Vec<Component> {
        let mut vmark = vec![NONE; self.vertex_count];
        let mut loop_count = vec![0usize; comps.len()];
        for (_, lp) in self.boundary_loop_edges() {
            let h = self.edge_half_edges(lp[0])[0];
            loop_count[comp[self.corner_face[h as usize] as usize] as usize] += 1;
        }
        comps
            .into_iter()
            .enumerate()
            .map(|(i, faces)| {
                let mut vc = 0usize;
                let (mut ec, mut bc) = (0usize, 0usize);
                let mut manifold = true;
                let mut consistent = true;
                for &f in &faces {
                    for c in self.face_corners(f as usize) {
                        let v = self.corners[c as usize];
                        if vmark[v as usize] != i as u32 {
                            vmark[v as usize] = i as u32;
                            vc += 1;
                            // Fans of `v` inside this component: components that only
                            // touch at `v` leave each of them manifold there.
                            // Only a vertex with several fans can have several in one
                            // component: count first, build the fans only then.
                            if self.fan_count(v) > 1 {
                                let own = self
                                    .fans(v)
                                    .iter()
                                    .filter(|fan| comp[fan.faces[0] as usize] == i as u32)
                                    .count();
                                if own > 1 {
                                    manifold = false;
                                }
                            }
                        }
                        let e = self.corner_edge[c as usize];
                        let hs = self.edge_half_edges(e);
                        // Count each edge once: at its first half-edge.
                        if hs[0] == c {
                            ec += 1;
                            match hs.len() {
                                1 => bc += 1,
                                2 => {
                                    if self.corners[hs[0] as usize] == self.corners[hs[1] as usize]
                                    {
                                        consistent = false;
                                    }
                                }
                                _ => manifold = false,
                            }
                        }
                    }
                }
                let chi = vc as i64 - ec as i64 + faces.len() as i64;
                let b = loop_count[i];
                let orient = manifold && orientable[i];
                let g2 = 2 - chi - b as i64;
                let genus = (orient && g2 >= 0 && g2 % 2 == 0).then_some((g2 / 2) as u32);
                Component {
                    faces,
                    vertex_count: vc,
                    edge_count: ec,
                    boundary_edge_count: bc,
                    boundary_loop_count: b,
                    euler_characteristic: chi,
                    manifold,
                    orientable: orient,
                    consistently_oriented: consistent,
                    genus,
                }
            })
            .collect()
    }
}
