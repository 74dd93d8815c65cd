//! The indexed polygon mesh as read from a file: positions, polygons of any size, optional
//! per-vertex normals and named per-vertex / per-face properties, in the file's own order.

use glam::DVec3;

/// A named scalar property attached to every vertex or every face (for example a PLY
/// `quality` or the `patch_id` that `algesurf smooth` writes).
#[derive(Clone, Debug, PartialEq)]
pub struct Property {
    /// Property name as it appears in the file (`patch_id`, `quality`, ...).
    pub name: String,
    /// One value per element.
    pub values: PropertyValues,
}

/// The values of a [`Property`]: integers or floating point, one per element.
#[derive(Clone, Debug, PartialEq)]
pub enum PropertyValues {
    /// Integer values (PLY char/uchar/short/ushort/int/uint).
    Int(Vec<i64>),
    /// Floating-point values (PLY float/double).
    Float(Vec<f64>),
}

impl PropertyValues {
    /// Number of values.
    pub fn len(&self) -> usize {
        match self {
            PropertyValues::Int(v) => v.len(),
            PropertyValues::Float(v) => v.len(),
        }
    }
    /// True when there are no values.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// An indexed polygon mesh that keeps the vertex and face order of its source, so that element
/// ids reported by later stages can be found in the user's file.
///
/// Faces are stored flat: face `f` uses `indices[offsets[f]..offsets[f + 1]]`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PolygonMesh {
    /// Vertex positions.
    pub positions: Vec<DVec3>,
    /// Optional per-vertex normals (same length as `positions`), as read from the file.
    pub normals: Option<Vec<DVec3>>,
    /// Flattened polygon corner indices.
    indices: Vec<u32>,
    /// Face start offsets into `indices`, with a final sentinel (`len = faces + 1`).
    offsets: Vec<u32>,
    /// Per-vertex scalar properties.
    pub vertex_properties: Vec<Property>,
    /// Per-face scalar properties.
    pub face_properties: Vec<Property>,
}

impl PolygonMesh {
    /// An empty mesh.
    pub fn new() -> Self {
        PolygonMesh {
            offsets: vec![0],
            ..Default::default()
        }
    }

    /// A mesh from positions and triangles.
    ///
    /// ```
    /// use algesurf_mesh::PolygonMesh;
    /// use glam::DVec3;
    /// let m = PolygonMesh::from_triangles(vec![DVec3::ZERO; 4], &[[0, 1, 2], [2, 1, 3]]);
    /// assert_eq!(m.face_count(), 2);
    /// assert_eq!(m.face(1), &[2, 1, 3]);
    /// let empty = PolygonMesh::from_triangles(Vec::new(), &[]);
    /// assert_eq!(empty.face_count(), 0);
    /// ```
    pub fn from_triangles(positions: Vec<DVec3>, triangles: &[[u32; 3]]) -> Self {
        // Built in one go, not face by face: pushing grew both vectors by doubling, which for
        // a tessellation's 1.5 M triangles was a tenth of the command's write stage.
        PolygonMesh {
            positions,
            indices: triangles.as_flattened().to_vec(),
            offsets: (0..=triangles.len() as u32).map(|k| 3 * k).collect(),
            ..Default::default()
        }
    }

    /// [`PolygonMesh::from_triangles`] taking the triangles by value: their memory becomes
    /// the mesh's corner list, with no copy (a tessellation's triangle list is tens of MB,
    /// and a copy's fresh pages cost ~2.4 µs per 4 KiB page on the development machine).
    ///
    /// ```
    /// use algesurf_mesh::PolygonMesh;
    /// use glam::DVec3;
    /// let tris = vec![[0, 1, 2], [2, 1, 3]];
    /// let m = PolygonMesh::from_owned_triangles(vec![DVec3::ZERO; 4], tris.clone());
    /// assert_eq!(m, PolygonMesh::from_triangles(vec![DVec3::ZERO; 4], &tris));
    /// ```
    pub fn from_owned_triangles(positions: Vec<DVec3>, triangles: Vec<[u32; 3]>) -> Self {
        PolygonMesh {
            positions,
            offsets: (0..=triangles.len() as u32).map(|k| 3 * k).collect(),
            indices: triangles.into_flattened(),
            ..Default::default()
        }
    }

    /// Appends a polygon (any number of corners).
    pub fn push_face(&mut self, corners: &[u32]) {
        if self.offsets.is_empty() {
            self.offsets.push(0);
        }
        self.indices.extend_from_slice(corners);
        self.offsets.push(self.indices.len() as u32);
    }

    /// Number of faces.
    pub fn face_count(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// The corners of face `f`.
    pub fn face(&self, f: usize) -> &[u32] {
        &self.indices[self.offsets[f] as usize..self.offsets[f + 1] as usize]
    }

    /// Iterates over all faces in order.
    pub fn faces(&self) -> impl ExactSizeIterator<Item = &[u32]> + '_ {
        (0..self.face_count()).map(move |f| self.face(f))
    }
}
