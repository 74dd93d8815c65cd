//! The simplicial hull Σ with intersection checks and local Butterfly refinement (§3.1).

use crate::bvh::Bvh;
use crate::classify::Side;
use crate::hull::{HullEdge, HullFace, build as build_faces_edges, check_input};
use crate::overlap::overlap_depth;
use crate::{HullError, HullOptions};
use algesurf_mesh::{TriMesh, butterfly_refine_edge, loop_limit_normal};
use glam::DVec3;
use std::collections::HashMap;

/// The mesh element a hull tetrahedron belongs to (ids of the possibly refined mesh).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Element {
    /// A face tetrahedron of this face.
    Face(u32),
    /// An edge tetrahedron of this edge (index into [`SimplicialHull::edges`]).
    Edge(u32),
}

/// One tetrahedron of Σ, as listed by [`SimplicialHull::tetrahedra`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HullTetrahedron {
    /// The face or edge it belongs to.
    pub element: Element,
    /// Its side.
    pub side: Side,
    /// Its vertices in the order of [`crate::FaceTetrahedron`] / [`crate::EdgeTetrahedron`].
    pub vertices: [glam::DVec3; 4],
}

/// Two hull tetrahedra whose interiors overlap ([`SimplicialHull::intersections`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Intersection {
    /// The first tetrahedron.
    pub first: HullTetrahedron,
    /// The second tetrahedron.
    pub second: HullTetrahedron,
    /// [`crate::overlap_depth`] of the pair (> the tolerance).
    pub depth: f64,
}

/// One local refinement step done while building the hull.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Refinement {
    /// The round (0-based) it was done in.
    pub round: usize,
    /// The split edge (vertex ids at the time of the split).
    pub edge: [u32; 2],
    /// The input edge whose neighbourhood it refines (input vertex ids).
    pub input_edge: [u32; 2],
    /// The inserted vertex.
    pub new_vertex: u32,
}

/// The simplicial hull Σ of §3: classification of every edge and face, the face tetrahedra
/// (§3.1) and edge tetrahedra (§3.2), built on the input mesh or — where adjacent tetrahedra
/// intersected — on a locally refined copy of it.
#[derive(Clone, Debug)]
pub struct SimplicialHull {
    mesh: TriMesh,
    normals: Vec<DVec3>,
    faces: Vec<HullFace>,
    edges: Vec<HullEdge>,
    face_map: Vec<u32>,
    input_vertex_count: usize,
    refinements: Vec<Refinement>,
    options: HullOptions,
}

fn key(a: u32, b: u32) -> [u32; 2] {
    if a < b { [a, b] } else { [b, a] }
}

impl SimplicialHull {
    /// Builds the hull of the triangle mesh `(positions, triangles)` with per-vertex normals.
    ///
    /// `normals[v]` is used as the gradient `∇F(p_v)` (pass unit normals, as the paper does;
    /// classification tolerances are applied to their directions). Triangles must be oriented
    /// consistently, counter-clockwise seen from the positive side (the side the normals point
    /// to). Open meshes are accepted: boundary edges are classified but carry no edge
    /// tetrahedra, so the hull — and the surface built in it — ends at the boundary.
    ///
    /// Procedure: build all tetrahedra; find every pair whose interiors overlap (candidates from
    /// a bounding-volume hierarchy, exact test by [`crate::overlap_depth`]); if there are any,
    /// split an edge per pair by the modified Butterfly rule (the shared edge of adjacent
    /// tetrahedra, else the longest edge of each element), give each new vertex its Loop limit
    /// normal, rebuild and repeat, at most [`HullOptions::max_refinement_rounds`] times.
    ///
    /// # Errors
    /// See [`HullError`]; [`HullError::UnresolvedIntersection`] names the input edge when
    /// refinement does not separate the tetrahedra.
    pub fn new(
        positions: &[DVec3],
        triangles: &[[u32; 3]],
        normals: &[DVec3],
        options: &HullOptions,
    ) -> Result<SimplicialHull, HullError> {
        let mesh = TriMesh::new(positions.to_vec(), triangles.to_vec())?;
        Self::build(mesh, normals.to_vec(), options)
    }

    /// As [`SimplicialHull::new`], for a [`TriMesh`] (its positions and triangles; the face map
    /// refers to its triangle ids).
    ///
    /// # Errors
    /// See [`SimplicialHull::new`].
    pub fn from_mesh(mesh: &TriMesh, normals: &[DVec3], options: &HullOptions) -> Result<SimplicialHull, HullError> {
        Self::new(mesh.positions(), mesh.triangles(), normals, options)
    }

    fn build(mut mesh: TriMesh, mut normals: Vec<DVec3>, options: &HullOptions) -> Result<SimplicialHull, HullError> {
        options.validate()?;
        check_input(&mesh, &normals)?;
        let input_vertex_count = mesh.vertex_count();
        let mut face_map: Vec<u32> = (0..mesh.face_count() as u32).collect();
        let mut ancestor: HashMap<[u32; 2], [u32; 2]> = HashMap::new();
        let mut refinements = Vec::new();
        let mut round = 0;
        loop {
            let (faces, edges) = build_faces_edges(&mesh, &normals, &face_map, options)?;
            let hull = SimplicialHull {
                mesh,
                normals,
                faces,
                edges,
                face_map,
                input_vertex_count,
                refinements,
                options: options.clone(),
            };
            if !options.check_intersections {
                return Ok(hull);
            }
            let hits = hull.intersections();
            if hits.is_empty() {
                return Ok(hull);
            }
            if std::env::var_os("HULL_DEBUG").is_some() {
                eprintln!("round {round}: {} hits, faces {}", hits.len(), hull.faces.len());
                for h in hits.iter().take(6) {
                    eprintln!("   {:?} {:?} / {:?} {:?} depth {:.3e}", h.first.element, h.first.side, h.second.element, h.second.side, h.depth);
                }
            }
            let mut splits: Vec<[u32; 2]> = Vec::new();
            for hit in &hits {
                for e in hull.edges_to_refine(hit) {
                    let v = hull.edges[e as usize].vertices;
                    if !splits.contains(&key(v[0], v[1])) {
                        splits.push(key(v[0], v[1]));
                    }
                }
            }
            if round == options.max_refinement_rounds {
                let hit = &hits[0];
                let e = hull.edges_to_refine(hit)[0];
                let [a, b] = hull.edges[e as usize].vertices;
                return Err(HullError::UnresolvedIntersection {
                    edge: ancestor.get(&key(a, b)).copied().unwrap_or(key(a, b)),
                    faces: [hull.input_face_of(hit.first.element), hull.input_face_of(hit.second.element)],
                    rounds: round,
                });
            }
            let SimplicialHull {
                mesh: m,
                normals: n,
                face_map: fm,
                refinements: r,
                ..
            } = hull;
            (mesh, normals, face_map, refinements) = (m, n, fm, r);
            for [a, b] in splits {
                if mesh.topology().find_edge(a, b).is_none() {
                    continue; // already split this round
                }
                let input_edge = ancestor.get(&[a, b]).copied().unwrap_or([a, b]);
                let refined = butterfly_refine_edge(&mesh, a, b)?;
                let mv = refined.new_vertex;
                face_map = refined.face_parent.iter().map(|&f| face_map[f as usize]).collect();
                mesh = refined.mesh;
                normals.push(new_vertex_normal(&mesh, mv));
                for &w in mesh.one_ring(mv).map(|r| r.neighbors).unwrap_or_default().iter() {
                    ancestor.insert(key(mv, w), input_edge);
                }
                refinements.push(Refinement {
                    round,
                    edge: [a, b],
                    input_edge,
                    new_vertex: mv,
                });
            }
            round += 1;
        }
    }

    /// The input face a tetrahedron's element lies in (for an edge: its face `[p_i p_j p_k]`).
    fn input_face_of(&self, e: Element) -> u32 {
        match e {
            Element::Face(f) => self.face_map[f as usize],
            Element::Edge(e) => self.face_map[self.edges[e as usize].face_k as usize],
        }
    }

    /// The edges of `element` (one for an edge, three for a face).
    fn element_edges(&self, e: Element) -> Vec<u32> {
        match e {
            Element::Face(f) => self.faces[f as usize].edges.to_vec(),
            Element::Edge(e) => vec![e],
        }
    }

    fn edge_length(&self, e: u32) -> f64 {
        let [a, b] = self.edges[e as usize].vertices;
        self.mesh.positions()[a as usize].distance(self.mesh.positions()[b as usize])
    }

    /// The edges to split for an intersecting pair: their shared edge, else the longest edge of
    /// each element.
    fn edges_to_refine(&self, hit: &Intersection) -> Vec<u32> {
        let ea = self.element_edges(hit.first.element);
        let eb = self.element_edges(hit.second.element);
        if let Some(&e) = ea.iter().find(|e| eb.contains(e)) {
            return vec![e];
        }
        let longest = |es: &[u32]| {
            es.iter()
                .copied()
                .max_by(|&x, &y| self.edge_length(x).total_cmp(&self.edge_length(y)))
                .unwrap_or(0)
        };
        let (x, y) = (longest(&ea), longest(&eb));
        if x == y { vec![x] } else { vec![x, y] }
    }

    /// Every tetrahedron of Σ: face tetrahedra in face order (positive before negative), then
    /// edge tetrahedra in edge order.
    pub fn tetrahedra(&self) -> Vec<HullTetrahedron> {
        let mut out = Vec::new();
        for (f, face) in self.faces.iter().enumerate() {
            for t in face.positive.iter().chain(face.negative.iter()) {
                out.push(HullTetrahedron {
                    element: Element::Face(f as u32),
                    side: t.side,
                    vertices: *t.tetrahedron.vertices(),
                });
            }
        }
        for (e, edge) in self.edges.iter().enumerate() {
            for t in edge.positive.iter().chain(edge.negative.iter()) {
                out.push(HullTetrahedron {
                    element: Element::Edge(e as u32),
                    side: t.side,
                    vertices: *t.tetrahedron.vertices(),
                });
            }
        }
        out
    }

    /// All pairs of tetrahedra of Σ whose interiors overlap by more than
    /// [`HullOptions::overlap_tolerance`] — adjacent or not. Candidate pairs come from a
    /// bounding-volume hierarchy over the tetrahedra's boxes; each candidate is decided by
    /// [`crate::overlap_depth`]. Empty for a valid hull.
    pub fn intersections(&self) -> Vec<Intersection> {
        let tets = self.tetrahedra();
        let boxes = tets
            .iter()
            .map(|t| {
                let (mut lo, mut hi) = (t.vertices[0], t.vertices[0]);
                for v in &t.vertices[1..] {
                    lo = lo.min(*v);
                    hi = hi.max(*v);
                }
                (lo, hi)
            })
            .collect();
        let bvh = Bvh::new(boxes);
        let mut out = Vec::new();
        for (i, j) in bvh.pairs() {
            let (a, b) = (&tets[i as usize], &tets[j as usize]);
            let depth = overlap_depth(&a.vertices, &b.vertices);
            if depth > self.options.overlap_tolerance {
                out.push(Intersection {
                    first: *a,
                    second: *b,
                    depth,
                });
            }
        }
        out
    }

    /// The (possibly refined) mesh the hull is built on. Vertices `0..input_vertex_count()` are
    /// the input vertices, unchanged; later ones were inserted by refinement.
    pub fn mesh(&self) -> &TriMesh {
        &self.mesh
    }
    /// Per-vertex normals of [`SimplicialHull::mesh`]: the input normals, then the Loop limit
    /// normals of inserted vertices.
    pub fn normals(&self) -> &[DVec3] {
        &self.normals
    }
    /// Per face of [`SimplicialHull::mesh`] (same index as [`SimplicialHull::faces`]).
    pub fn faces(&self) -> &[HullFace] {
        &self.faces
    }
    /// Per edge of [`SimplicialHull::mesh`], indexed by the mesh topology's edge id.
    pub fn edges(&self) -> &[HullEdge] {
        &self.edges
    }
    /// The edge joining vertices `a` and `b`, if any.
    pub fn edge_between(&self, a: u32, b: u32) -> Option<&HullEdge> {
        self.mesh
            .topology()
            .find_edge(a, b)
            .map(|e| &self.edges[e as usize])
    }
    /// For each face of [`SimplicialHull::mesh`], the input face it lies in.
    pub fn face_map(&self) -> &[u32] {
        &self.face_map
    }
    /// Number of vertices of the input mesh.
    pub fn input_vertex_count(&self) -> usize {
        self.input_vertex_count
    }
    /// The local refinement steps done, in order (empty when the input needed none).
    pub fn refinements(&self) -> &[Refinement] {
        &self.refinements
    }
    /// The options the hull was built with.
    pub fn options(&self) -> &HullOptions {
        &self.options
    }
}

/// The normal given to a vertex inserted by refinement: the unit normal of the limit surface of
/// Loop's scheme on the refined mesh (the paper's choice of normals, §3), turned to the faces'
/// side; the area-weighted normal where the Loop normal is undefined.
fn new_vertex_normal(mesh: &TriMesh, v: u32) -> DVec3 {
    let mut area = DVec3::ZERO;
    for f in mesh.topology().vertex_faces(v) {
        area += mesh.face_normal(f as usize);
    }
    let l = loop_limit_normal(mesh, v).unwrap_or(DVec3::ZERO);
    let l = if l.length() > 0.0 && l.is_finite() { l.normalize() } else { area.normalize_or_zero() };
    if l.dot(area) < 0.0 { -l } else { l }
}
