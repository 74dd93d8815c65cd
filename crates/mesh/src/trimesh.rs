//! The triangle mesh with full adjacency.

use crate::geometry::{Aabb, signed_volume, triangle_normal};
use crate::topology::{Component, Fan, Topology};
use crate::triangulate::triangulate_polygon;
use crate::{MeshError, PolygonMesh};
use glam::DVec3;

/// A triangle mesh with full adjacency ([`Topology`]).
///
/// Invariants (checked by the constructors): every index is in range and every triangle has
/// three distinct vertices. Geometrically degenerate (zero-area) triangles, non-manifold
/// edges/vertices and inconsistent orientation are allowed and can be queried; the
/// operations that need a manifold (subdivision, Loop normals) say so in their errors.
#[derive(Clone, Debug)]
pub struct TriMesh {
    positions: Vec<DVec3>,
    triangles: Vec<[u32; 3]>,
    normals: Option<Vec<DVec3>>,
    source_faces: Vec<u32>,
    topology: Topology,
}

impl TriMesh {
    /// A triangle mesh from positions and triangles. Each triangle is its own source face.
    ///
    /// # Errors
    /// [`MeshError::IndexOutOfRange`] or [`MeshError::RepeatedVertex`] naming the triangle.
    pub fn new(positions: Vec<DVec3>, triangles: Vec<[u32; 3]>) -> Result<TriMesh, MeshError> {
        let source = (0..triangles.len() as u32).collect();
        TriMesh::with_source_faces(positions, triangles, source)
    }

    /// Like [`TriMesh::new`], with `source_faces[t]` the id of the polygon triangle `t` came
    /// from.
    pub fn with_source_faces(
        positions: Vec<DVec3>,
        triangles: Vec<[u32; 3]>,
        source_faces: Vec<u32>,
    ) -> Result<TriMesh, MeshError> {
        if source_faces.len() != triangles.len() {
            return Err(MeshError::LengthMismatch {
                what: "source faces",
                expected: triangles.len(),
                found: source_faces.len(),
            });
        }
        let topology = Topology::from_triangles(positions.len(), &triangles)?;
        Ok(TriMesh {
            positions,
            triangles,
            normals: None,
            source_faces,
            topology,
        })
    }

    /// The same positions, triangles and topology with each triangle its own source face and
    /// no file normals: what [`TriMesh::new`] gives on copies of this mesh's positions and
    /// triangles, without building the topology again (its arrays are copied; on the
    /// Stanford bunny 3 ms instead of 16).
    ///
    /// ```
    /// use algesurf_mesh::{shapes, TriMesh};
    /// let mesh = shapes::icosphere(1);
    /// let copy = mesh.plain_copy();
    /// let rebuilt = TriMesh::new(mesh.positions().to_vec(), mesh.triangles().to_vec()).unwrap();
    /// assert_eq!(copy.topology(), rebuilt.topology());
    /// assert_eq!(copy.source_faces(), rebuilt.source_faces());
    /// ```
    pub fn plain_copy(&self) -> TriMesh {
        TriMesh {
            positions: self.positions.clone(),
            triangles: self.triangles.clone(),
            normals: None,
            source_faces: (0..self.triangles.len() as u32).collect(),
            topology: self.topology.clone(),
        }
    }

    /// Converts a polygon mesh: polygons with more than three corners are triangulated by ear
    /// clipping in the plane of their Newell normal ([`triangulate_polygon`]); per-vertex
    /// normals are kept. [`TriMesh::source_faces`] maps each triangle to its polygon id.
    ///
    /// # Errors
    /// Polygons with out-of-range indices, fewer than three corners or repeated vertices are
    /// rejected with an error naming the polygon (run [`crate::repair()`] first for messy input).
    pub fn from_polygon_mesh(mesh: &PolygonMesh) -> Result<TriMesh, MeshError> {
        let nv = mesh.vertex_count();
        let mut tris = Vec::with_capacity(mesh.face_count());
        let mut src = Vec::with_capacity(mesh.face_count());
        let mut pts = Vec::new();
        for (f, face) in mesh.faces().enumerate() {
            if face.len() < 3 {
                return Err(MeshError::TooFewCorners {
                    face: f,
                    corners: face.len(),
                });
            }
            for (i, &v) in face.iter().enumerate() {
                if v as usize >= nv {
                    return Err(MeshError::IndexOutOfRange {
                        face: f,
                        corner: i,
                        index: v,
                        vertex_count: nv,
                    });
                }
                if face[..i].contains(&v) {
                    return Err(MeshError::RepeatedVertex {
                        face: f,
                        corners: [face[0], face[1], v],
                    });
                }
            }
            if face.len() == 3 {
                tris.push([face[0], face[1], face[2]]);
                src.push(f as u32);
                continue;
            }
            pts.clear();
            pts.extend(face.iter().map(|&v| mesh.positions[v as usize]));
            for t in triangulate_polygon(&pts) {
                tris.push([face[t[0]], face[t[1]], face[t[2]]]);
                src.push(f as u32);
            }
        }
        let mut m = TriMesh::with_source_faces(mesh.positions.clone(), tris, src)?;
        if let Some(n) = &mesh.normals
            && n.len() == nv
        {
            m.normals = Some(n.clone());
        }
        Ok(m)
    }

    /// Back to a polygon mesh of triangles (normals kept, no properties).
    pub fn to_polygon_mesh(&self) -> PolygonMesh {
        let mut m = PolygonMesh::from_triangles(self.positions.clone(), &self.triangles);
        m.normals = self.normals.clone();
        m
    }

    /// Vertex positions.
    pub fn positions(&self) -> &[DVec3] {
        &self.positions
    }
    /// Mutable vertex positions (the count cannot change, so the adjacency stays valid).
    pub fn positions_mut(&mut self) -> &mut [DVec3] {
        &mut self.positions
    }
    /// Triangles as vertex index triples.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }
    /// The per-vertex normals read from a file, if any.
    pub fn file_normals(&self) -> Option<&[DVec3]> {
        self.normals.as_deref()
    }
    /// Sets (or clears) the per-vertex normals carried with the mesh.
    ///
    /// # Errors
    /// [`MeshError::LengthMismatch`] when the count differs from the vertex count.
    pub fn set_file_normals(&mut self, normals: Option<Vec<DVec3>>) -> Result<(), MeshError> {
        if let Some(n) = &normals
            && n.len() != self.positions.len()
        {
            return Err(MeshError::LengthMismatch {
                what: "normals",
                expected: self.positions.len(),
                found: n.len(),
            });
        }
        self.normals = normals;
        Ok(())
    }
    /// For each triangle, the id of the source polygon it came from.
    pub fn source_faces(&self) -> &[u32] {
        &self.source_faces
    }
    /// The adjacency.
    pub fn topology(&self) -> &Topology {
        &self.topology
    }
    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }
    /// Number of triangles.
    pub fn face_count(&self) -> usize {
        self.triangles.len()
    }
    /// The three corner positions of triangle `f`.
    pub fn triangle_points(&self, f: usize) -> [DVec3; 3] {
        let t = self.triangles[f];
        [
            self.positions[t[0] as usize],
            self.positions[t[1] as usize],
            self.positions[t[2] as usize],
        ]
    }
    /// Twice the area vector of triangle `f` (its unnormalised normal).
    pub fn face_normal(&self, f: usize) -> DVec3 {
        let [a, b, c] = self.triangle_points(f);
        triangle_normal(a, b, c)
    }
    /// The bounding box of the finite positions.
    pub fn bounding_box(&self) -> Aabb {
        Aabb::from_points(&self.positions)
    }
    /// The one-ring of vertex `v` in cyclic order (`None` when unused or non-manifold).
    pub fn one_ring(&self, v: u32) -> Option<Fan> {
        if v as usize >= self.positions.len() {
            return None;
        }
        self.topology.one_ring(v)
    }
    /// Boundary loops as vertex sequences.
    pub fn boundary_loops(&self) -> Vec<Vec<u32>> {
        self.topology.boundary_loops()
    }
    /// Connected components with Euler characteristic and genus.
    pub fn components(&self) -> Vec<Component> {
        self.topology.components()
    }
    /// Euler characteristic V - E + F of the whole mesh (unused vertices not counted; a
    /// vertex shared by several components counts once, see
    /// [`Topology::euler_characteristic`]).
    pub fn euler_characteristic(&self) -> i64 {
        self.topology.euler_characteristic()
    }
    /// Signed enclosed volume of the triangles in `faces` (positive when a closed surface is
    /// oriented outward), measured from the centroid of their vertices.
    pub fn signed_volume_of(&self, faces: &[u32]) -> f64 {
        let mut o = DVec3::ZERO;
        for &f in faces {
            let [a, b, c] = self.triangle_points(f as usize);
            o += (a + b + c) / 3.0;
        }
        if !faces.is_empty() {
            o /= faces.len() as f64;
        }
        signed_volume(o, faces.iter().map(|&f| self.triangle_points(f as usize)))
    }
    /// Signed volume of the whole mesh.
    pub fn signed_volume(&self) -> f64 {
        let all: Vec<u32> = (0..self.triangles.len() as u32).collect();
        self.signed_volume_of(&all)
    }
}
