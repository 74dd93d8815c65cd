//! The worked configurations of §6 of Xu–Huang–Bajaj 2001 (Figs. 6, 7, 9 and 10): two
//! triangles `[p1 p2 p3]` and `[p2 p1 p4]` sharing the edge `p1 p2`, with the normals the paper
//! gives, which make the faces convex, nonconvex or zero convex. Tests, the figure gallery and
//! users exploring the method start from them.
//!
//! # Example
//! ```
//! use algesurf_apatch::examples::WorkedExample;
//! use algesurf_apatch::{ApatchSurface, FaceFunction, SurfaceOptions};
//!
//! let (mesh, normals) = WorkedExample::Fig10.mesh_and_normals();
//! let s = ApatchSurface::new(&mesh, &normals, &SurfaceOptions::default()).unwrap();
//! // Fig. 10: [p1 p2 p3] is nonconvex (split), [p1 p2 p4] zero convex (planar).
//! assert!(matches!(s.faces()[0], FaceFunction::Split(_)));
//! assert!(matches!(s.faces()[1], FaceFunction::Planar));
//! ```

use algesurf_mesh::TriMesh;
use glam::DVec3;

/// One of the paper's two-triangle configurations (§6).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum WorkedExample {
    /// Fig. 6: both faces convex. `p1 = (−2, 0, 0)`, `p2 = (2, 0, 0)`, `p3 = (0, 4, −1)`,
    /// `p4 = (0, −4, −1)`; `n1 = (−1, 0, 1)`, `n2 = (1, 0, 1)`, `n3 = (0, 1, 1)`,
    /// `n4 = (0, −1, 1)`. Also the data of Fig. 2 (the surface family).
    Fig6,
    /// Fig. 7: as Fig. 6 with `n3 = n4 = (0, 1, 1.5)`: `[p1 p2 p3]` convex, `[p1 p2 p4]`
    /// nonconvex.
    Fig7,
    /// Fig. 9: `n1 = n2 = (1, 0, 1)`, `n3 = (0, −1, 1.5)`, `n4 = (0, 1, 1.5)`: both faces and
    /// the common edge nonconvex. Also the data of Fig. 3 (multiple sheets).
    Fig9,
    /// Fig. 10: `p4 = (0, −4, 0)`, `n1 = n2 = n4 = (0, 0, 1)`, `n3 = (0, −1, 1.5)`: a nonconvex
    /// face joining a zero convex (planar) one.
    Fig10,
}

/// How §6 says a face of a worked example is classified.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ExpectedFace {
    /// Zero convex: the patch is the triangle itself.
    Planar,
    /// Positive or negative convex: one rational cubic.
    Convex,
    /// Nonconvex: three cubics on the centroid split.
    Split,
}

impl WorkedExample {
    /// All four, in the paper's order.
    pub const ALL: [WorkedExample; 4] = [
        WorkedExample::Fig6,
        WorkedExample::Fig7,
        WorkedExample::Fig9,
        WorkedExample::Fig10,
    ];

    /// The figure's name, e.g. `"Fig. 6"`.
    pub fn name(self) -> &'static str {
        match self {
            WorkedExample::Fig6 => "Fig. 6",
            WorkedExample::Fig7 => "Fig. 7",
            WorkedExample::Fig9 => "Fig. 9",
            WorkedExample::Fig10 => "Fig. 10",
        }
    }

    /// The two triangles (`[p1 p2 p3]`, `[p2 p1 p4]`, consistently oriented) and the unit
    /// normals at `p1 … p4`.
    pub fn mesh_and_normals(self) -> (TriMesh, Vec<DVec3>) {
        let z4 = if self == WorkedExample::Fig10 {
            0.0
        } else {
            -1.0
        };
        let p = vec![
            DVec3::new(-2.0, 0.0, 0.0),
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(0.0, 4.0, -1.0),
            DVec3::new(0.0, -4.0, z4),
        ];
        let n: [[f64; 3]; 4] = match self {
            WorkedExample::Fig6 => [
                [-1.0, 0.0, 1.0],
                [1.0, 0.0, 1.0],
                [0.0, 1.0, 1.0],
                [0.0, -1.0, 1.0],
            ],
            WorkedExample::Fig7 => [
                [-1.0, 0.0, 1.0],
                [1.0, 0.0, 1.0],
                [0.0, 1.0, 1.5],
                [0.0, 1.0, 1.5],
            ],
            WorkedExample::Fig9 => [
                [1.0, 0.0, 1.0],
                [1.0, 0.0, 1.0],
                [0.0, -1.0, 1.5],
                [0.0, 1.0, 1.5],
            ],
            WorkedExample::Fig10 => [
                [0.0, 0.0, 1.0],
                [0.0, 0.0, 1.0],
                [0.0, -1.0, 1.5],
                [0.0, 0.0, 1.0],
            ],
        };
        let mesh = TriMesh::new(p, vec![[0, 1, 2], [1, 0, 3]])
            .expect("the worked examples are valid meshes");
        let normals = n
            .iter()
            .map(|v| DVec3::from_array(*v).normalize())
            .collect();
        (mesh, normals)
    }

    /// The classification of `[p1 p2 p3]` and `[p1 p2 p4]` that §6 states.
    pub fn expected_faces(self) -> [ExpectedFace; 2] {
        match self {
            WorkedExample::Fig6 => [ExpectedFace::Convex, ExpectedFace::Convex],
            WorkedExample::Fig7 => [ExpectedFace::Convex, ExpectedFace::Split],
            WorkedExample::Fig9 => [ExpectedFace::Split, ExpectedFace::Split],
            WorkedExample::Fig10 => [ExpectedFace::Split, ExpectedFace::Planar],
        }
    }
}
