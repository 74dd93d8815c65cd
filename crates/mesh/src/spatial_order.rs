//! A mesh's faces and vertices numbered in spatial order: what neighbours in space are,
//! neighbours in memory are.
//!
//! A scanned mesh (the Stanford bunny's OBJ) lists its faces in no spatial order: consecutive
//! faces' smallest vertex ids differ by ~1 400 in the median. Every loop that walks a mesh's
//! edges and reads the records of the two faces of each edge then misses the cache on most
//! reads. [`SpatialOrder`] renumbers the faces along the Z-order curve of their centroids
//! ([`crate::morton::morton_order`]) and the vertices in the order those faces first use them,
//! so that edges, numbered by their vertex pairs ([`Topology`](crate::Topology)), come in
//! spatial order too.
//!
//! ```
//! use algesurf_mesh::{shapes, spatial_order::SpatialOrder};
//! let mesh = shapes::icosphere(2);
//! let order = SpatialOrder::of(&mesh);
//! let ordered = order.apply(&mesh)?;
//! // The same triangles, renumbered.
//! for (new, &old) in order.faces().iter().enumerate() {
//!     let before = mesh.triangles()[old as usize].map(|v| mesh.positions()[v as usize]);
//!     let after = ordered.triangles()[new].map(|v| ordered.positions()[v as usize]);
//!     assert_eq!(before, after);
//! }
//! // Values per vertex follow their vertices.
//! let heights: Vec<f64> = mesh.positions().iter().map(|p| p.z).collect();
//! let moved = order.vertex_values(&heights);
//! assert!(ordered.positions().iter().zip(&moved).all(|(p, &z)| p.z == z));
//! # Ok::<(), algesurf_mesh::MeshError>(())
//! ```

use crate::morton::morton_order;
use crate::{MeshError, TriMesh};
use glam::DVec3;
use rayon::prelude::*;

/// A renumbering of a [`TriMesh`]'s faces and vertices (see the module docs): faces sorted
/// along the Z-order curve of their centroids, vertices numbered by their first use in that
/// face order (vertices no face uses last, in their old order).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SpatialOrder {
    /// `faces[new] = old`.
    faces: Vec<u32>,
    /// `vertices[new] = old`.
    vertices: Vec<u32>,
    /// `new_vertex[old] = new`.
    new_vertex: Vec<u32>,
}

impl SpatialOrder {
    /// The spatial order of `mesh`'s faces and vertices. Deterministic: it depends only on the
    /// positions and triangles.
    pub fn of(mesh: &TriMesh) -> SpatialOrder {
        let centroids: Vec<DVec3> = (0..mesh.face_count())
            .into_par_iter()
            .map(|f| {
                let [a, b, c] = mesh.triangle_points(f);
                (a + b + c) / 3.0
            })
            .collect();
        let faces = morton_order(&centroids);
        const UNSEEN: u32 = u32::MAX;
        let mut new_vertex = vec![UNSEEN; mesh.vertex_count()];
        let mut vertices = Vec::with_capacity(mesh.vertex_count());
        for &f in &faces {
            for v in mesh.triangles()[f as usize] {
                if new_vertex[v as usize] == UNSEEN {
                    new_vertex[v as usize] = vertices.len() as u32;
                    vertices.push(v);
                }
            }
        }
        for (v, new) in new_vertex.iter_mut().enumerate() {
            if *new == UNSEEN {
                *new = vertices.len() as u32;
                vertices.push(v as u32);
            }
        }
        SpatialOrder {
            faces,
            vertices,
            new_vertex,
        }
    }

    /// The old id of each new face: `faces()[new] = old`.
    pub fn faces(&self) -> &[u32] {
        &self.faces
    }

    /// The old id of each new vertex: `vertices()[new] = old`.
    pub fn vertices(&self) -> &[u32] {
        &self.vertices
    }

    /// The new id of old vertex `old`.
    ///
    /// # Panics
    /// If `old` is not a vertex of the mesh the order was made for.
    pub fn new_vertex(&self, old: u32) -> u32 {
        self.new_vertex[old as usize]
    }

    /// Per-vertex values (in the old numbering) moved to the new numbering.
    ///
    /// # Panics
    /// If `old_values` has fewer entries than the mesh has vertices.
    pub fn vertex_values<T: Copy + Send + Sync>(&self, old_values: &[T]) -> Vec<T> {
        self.vertices
            .par_iter()
            .map(|&v| old_values[v as usize])
            .collect()
    }

    /// The mesh renumbered: new face `f` is old face `faces()[f]` with its corners (in the same
    /// cyclic order, so the same orientation) renamed, its source face kept; new vertex `v` has
    /// the position and file normal of old vertex `vertices()[v]`. The topology is built anew
    /// for the new numbering.
    ///
    /// # Errors
    /// [`MeshError::LengthMismatch`] when `mesh` has another vertex or face count than the
    /// mesh the order was made for.
    pub fn apply(&self, mesh: &TriMesh) -> Result<TriMesh, MeshError> {
        for (what, expected, found) in [
            ("vertices", self.vertices.len(), mesh.vertex_count()),
            ("faces", self.faces.len(), mesh.face_count()),
        ] {
            if expected != found {
                return Err(MeshError::LengthMismatch {
                    what,
                    expected,
                    found,
                });
            }
        }
        let triangles: Vec<[u32; 3]> = self
            .faces
            .par_iter()
            .map(|&f| mesh.triangles()[f as usize].map(|v| self.new_vertex[v as usize]))
            .collect();
        let sources: Vec<u32> = self
            .faces
            .iter()
            .map(|&f| mesh.source_faces()[f as usize])
            .collect();
        let mut ordered =
            TriMesh::with_source_faces(self.vertex_values(mesh.positions()), triangles, sources)?;
        ordered.set_file_normals(mesh.file_normals().map(|n| self.vertex_values(n)))?;
        Ok(ordered)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes;
    use crate::test_rng::Lcg;

    /// A mesh whose faces and vertices are numbered at random (a shuffled icosphere).
    fn shuffled(level: u32, seed: u64) -> TriMesh {
        let mesh = shapes::icosphere(level);
        let mut rng = Lcg(seed);
        let mut below = |n: usize| ((rng.next() * n as f64) as usize).min(n - 1);
        let mut perm: Vec<u32> = (0..mesh.vertex_count() as u32).collect();
        let mut faces: Vec<[u32; 3]> = mesh.triangles().to_vec();
        for k in (1..perm.len()).rev() {
            perm.swap(k, below(k + 1));
        }
        for k in (1..faces.len()).rev() {
            faces.swap(k, below(k + 1));
        }
        let mut positions = vec![DVec3::ZERO; mesh.vertex_count()];
        for (old, &new) in perm.iter().enumerate() {
            positions[new as usize] = mesh.positions()[old];
        }
        let faces = faces
            .into_iter()
            .map(|t| t.map(|v| perm[v as usize]))
            .collect();
        TriMesh::new(positions, faces).unwrap()
    }

    /// Mean distance between the centroids of consecutive faces.
    fn mean_step(mesh: &TriMesh) -> f64 {
        let c = |f: usize| {
            let [a, b, c] = mesh.triangle_points(f);
            (a + b + c) / 3.0
        };
        let n = mesh.face_count();
        (1..n).map(|f| c(f).distance(c(f - 1))).sum::<f64>() / (n - 1) as f64
    }

    #[test]
    fn the_orders_are_permutations_and_the_mesh_is_the_same_surface() {
        let mesh = shuffled(3, 7);
        let order = SpatialOrder::of(&mesh);
        let ordered = order.apply(&mesh).unwrap();
        let mut faces = order.faces().to_vec();
        faces.sort_unstable();
        assert!(faces.iter().copied().eq(0..mesh.face_count() as u32));
        let mut vertices = order.vertices().to_vec();
        vertices.sort_unstable();
        assert!(vertices.iter().copied().eq(0..mesh.vertex_count() as u32));
        for (new, &old) in order.vertices().iter().enumerate() {
            assert_eq!(order.new_vertex(old), new as u32);
            assert_eq!(ordered.positions()[new], mesh.positions()[old as usize]);
        }
        for (new, &old) in order.faces().iter().enumerate() {
            let renamed = mesh.triangles()[old as usize].map(|v| order.new_vertex(v));
            assert_eq!(
                ordered.triangles()[new],
                renamed,
                "same corners, same cyclic order"
            );
            assert_eq!(ordered.source_faces()[new], old);
        }
        assert_eq!(ordered.euler_characteristic(), mesh.euler_characteristic());
        // The same volume, summed in another order.
        let (a, b) = (ordered.signed_volume(), mesh.signed_volume());
        assert!(a > 0.0 && (a - b).abs() <= 1e-12 * b, "{a} against {b}");
    }

    #[test]
    fn consecutive_faces_are_near_each_other_after_ordering() {
        let mesh = shuffled(4, 11);
        let ordered = SpatialOrder::of(&mesh).apply(&mesh).unwrap();
        let (before, after) = (mean_step(&mesh), mean_step(&ordered));
        // The shuffled sphere's consecutive faces are ~1.3 apart (random points on a unit
        // sphere); along the curve they are neighbours, a few edge lengths (~0.08) apart.
        assert!(after < before / 5.0, "mean step {before} → {after}");
    }

    #[test]
    fn vertices_are_numbered_by_first_use_and_unused_ones_come_last() {
        let mut positions = shapes::icosphere(0).positions().to_vec();
        positions.push(DVec3::splat(9.0)); // no face uses vertex 12 (the icosahedron has 0–11)
        let mesh = TriMesh::new(positions, shapes::icosphere(0).triangles().to_vec()).unwrap();
        let order = SpatialOrder::of(&mesh);
        assert_eq!(*order.vertices().last().unwrap(), 12);
        let ordered = order.apply(&mesh).unwrap();
        let mut next = 0;
        for t in ordered.triangles() {
            for &v in t {
                assert!(v <= next, "vertex {v} used before {next}");
                if v == next {
                    next += 1;
                }
            }
        }
        assert_eq!(next, 12);
    }

    #[test]
    fn file_normals_follow_their_vertices() {
        let mut mesh = shuffled(1, 3);
        let normals: Vec<DVec3> = mesh.positions().iter().map(|p| p.normalize()).collect();
        mesh.set_file_normals(Some(normals)).unwrap();
        let ordered = SpatialOrder::of(&mesh).apply(&mesh).unwrap();
        let n = ordered.file_normals().unwrap();
        for (p, n) in ordered.positions().iter().zip(n) {
            assert_eq!(p.normalize(), *n);
        }
    }

    #[test]
    fn another_mesh_is_refused() {
        let order = SpatialOrder::of(&shapes::icosphere(1));
        assert!(matches!(
            order.apply(&shapes::icosphere(2)),
            Err(MeshError::LengthMismatch {
                what: "vertices",
                ..
            })
        ));
    }
}
