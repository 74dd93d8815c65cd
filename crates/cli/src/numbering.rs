//! `smooth` and `check` build the surface on the repaired mesh numbered in spatial order
//! ([`SpatialOrder`]: faces along the Z-order curve of their centroids, vertices by first
//! use), and speak to the user in the repaired mesh's own numbering.
//!
//! Why: the construction's loops over edges read the records of each edge's two faces, and a
//! scanned mesh lists its faces in no spatial order (the bunny's consecutive faces' smallest
//! vertex ids differ by ~1 400 in the median), so most of those reads missed the cache. On
//! the bunny the spatial numbering made the edge cubics 26 % and the edges' single-sheet
//! bounds 22 % faster, construction 7 % (docs/PERFORMANCE.md, twenty-third and twenty-fourth
//! passes).
//!
//! What the user sees does not change numbering:
//! * the ids the commands print (adjusted normals, the input's self-crossings, `check`'s mesh
//!   vertices) are mapped back to the repaired mesh's ([`Numbering::repaired_vertices`],
//!   [`Numbering::repaired_faces`], [`Numbering::repaired_location`]); the hull's faces and
//!   edges, which are the surface's patches, keep the surface's numbering, as the output's
//!   patch ids do;
//! * a build that fails on the spatial numbering is run again on the repaired numbering, and
//!   that build's result is the command's: its error names the repaired mesh's vertices,
//!   faces and edges, as before ([`build_surface`]). The failed build is not hidden: the
//!   summary and the report say why it failed and how long it took
//!   ([`Numbering::spatial_failure`]), since construction's time includes it (Suzanne's hull
//!   on the spatial numbering still overlaps after 24 refinement rounds, ~0.7 s of its
//!   1.5 s construction, where its own numbering's separates in 17);
//! * the output's first vertices are the repaired mesh's, in its order
//!   ([`Numbering::restore_vertex_order`]).
//!
//! The surface itself can differ from one built on the repaired numbering: the hull's
//! refinement bisects overlapping tetrahedra in the order of their faces (98 refinements
//! instead of 104 on the bunny). Both pass every property `algesurf check` measures; the
//! command's result is deterministic for a given input and options.

use algesurf_apatch::{ApatchError, ApatchSurface, SurfaceOptions};
use algesurf_inspect::check::{Element, Location};
use algesurf_mesh::TriMesh;
use algesurf_mesh::progress::Progress;
use algesurf_mesh::spatial_order::SpatialOrder;
use glam::DVec3;
use rayon::prelude::*;

/// The repaired mesh's id of vertex `v` of the built mesh, `old` the spatial order's
/// [`SpatialOrder::vertices`]: ids past the repaired mesh's vertices (the hull's refinement
/// vertices, a tessellation's ray points) are numbered alike in both and stay as they are.
fn repaired_vertex(old: &[u32], v: u32) -> u32 {
    old.get(v as usize).copied().unwrap_or(v)
}

/// How the mesh a surface was built on is numbered against the repaired mesh.
#[derive(Debug, Default)]
pub(crate) struct Numbering {
    /// `Some`: the spatial order; `None`: the repaired mesh's own numbering.
    order: Option<SpatialOrder>,
    /// Why and after how long the build on the spatial numbering failed, when the surface
    /// was then built on the repaired mesh's own numbering.
    spatial_failure: Option<SpatialFailure>,
}

/// A build on the spatial numbering that failed ([`build_surface`] then built again on the
/// repaired mesh's numbering).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct SpatialFailure {
    /// The build's error, as it would have been reported (its ids are the spatial
    /// numbering's).
    pub error: String,
    /// Wall-clock seconds the failed build took: part of construction's time.
    pub seconds: f64,
}

impl Numbering {
    /// Whether the surface was built on the spatial numbering.
    pub(crate) fn is_spatial(&self) -> bool {
        self.order.is_some()
    }

    /// The failed build on the spatial numbering, when the surface was built again on the
    /// repaired mesh's own.
    pub(crate) fn spatial_failure(&self) -> Option<&SpatialFailure> {
        self.spatial_failure.as_ref()
    }

    /// The repaired mesh's ids of vertices `ids` of the built mesh (ids past the repaired
    /// mesh's vertices, such as the hull's refinement vertices, are numbered alike in both).
    pub(crate) fn repaired_vertices(&self, ids: &[u32]) -> Vec<u32> {
        let Some(order) = &self.order else {
            return ids.to_vec();
        };
        let old = order.vertices();
        let mut v: Vec<u32> = ids.iter().map(|&i| repaired_vertex(old, i)).collect();
        v.sort_unstable();
        v
    }

    /// `check`'s location `at` with its mesh vertices, and the tessellation vertices that are
    /// mesh vertices (the first ones), named by the repaired mesh's ids. Faces and edges stay
    /// the hull's: they are the surface's own pieces and patches, numbered as the patch ids of
    /// `smooth`'s output are.
    pub(crate) fn repaired_location(&self, at: Location) -> Location {
        let Some(order) = &self.order else {
            return at;
        };
        let old = order.vertices();
        let vertex = |v: usize| repaired_vertex(old, v as u32) as usize;
        let element = |e: Element| match e {
            Element::Vertex(v) => Element::Vertex(vertex(v)),
            e => e,
        };
        match at {
            Location::Element(e) => Location::Element(element(e)),
            Location::Facet(a, b) => Location::Facet(element(a), element(b)),
            Location::Boundary { vertex: v, patches } => Location::Boundary {
                vertex: vertex(v),
                patches: (element(patches.0), element(patches.1)),
            },
            Location::TessellationVertex(v) => Location::TessellationVertex(vertex(v)),
            Location::TessellationEdge(a, b) => {
                Location::TessellationEdge(repaired_vertex(old, a), repaired_vertex(old, b))
            }
            at @ Location::Euler { .. } => at,
        }
    }

    /// The repaired mesh's ids of the face pairs `pairs` of the built mesh, each `[f, g]` with
    /// `f < g`, ascending.
    pub(crate) fn repaired_faces(&self, pairs: &[[u32; 2]]) -> Vec<[u32; 2]> {
        let Some(order) = &self.order else {
            return pairs.to_vec();
        };
        let old = order.faces();
        let mut v: Vec<[u32; 2]> = pairs
            .iter()
            .map(|&[f, g]| {
                let (f, g) = (old[f as usize], old[g as usize]);
                [f.min(g), f.max(g)]
            })
            .collect();
        v.sort_unstable();
        v
    }

    /// Renumbers an output mesh whose first vertices are those of the built mesh (a
    /// tessellation's: [`algesurf_apatch::Tessellation::positions`]) so that they are the
    /// repaired mesh's vertices in its order: vertex `v` of the repaired mesh is output vertex
    /// `v` again. Later vertices keep their ids; triangles keep their order and orientation.
    pub(crate) fn restore_vertex_order(
        &self,
        positions: &mut [DVec3],
        normals: &mut [DVec3],
        triangles: &mut [[u32; 3]],
    ) {
        let Some(order) = &self.order else {
            return;
        };
        let old = order.vertices();
        let n = old.len();
        for values in [positions, normals] {
            let built: Vec<DVec3> = values[..n].to_vec();
            for (new, &v) in old.iter().enumerate() {
                values[v as usize] = built[new];
            }
        }
        triangles.par_iter_mut().for_each(|t| {
            for v in t {
                *v = repaired_vertex(old, *v);
            }
        });
    }
}

/// The surface on `tri` and `normals` (the repaired mesh, its vertex normals), built on the
/// spatial numbering ([`SpatialOrder`]); when that build fails (for any reason but `progress`
/// asking it to stop), built again on `tri`'s own numbering, whose result is returned, and the
/// failure is kept ([`Numbering::spatial_failure`]). With the surface: the mesh it was built
/// on and how that is numbered.
pub(crate) fn build_surface(
    tri: TriMesh,
    normals: &[DVec3],
    options: &SurfaceOptions,
    progress: &dyn Progress,
) -> (Result<ApatchSurface, ApatchError>, TriMesh, Numbering) {
    let start = std::time::Instant::now();
    let order = SpatialOrder::of(&tri);
    let mut spatial_failure = None;
    // `apply` fails only for a mesh of another size than the order's: not this one.
    if let Ok(ordered) = order.apply(&tri) {
        let ordered_normals = order.vertex_values(normals);
        match ApatchSurface::with_progress(&ordered, &ordered_normals, options, progress) {
            Ok(surface) => {
                let numbering = Numbering {
                    order: Some(order),
                    spatial_failure: None,
                };
                return (Ok(surface), ordered, numbering);
            }
            Err(ApatchError::Cancelled) => {
                return (Err(ApatchError::Cancelled), tri, Numbering::default());
            }
            Err(e) => {
                spatial_failure = Some(SpatialFailure {
                    error: e.to_string(),
                    seconds: start.elapsed().as_secs_f64(),
                });
            }
        }
    }
    let surface = ApatchSurface::with_progress(&tri, normals, options, progress);
    let numbering = Numbering {
        order: None,
        spatial_failure,
    };
    (surface, tri, numbering)
}

#[cfg(test)]
mod tests {
    use super::*;
    use algesurf_mesh::progress::NoProgress;
    use algesurf_mesh::shapes;

    /// A sphere whose vertex numbering is reversed: its spatial order differs from its own.
    fn reversed_sphere() -> (TriMesh, Vec<DVec3>) {
        let mesh = shapes::icosphere(2);
        let n = mesh.vertex_count() as u32;
        let positions: Vec<DVec3> = mesh.positions().iter().rev().copied().collect();
        let faces = mesh
            .triangles()
            .iter()
            .rev()
            .map(|t| t.map(|v| n - 1 - v))
            .collect();
        let tri = TriMesh::new(positions, faces).unwrap();
        let normals = tri.positions().iter().map(|p| p.normalize()).collect();
        (tri, normals)
    }

    #[test]
    fn the_output_starts_with_the_repaired_vertices_in_their_order() {
        let (tri, normals) = reversed_sphere();
        let (surface, built, numbering) = build_surface(
            tri.clone(),
            &normals,
            &SurfaceOptions::default(),
            &NoProgress,
        );
        assert!(numbering.order.is_some(), "built on the spatial numbering");
        assert!(numbering.spatial_failure().is_none());
        assert_ne!(built.positions(), tri.positions());
        let mut t = surface.unwrap().tessellate(2, 2).unwrap();
        let (points, triangles) = (t.positions.clone(), t.triangles.clone());
        numbering.restore_vertex_order(&mut t.positions, &mut t.normals, &mut t.triangles);
        let n = tri.vertex_count();
        assert_eq!(&t.positions[..n], tri.positions());
        assert_eq!(t.positions[n..], points[n..]);
        // The same triangles in the same order: each one's corners are the same points.
        for (a, b) in triangles.iter().zip(&t.triangles) {
            assert_eq!(
                a.map(|v| points[v as usize]),
                b.map(|v| t.positions[v as usize])
            );
        }
    }

    #[test]
    fn ids_are_mapped_back_to_the_repaired_numbering() {
        let (tri, _) = reversed_sphere();
        let order = SpatialOrder::of(&tri);
        let (v, f) = (order.vertices().to_vec(), order.faces().to_vec());
        let numbering = Numbering {
            order: Some(order),
            spatial_failure: None,
        };
        let n = v.len() as u32;
        assert_eq!(numbering.repaired_vertices(&[0, 1, n + 5]), {
            let mut e = vec![v[0], v[1], n + 5];
            e.sort_unstable();
            e
        });
        let [a, b] = [f[3], f[7]];
        assert_eq!(
            numbering.repaired_faces(&[[3, 7]]),
            vec![[a.min(b), a.max(b)]]
        );
        // Vertices named by the repaired ids; faces and edges (the surface's patches) kept.
        let at = Location::Facet(Element::Vertex(2), Element::Face(5, None));
        assert_eq!(
            numbering.repaired_location(at),
            Location::Facet(Element::Vertex(v[2] as usize), Element::Face(5, None))
        );
        assert_eq!(
            numbering.repaired_location(Location::TessellationEdge(1, n + 9)),
            Location::TessellationEdge(v[1], n + 9)
        );
        let none = Numbering::default();
        assert_eq!(none.repaired_vertices(&[4, 2]), vec![4, 2]);
    }
}
