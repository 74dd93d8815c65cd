//! Sharp rims and crossings of real meshes (`ALGESURF_CORPUS`; "skipped" when unset).
//!
//! The cow's ears pass through its head, and its horns and ears have rims where the surface
//! turns back within one ring. With the default normals
//! ([`algesurf_mesh::NormalMethod::LoopButterfly`]: Butterfly limit normals where the Loop
//! normal is steep) refinement separates every overlap it can within the default bound, and
//! the only overlaps left are around the input's own crossings.

use algesurf_hull::{HullOptions, SimplicialHull};
use algesurf_mesh::{
    DEFAULT_MIN_NORMAL_COSINE, NormalMethod, RepairOptions, TriMesh, condition_normals, repair,
    self_intersections, vertex_normals,
};

fn corpus_mesh(name: &str) -> Option<TriMesh> {
    let dir = algesurf_mesh::test_corpus::corpus_dir()?;
    let poly = algesurf_io::read(dir.join(name)).unwrap();
    let repaired = repair(&poly, &RepairOptions::default()).unwrap().mesh;
    Some(TriMesh::from_polygon_mesh(&repaired).unwrap())
}

#[test]
fn cow_hull_separates_everything_but_its_own_crossings() {
    let Some(mesh) = corpus_mesh("cow.obj") else {
        return;
    };
    let normals = vertex_normals(&mesh, NormalMethod::LoopButterfly).unwrap();
    let (normals, _) = condition_normals(&mesh, &normals, DEFAULT_MIN_NORMAL_COSINE);
    let hull = SimplicialHull::from_mesh(&mesh, &normals, &HullOptions::default()).unwrap();
    let crossings = self_intersections(&mesh);
    assert_eq!(hull.input_crossings(), crossings.as_slice());
    assert!(!crossings.is_empty(), "the cow's ears cross its head");
    // Every overlap left is between tetrahedra around two crossing input faces' rings.
    let left = hull.distant_intersections();
    assert_eq!(left.len(), hull.intersections().len());
    let ring2 = |f: u32| -> Vec<u32> {
        let t = mesh.topology();
        let mut r: Vec<u32> = mesh.triangles()[f as usize]
            .iter()
            .flat_map(|&v| t.vertex_faces(v))
            .flat_map(|g| mesh.triangles()[g as usize])
            .flat_map(|v| t.vertex_faces(v))
            .collect();
        r.sort_unstable();
        r.dedup();
        r
    };
    let zones: Vec<(Vec<u32>, Vec<u32>)> = crossings
        .iter()
        .map(|&[f, g]| (ring2(f), ring2(g)))
        .collect();
    let input_faces = |e: algesurf_hull::Element| -> Vec<u32> {
        match e {
            algesurf_hull::Element::Face(f) => vec![hull.face_map()[f as usize]],
            algesurf_hull::Element::Edge(e) => {
                let edge = &hull.edges()[e as usize];
                std::iter::once(edge.face_k)
                    .chain(edge.face_l)
                    .map(|f| hull.face_map()[f as usize])
                    .collect()
            }
        }
    };
    for h in &left {
        let (a, b) = (input_faces(h.first.element), input_faces(h.second.element));
        let around = zones.iter().any(|(zf, zg)| {
            a.iter().any(|x| {
                b.iter().any(|y| {
                    (zf.contains(x) && zg.contains(y)) || (zg.contains(x) && zf.contains(y))
                })
            })
        });
        assert!(around, "overlap left away from every crossing: {h:?}");
    }
    println!(
        "cow: {} crossings, {} hull faces, {} refinements, {} overlaps left around crossings",
        crossings.len(),
        hull.faces().len(),
        hull.refinements().len(),
        left.len()
    );
}
