//! Shared mesh generators for the integration tests.
#![allow(dead_code)]

use algesurf_io::{OBJ_GROUP, PATCH_ID};
use algesurf_mesh::{PolygonMesh, Property, PropertyValues};
use glam::DVec3;
use proptest::prelude::*;

/// A bumpy `n × m` grid of quads (split into triangles on odd rows when `mixed`), with normals,
/// a per-vertex patch id and quality, and a per-face group and weight.
pub fn grid(n: u32, m: u32, mixed: bool) -> PolygonMesh {
    let mut mesh = PolygonMesh::new();
    for j in 0..=m {
        for i in 0..=n {
            let (x, y) = (i as f64 / n as f64, j as f64 / m as f64);
            mesh.positions.push(DVec3::new(
                x,
                y,
                0.1 * (3.0 * x).sin() * (2.0 * y).cos() + 1.0 / 3.0,
            ));
        }
    }
    let id = |i: u32, j: u32| j * (n + 1) + i;
    for j in 0..m {
        for i in 0..n {
            let q = [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)];
            if mixed && j % 2 == 1 {
                mesh.push_face(&[q[0], q[1], q[2]]);
                mesh.push_face(&[q[0], q[2], q[3]]);
            } else {
                mesh.push_face(&q);
            }
        }
    }
    let nv = mesh.vertex_count();
    let nf = mesh.face_count();
    mesh.normals = Some(
        mesh.positions
            .iter()
            .map(|p| DVec3::new(-0.3 * p.x, 0.2 * p.y, 1.0).normalize())
            .collect(),
    );
    mesh.vertex_properties = vec![
        Property {
            name: PATCH_ID.into(),
            values: PropertyValues::Int((0..nv as i64).map(|v| v % 7).collect()),
        },
        Property {
            name: "quality".into(),
            values: PropertyValues::Float((0..nv).map(|v| v as f64 / 3.0).collect()),
        },
    ];
    mesh.face_properties = vec![
        Property {
            name: OBJ_GROUP.into(),
            values: PropertyValues::Int((0..nf as i64).map(|f| f / 5).collect()),
        },
        Property {
            name: "weight".into(),
            values: PropertyValues::Float((0..nf).map(|f| 1.0 / (f as f64 + 1.0)).collect()),
        },
    ];
    mesh
}

/// A closed tetrahedron without normals or properties.
pub fn tetrahedron() -> PolygonMesh {
    PolygonMesh::from_triangles(
        vec![
            DVec3::ZERO,
            DVec3::X,
            DVec3::Y,
            DVec3::new(0.1, 0.2, 1.0 / 3.0),
        ],
        &[[0, 2, 1], [0, 1, 3], [1, 2, 3], [2, 0, 3]],
    )
}

/// The mesh with only what `keep` names: positions and faces always.
pub fn strip(mesh: &PolygonMesh, normals: bool, vprops: &[&str], fprops: &[&str]) -> PolygonMesh {
    let mut m = mesh.clone();
    if !normals {
        m.normals = None;
    }
    m.vertex_properties
        .retain(|p| vprops.contains(&p.name.as_str()));
    m.face_properties
        .retain(|p| fprops.contains(&p.name.as_str()));
    m
}

/// Every face as a list of its corner positions rounded to f32 (for formats that renumber).
pub fn corner_positions_f32(mesh: &PolygonMesh) -> Vec<Vec<[f32; 3]>> {
    mesh.faces()
        .map(|f| {
            f.iter()
                .map(|&v| {
                    let p = mesh.positions[v as usize];
                    [p.x as f32, p.y as f32, p.z as f32]
                })
                .collect()
        })
        .collect()
}

/// Fan triangulation, as the STL and glTF writers do.
pub fn fan(mesh: &PolygonMesh) -> PolygonMesh {
    let mut out = PolygonMesh::new();
    out.positions = mesh.positions.clone();
    out.normals = mesh.normals.clone();
    out.vertex_properties = mesh.vertex_properties.clone();
    for f in mesh.faces() {
        for i in 1..f.len() - 1 {
            out.push_face(&[f[0], f[i], f[i + 1]]);
        }
    }
    out
}

fn finite() -> impl Strategy<Value = f64> {
    prop_oneof![
        -1e3..1e3f64,
        any::<f64>().prop_filter("finite", |x| x.is_finite()),
        Just(0.0),
        Just(1.0 / 3.0),
    ]
}

/// Random polygon meshes: 3..40 vertices, 0..30 faces of 3..7 corners (corners may repeat:
/// writers and readers must not care), optional normals and properties.
pub fn arb_mesh() -> impl Strategy<Value = PolygonMesh> {
    (3usize..40, any::<bool>(), any::<bool>())
        .prop_flat_map(|(nv, with_normals, with_props)| {
            let pos = prop::collection::vec((finite(), finite(), finite()), nv);
            let faces = prop::collection::vec(prop::collection::vec(0..nv as u32, 3..8), 0..30);
            let normals = prop::collection::vec((-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64), nv);
            let ints = prop::collection::vec(i64::from(i32::MIN)..=i64::from(i32::MAX), nv);
            (
                pos,
                faces,
                normals,
                ints,
                Just(with_normals),
                Just(with_props),
            )
        })
        .prop_map(|(pos, faces, normals, ints, with_normals, with_props)| {
            let mut m = PolygonMesh::new();
            m.positions = pos
                .into_iter()
                .map(|(x, y, z)| DVec3::new(x, y, z))
                .collect();
            for f in &faces {
                m.push_face(f);
            }
            if with_normals {
                m.normals = Some(
                    normals
                        .into_iter()
                        .map(|(x, y, z)| DVec3::new(x, y, z))
                        .collect(),
                );
            }
            if with_props {
                let nf = m.face_count();
                m.vertex_properties.push(Property {
                    name: "big".into(),
                    values: PropertyValues::Int(ints.clone()),
                });
                m.vertex_properties.push(Property {
                    name: PATCH_ID.into(),
                    values: PropertyValues::Int(ints.iter().map(|x| x.rem_euclid(1000)).collect()),
                });
                m.face_properties.push(Property {
                    name: "area".into(),
                    values: PropertyValues::Float((0..nf).map(|f| f as f64 * 0.1).collect()),
                });
            }
            m
        })
}
