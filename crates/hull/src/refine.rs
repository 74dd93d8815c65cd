//! Local refinement of the mesh where hull tetrahedra intersect (§3.1).
//!
//! The paper "locally modifies the common edge by the Butterfly subdivision scheme … the local
//! subdivision may take several steps". Splitting only the common edge does not work: it cuts
//! the two faces into slivers that keep their far vertex and therefore their tall tetrahedra
//! (on a coarse `sin·sin` height field the intersections never went away that way). So each
//! face of an intersecting pair is *bisected by its longest edge*, with Rivara's longest-edge
//! propagation path (LEPP): walk to the neighbour across the longest edge until an edge is
//! longest in both its faces (or on the boundary), split that edge, and repeat until the face
//! itself has been split. Every split puts the new vertex at the modified Butterfly edge point
//! (`algesurf_mesh::butterfly_refine_edge`) — pulled towards the edge's midpoint where that
//! would fold a face against a vertex normal (`crate::edge_point`) — splits the edge in both
//! its faces (conforming, no T-junctions), and leaves all other vertices where they are. Longest-edge bisection keeps the
//! triangles' angles bounded away from zero, so repeated rounds shrink the faces in every
//! direction.

use crate::HullError;
use crate::edge_point::fold_safe_split;
use crate::edit::EditMesh;
use crate::simplicial::Refinement;
use algesurf_mesh::TriMesh;
use glam::DVec3;
use std::collections::HashMap;

/// The mesh being refined, with its per-vertex and per-face bookkeeping.
pub(crate) struct RefineState {
    pub(crate) mesh: TriMesh,
    pub(crate) normals: Vec<DVec3>,
    pub(crate) face_map: Vec<u32>,
    pub(crate) refinements: Vec<Refinement>,
    pub(crate) input_vertex_count: usize,
    /// For edges incident to an inserted vertex: the input edge whose refinement made them.
    pub(crate) ancestor: HashMap<[u32; 2], [u32; 2]>,
    /// The mesh open to splits, made from `mesh` at the first split and kept from round to
    /// round (building its faces-per-vertex lists again each round took a serial 8 ms on the
    /// bunny); `mesh` is stale while `edited` is set (see [`RefineState::finish_round`]).
    edit: Option<EditMesh>,
    /// Whether `edit` has splits that `mesh` does not have yet.
    edited: bool,
    /// What the splits since the last [`RefineState::take_changes`] changed.
    changes: Changes,
}

/// What a round's splits changed: the faces they split (kept ids, new corners) or appended,
/// and the edges they removed (each split edge, by its key). A refinement round rebuilds only
/// these (`crate::simplicial::rounds`).
#[derive(Clone, Debug, Default)]
pub(crate) struct Changes {
    /// Changed and appended face ids, in the order the splits made them (with repeats).
    pub(crate) faces: Vec<u32>,
    /// The split edges' keys (`[smaller, larger]` vertex id).
    pub(crate) removed_edges: Vec<[u32; 2]>,
}

pub(crate) fn key(a: u32, b: u32) -> [u32; 2] {
    if a < b { [a, b] } else { [b, a] }
}

/// A total order on edges: longer first, ties broken by the vertex ids, so that the LEPP walk
/// strictly climbs and terminates.
fn edge_rank(p: &[DVec3], a: u32, b: u32) -> (f64, [u32; 2]) {
    (p[a as usize].distance_squared(p[b as usize]), key(a, b))
}

fn longest_edge(mesh: &EditMesh, f: u32) -> [u32; 2] {
    let t = mesh.triangles()[f as usize];
    let p = mesh.positions();
    let mut best = [t[0], t[1]];
    for c in 1..3 {
        let (a, b) = (t[c], t[(c + 1) % 3]);
        let (r, s) = (edge_rank(p, a, b), edge_rank(p, best[0], best[1]));
        if r.0 > s.0 || (r.0 == s.0 && r.1 > s.1) {
            best = [a, b];
        }
    }
    best
}

impl RefineState {
    pub(crate) fn new(mesh: TriMesh, normals: Vec<DVec3>) -> RefineState {
        RefineState {
            input_vertex_count: mesh.vertex_count(),
            face_map: (0..mesh.face_count() as u32).collect(),
            mesh,
            normals,
            refinements: Vec::new(),
            ancestor: HashMap::new(),
            edit: None,
            edited: false,
            changes: Changes::default(),
        }
    }

    /// The state a hull was left in (see `SimplicialHull::refine_faces`).
    pub(crate) fn from_parts(
        mesh: TriMesh,
        normals: Vec<DVec3>,
        face_map: Vec<u32>,
        refinements: Vec<Refinement>,
        input_vertex_count: usize,
        ancestor: HashMap<[u32; 2], [u32; 2]>,
    ) -> RefineState {
        RefineState {
            mesh,
            normals,
            face_map,
            refinements,
            input_vertex_count,
            ancestor,
            edit: None,
            edited: false,
            changes: Changes::default(),
        }
    }

    /// The input edge an edge of the current mesh comes from. An edge between two input
    /// vertices is always an input edge (splits only create edges at the new vertex).
    pub(crate) fn input_edge(&self, a: u32, b: u32) -> [u32; 2] {
        self.ancestor.get(&key(a, b)).copied().unwrap_or(key(a, b))
    }

    /// Ends a round of splits: the mesh is rebuilt from the edits once.
    pub(crate) fn finish_round(&mut self) -> Result<(), HullError> {
        if let Some(mesh) = self.pending_edit().map(EditMesh::to_mesh).transpose()? {
            self.mesh = mesh;
            self.edited = false;
        }
        Ok(())
    }

    /// The edited mesh while it has splits that `mesh` does not have yet.
    fn pending_edit(&self) -> Option<&EditMesh> {
        self.edit.as_ref().filter(|_| self.edited)
    }

    /// The current positions and triangles: the edited mesh's while splits are pending
    /// ([`RefineState::finish_round`] has not run since), else `mesh`'s.
    pub(crate) fn current(&self) -> (&[DVec3], &[[u32; 3]]) {
        match self.pending_edit() {
            Some(edit) => (edit.positions(), edit.triangles()),
            None => (self.mesh.positions(), self.mesh.triangles()),
        }
    }

    /// The faces on edge `a`–`b` of the current mesh, ascending (see
    /// [`RefineState::current`]); only while splits are pending.
    pub(crate) fn edge_faces(&self, a: u32, b: u32) -> Option<Vec<u32>> {
        self.pending_edit().map(|edit| edit.edge_faces(a, b))
    }

    /// What the splits since the last call changed.
    pub(crate) fn take_changes(&mut self) -> Changes {
        std::mem::take(&mut self.changes)
    }

    fn edit(&mut self) -> &mut EditMesh {
        self.edited = true;
        self.edit.get_or_insert_with(|| EditMesh::new(&self.mesh))
    }

    /// Splits edge `a`–`b` and gives the new vertex its normal, without making any face
    /// invalid (see [`fold_safe_split`], run on the faces at `a` and `b`, which hold all it
    /// reads).
    fn split(&mut self, a: u32, b: u32, round: usize) -> Result<(), HullError> {
        let input_edge = self.input_edge(a, b);
        let cut = self.edit().cut_out(a, b)?;
        let local_normals: Vec<DVec3> = cut
            .global
            .iter()
            .map(|&v| self.normals[v as usize])
            .collect();
        let (refined, normal) = fold_safe_split(&cut.mesh, &local_normals, cut.a, cut.b)?;
        let point = refined.mesh.positions()[refined.new_vertex as usize];
        if !point.is_finite() {
            return Err(algesurf_mesh::MeshError::NonFinite(format!("edge point {point}")).into());
        }
        let edit = self.edit();
        let first_new = edit.triangles().len() as u32;
        let (m, split) = edit.split_edge(a, b, point);
        let appended = first_new..edit.triangles().len() as u32;
        let mut neighbours = vec![a, b];
        for &f in &split {
            let t = edit.triangles()[f as usize];
            neighbours.extend(t.iter().copied().filter(|&v| v != m && v != a && v != b));
        }
        self.changes
            .faces
            .extend(split.iter().copied().chain(appended));
        self.changes.removed_edges.push(key(a, b));
        self.face_map.extend(
            split
                .iter()
                .map(|&f| self.face_map[f as usize])
                .collect::<Vec<_>>(),
        );
        self.normals.push(normal);
        for w in neighbours {
            self.ancestor.insert(key(m, w), input_edge);
        }
        self.refinements.push(Refinement {
            round,
            edge: [a, b],
            input_edge,
            new_vertex: m,
        });
        Ok(())
    }

    /// Bisects face `f` (current id) by longest-edge propagation; a no-op when `f` no longer
    /// has the corners `corners` (an earlier bisection in this round split it already).
    pub(crate) fn bisect_face(
        &mut self,
        f: u32,
        corners: [u32; 3],
        round: usize,
    ) -> Result<(), HullError> {
        // Each pass splits one edge; the path climbs a strict order, so a pass is finite, and
        // each pass either splits `f` or a face on its path, which a few passes exhaust.
        for _ in 0..64 {
            let edit = self.edit();
            if edit.triangles().get(f as usize) != Some(&corners) {
                return Ok(());
            }
            let mut cur = f;
            let terminal = loop {
                let [a, b] = longest_edge(edit, cur);
                match edit.edge_faces(a, b).into_iter().find(|&g| g != cur) {
                    Some(g) if key_eq(longest_edge(edit, g), [a, b]) => break [a, b],
                    Some(g) => cur = g,
                    None => break [a, b],
                }
            };
            self.split(terminal[0], terminal[1], round)?;
        }
        Ok(())
    }
}

fn key_eq(x: [u32; 2], y: [u32; 2]) -> bool {
    key(x[0], x[1]) == key(y[0], y[1])
}
