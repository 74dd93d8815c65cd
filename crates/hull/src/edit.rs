//! A triangle mesh open to local edge splits, for hull refinement.
//!
//! [`algesurf_mesh::split_edge`] returns a new [`TriMesh`] (positions, triangles and topology
//! copied and rebuilt), which made every split of a refinement round cost `O(n)`: 12 ms a
//! split on the 70 k-face Stanford bunny, and most of the hull stage on Suzanne (5 272 splits).
//! Here a round's splits edit the triangles in place and keep the faces around each vertex up
//! to date; each split's Butterfly point, Loop normal and fold test run on a cut-out of the
//! faces at the edge's two ends, which holds everything those read (the Butterfly stencils
//! read the ends' one-rings and the wings across their faces' edges, all faces at an end), and
//! the [`TriMesh`] is rebuilt once per round. Faces, vertices and their ids come out as
//! `split_edge` made them; a Butterfly point can differ from the whole-mesh computation in
//! the last bit, because the stencil's terms are summed in another order (measured on the
//! cow: 2 215 splits in 16 rounds either way, points equal to 1 ulp; the Stanford bunny's
//! output is byte-identical).

use algesurf_mesh::{MeshError, TriMesh};
use glam::DVec3;

/// Positions, triangles (with their source faces) and the faces at each vertex.
#[derive(Clone, Debug)]
pub(crate) struct EditMesh {
    positions: Vec<DVec3>,
    triangles: Vec<[u32; 3]>,
    source: Vec<u32>,
    /// Per vertex, the faces that use it, ascending.
    vertex_faces: Vec<Vec<u32>>,
}

/// The faces at both ends of an edge as a mesh of their own (ascending face ids, so every
/// order the topology derives from ids is the whole mesh's), with the global id of each local
/// vertex.
pub(crate) struct CutOut {
    pub(crate) mesh: TriMesh,
    pub(crate) global: Vec<u32>,
    pub(crate) a: u32,
    pub(crate) b: u32,
}

impl EditMesh {
    pub(crate) fn new(mesh: &TriMesh) -> EditMesh {
        let mut vertex_faces = vec![Vec::new(); mesh.vertex_count()];
        for (f, t) in mesh.triangles().iter().enumerate() {
            for &v in t {
                vertex_faces[v as usize].push(f as u32);
            }
        }
        EditMesh {
            positions: mesh.positions().to_vec(),
            triangles: mesh.triangles().to_vec(),
            source: mesh.source_faces().to_vec(),
            vertex_faces,
        }
    }

    /// The mesh as a [`TriMesh`] (topology rebuilt).
    pub(crate) fn to_mesh(&self) -> Result<TriMesh, MeshError> {
        TriMesh::with_source_faces(
            self.positions.clone(),
            self.triangles.clone(),
            self.source.clone(),
        )
    }

    pub(crate) fn positions(&self) -> &[DVec3] {
        &self.positions
    }

    pub(crate) fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// The faces on edge `a`–`b`, ascending.
    pub(crate) fn edge_faces(&self, a: u32, b: u32) -> Vec<u32> {
        self.vertex_faces[a as usize]
            .iter()
            .copied()
            .filter(|&f| self.triangles[f as usize].contains(&b))
            .collect()
    }

    /// The faces at `a` or `b` as a [`CutOut`]; [`MeshError::NoSuchEdge`] if `a`–`b` is not
    /// an edge.
    pub(crate) fn cut_out(&self, a: u32, b: u32) -> Result<CutOut, MeshError> {
        let (fa, fb) = (
            &self.vertex_faces[a as usize],
            &self.vertex_faces[b as usize],
        );
        if a == b || fa.iter().all(|f| !fb.contains(f)) {
            return Err(MeshError::NoSuchEdge(a, b));
        }
        let mut faces: Vec<u32> = fa.iter().chain(fb).copied().collect();
        faces.sort_unstable();
        faces.dedup();
        let mut local = std::collections::HashMap::new();
        let mut global = Vec::new();
        let mut id = |v: u32| -> u32 {
            *local.entry(v).or_insert_with(|| {
                global.push(v);
                (global.len() - 1) as u32
            })
        };
        let (la, lb) = (id(a), id(b));
        let triangles: Vec<[u32; 3]> = faces
            .iter()
            .map(|&f| self.triangles[f as usize].map(&mut id))
            .collect();
        let positions = global.iter().map(|&v| self.positions[v as usize]).collect();
        Ok(CutOut {
            mesh: TriMesh::new(positions, triangles)?,
            global,
            a: la,
            b: lb,
        })
    }

    /// Splits edge `a`–`b` at `point` as [`algesurf_mesh::split_edge`] does: each face
    /// `(u, v, w)` on it (ascending, `u → v` the edge) becomes `(u, m, w)`, keeping its id, and
    /// `(m, v, w)`, appended. Returns `m` and the split faces in the order their halves were
    /// appended.
    pub(crate) fn split_edge(&mut self, a: u32, b: u32, point: DVec3) -> (u32, Vec<u32>) {
        let m = self.positions.len() as u32;
        self.positions.push(point);
        self.vertex_faces.push(Vec::new());
        let faces = self.edge_faces(a, b);
        for &f in &faces {
            let t = self.triangles[f as usize];
            let k = (0..3)
                .find(|&k| {
                    let (u, v) = (t[k], t[(k + 1) % 3]);
                    (u == a && v == b) || (u == b && v == a)
                })
                .expect("a face on the edge has it as a side");
            let (u, v, w) = (t[k], t[(k + 1) % 3], t[(k + 2) % 3]);
            let g = self.triangles.len() as u32;
            self.triangles[f as usize] = [u, m, w];
            self.triangles.push([m, v, w]);
            self.source.push(self.source[f as usize]);
            // `v` leaves `f` for `g`; `m` and `w` gain `g` (ids ascend: `g` is the largest).
            let vf = &mut self.vertex_faces[v as usize];
            vf.retain(|&x| x != f);
            vf.push(g);
            self.vertex_faces[w as usize].push(g);
            let mf = &mut self.vertex_faces[m as usize];
            mf.push(f);
            mf.push(g);
        }
        self.vertex_faces[m as usize].sort_unstable();
        (m, faces)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use algesurf_mesh::{butterfly_refine_edge, shapes, split_edge};

    /// A sequence of in-place splits gives the triangles, positions and source faces that
    /// `split_edge` gives on rebuilt meshes, and each cut-out's Butterfly point is the whole
    /// mesh's to rounding.
    #[test]
    fn in_place_splits_match_split_edge() {
        let mut whole = shapes::torus(10, 6, 1.0, 0.4);
        let mut edit = EditMesh::new(&whole);
        for step in 0..40u32 {
            let f = (step * 7) as usize % whole.face_count();
            let t = whole.triangles()[f];
            let (a, b) = (t[(step % 3) as usize], t[((step + 1) % 3) as usize]);
            let cut = edit.cut_out(a, b).unwrap();
            let local = butterfly_refine_edge(&cut.mesh, cut.a, cut.b).unwrap();
            let point = local.mesh.positions()[local.new_vertex as usize];
            let global = butterfly_refine_edge(&whole, a, b).unwrap();
            let expected = global.mesh.positions()[global.new_vertex as usize];
            assert!(
                (point - expected).length() < 1e-14,
                "step {step}: {point} vs {expected}"
            );
            let (m, split) = edit.split_edge(a, b, point);
            let reference = split_edge(&whole, a, b, point).unwrap();
            assert_eq!(m, reference.new_vertex);
            let appended = &reference.face_parent[whole.face_count()..];
            assert_eq!(split.as_slice(), appended);
            whole = reference.mesh;
            assert_eq!(edit.triangles(), whole.triangles());
            assert_eq!(edit.positions(), whole.positions());
            let rebuilt = edit.to_mesh().unwrap();
            assert_eq!(rebuilt.source_faces(), whole.source_faces());
            for v in 0..whole.vertex_count() as u32 {
                let faces: Vec<u32> = whole.topology().vertex_faces(v).collect();
                let mut sorted = faces.clone();
                sorted.sort_unstable();
                assert_eq!(edit.vertex_faces[v as usize], sorted, "vertex {v}");
            }
        }
        assert!(matches!(
            edit.cut_out(0, 0),
            Err(MeshError::NoSuchEdge(0, 0))
        ));
    }
}
