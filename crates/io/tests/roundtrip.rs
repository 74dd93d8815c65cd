//! read(write(mesh)) == mesh for every format, on generated and random meshes.

mod common;

use algesurf_io::{
    Format, OBJ_GROUP, PATCH_ID, WriteOptions, read, read_bytes, write, write_bytes,
};
use algesurf_mesh::{PolygonMesh, PropertyValues};
use common::*;
use proptest::prelude::*;

fn rt(mesh: &PolygonMesh, format: Format, options: WriteOptions) -> PolygonMesh {
    let bytes = write_bytes(mesh, format, &options).expect("write");
    read_bytes(&bytes, format).unwrap_or_else(|e| panic!("read back {format}: {e}"))
}

fn ply_options() -> Vec<WriteOptions> {
    let d = WriteOptions::default();
    vec![
        d,
        WriteOptions { ascii: true, ..d },
        WriteOptions {
            big_endian: true,
            ..d
        },
    ]
}

#[test]
fn ply_keeps_everything_in_every_encoding() {
    for mesh in [grid(5, 4, true), tetrahedron()] {
        for o in ply_options() {
            assert_eq!(rt(&mesh, Format::Ply, o), mesh, "{o:?}");
        }
    }
}

#[test]
fn ply_f32_shrinks() {
    let mesh = grid(3, 3, false);
    let o = WriteOptions {
        f32: true,
        ..Default::default()
    };
    let small = write_bytes(&mesh, Format::Ply, &o).unwrap();
    let full = write_bytes(&mesh, Format::Ply, &WriteOptions::default()).unwrap();
    assert!(small.len() < full.len());
    let back = read_bytes(&small, Format::Ply).unwrap();
    for (a, b) in back.positions.iter().zip(&mesh.positions) {
        assert_eq!(a.x, b.x as f32 as f64);
        assert_eq!(a.z, b.z as f32 as f64);
    }
    assert_eq!(back.vertex_properties[0], mesh.vertex_properties[0]); // ints stay ints
}

#[test]
fn ply_large_integers_become_doubles() {
    let mut mesh = tetrahedron();
    mesh.vertex_properties.push(algesurf_mesh::Property {
        name: "id64".into(),
        values: PropertyValues::Int(vec![1 << 40, -(1 << 40), 0, 7]),
    });
    let back = rt(&mesh, Format::Ply, WriteOptions::default());
    assert_eq!(
        back.vertex_properties[0].values,
        PropertyValues::Float(vec![(1u64 << 40) as f64, -((1u64 << 40) as f64), 0.0, 7.0])
    );
}

#[test]
fn obj_keeps_positions_faces_normals_groups() {
    let mesh = grid(5, 4, true);
    let want = strip(&mesh, true, &[], &[OBJ_GROUP]);
    assert_eq!(rt(&mesh, Format::Obj, WriteOptions::default()), want);
    let plain = tetrahedron();
    assert_eq!(rt(&plain, Format::Obj, WriteOptions::default()), plain);
    let no_normals = WriteOptions {
        normals: false,
        ..Default::default()
    };
    assert_eq!(
        rt(&mesh, Format::Obj, no_normals),
        strip(&mesh, false, &[], &[OBJ_GROUP])
    );
}

#[test]
fn obj_f32_writes_short_numbers() {
    let mesh = tetrahedron();
    let o = WriteOptions {
        f32: true,
        ..Default::default()
    };
    let text = String::from_utf8(write_bytes(&mesh, Format::Obj, &o).unwrap()).unwrap();
    assert!(text.contains("v 0.1 0.2 0.33333334"), "{text}");
    let full =
        String::from_utf8(write_bytes(&mesh, Format::Obj, &WriteOptions::default()).unwrap())
            .unwrap();
    assert!(full.contains("v 0.1 0.2 0.3333333333333333"), "{full}");
}

#[test]
fn off_keeps_positions_faces_normals() {
    let mesh = grid(4, 3, true);
    assert_eq!(
        rt(&mesh, Format::Off, WriteOptions::default()),
        strip(&mesh, true, &[], &[])
    );
    assert_eq!(
        rt(&tetrahedron(), Format::Off, WriteOptions::default()),
        tetrahedron()
    );
}

#[test]
fn stl_keeps_triangles_in_f32() {
    let mesh = grid(4, 3, true);
    for ascii in [false, true] {
        let o = WriteOptions {
            ascii,
            ..Default::default()
        };
        let back = rt(&mesh, Format::Stl, o);
        assert_eq!(
            corner_positions_f32(&back),
            corner_positions_f32(&fan(&mesh)),
            "ascii={ascii}"
        );
        // The grid has no duplicate positions, so vertices come back one to one, in order of
        // first use by the triangles.
        assert_eq!(back.vertex_count(), mesh.vertex_count());
    }
}

/// `back`, read from a glTF or GLB of `mesh`, is `mesh`'s fans with every position as its
/// `f32`, every normal (unit in `mesh`) to `f32` rounding and every patch id.
fn assert_reads_back_as_fans(back: &PolygonMesh, mesh: &PolygonMesh) {
    assert!(back.faces().eq(fan(mesh).faces()), "the fans, in order");
    assert_eq!(back.vertex_count(), mesh.vertex_count());
    for (a, b) in back.positions.iter().zip(&mesh.positions) {
        assert_eq!(*a, b.as_vec3().as_dvec3());
    }
    let normals = back.normals.as_ref().unwrap().iter();
    for (a, b) in normals.zip(mesh.normals.as_ref().unwrap()) {
        assert!((*a - *b).length() < 1e-6);
    }
    let ids = back.vertex_properties.iter().find(|p| p.name == PATCH_ID);
    assert_eq!(ids.unwrap().values, mesh.vertex_properties[0].values);
}

#[test]
fn glb_and_gltf_keep_triangles_normals_and_patch_ids() {
    let mesh = grid(4, 3, true);
    for format in [Format::Glb, Format::Gltf] {
        let back = rt(&mesh, format, WriteOptions::default());
        assert_reads_back_as_fans(&back, &mesh);
    }
    // Without patch ids or normals.
    let back = rt(&tetrahedron(), Format::Glb, WriteOptions::default());
    assert_eq!(
        back.faces().collect::<Vec<_>>(),
        tetrahedron().faces().collect::<Vec<_>>()
    );
    assert!(back.normals.is_none() && back.vertex_properties.is_empty());
}

#[test]
fn files_on_disk_by_extension_and_atomic() {
    let dir = std::env::temp_dir().join(format!("algesurf-io-rt-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mesh = grid(3, 2, false);
    for f in Format::ALL {
        let path = dir.join(format!("m.{}", f.extension()));
        write(&path, &mesh, &WriteOptions::default()).unwrap();
        let back = read(&path).unwrap();
        assert_eq!(back.face_count(), fan_or_not(&mesh, f).face_count(), "{f}");
    }
    // A failing write leaves the old file as it was and no temporary files behind.
    let path = dir.join("m.ply");
    let before = std::fs::read(&path).unwrap();
    let mut bad = mesh.clone();
    bad.push_face(&[0, 1, 999]);
    let err = write(&path, &bad, &WriteOptions::default()).unwrap_err();
    assert!(err.to_string().contains("999"), "{err}");
    assert_eq!(std::fs::read(&path).unwrap(), before);
    let leftovers: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().ends_with(".tmp"))
        .collect();
    assert!(leftovers.is_empty());
    // Unknown extension on write is an error naming the file.
    let err = write(dir.join("m.xyz"), &mesh, &WriteOptions::default()).unwrap_err();
    assert!(err.to_string().contains("m.xyz"));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A PLY file is streamed to disk in chunks of about a megabyte: the file holds exactly the
/// bytes `write_bytes` gives, in every encoding, for a mesh several chunks long (and reads
/// back as the mesh: its 120 k vertices and 180 k faces are encoded in blocks of 16 Ki, in
/// parallel, more than one batch of them for the faces); an error
/// found while streaming (a property name PLY cannot hold) leaves the old file as it was and
/// no temporary file behind.
#[test]
fn ply_streamed_to_disk_is_the_in_memory_encoding() {
    let dir = std::env::temp_dir().join(format!("algesurf-io-stream-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mesh = grid(400, 300, true);
    let path = dir.join("big.ply");
    for o in ply_options() {
        let bytes = write_bytes(&mesh, Format::Ply, &o).unwrap();
        assert!(
            bytes.len() > 3 << 20,
            "{} bytes: several chunks",
            bytes.len()
        );
        assert_eq!(read_bytes(&bytes, Format::Ply).unwrap(), mesh, "{o:?}");
        write(&path, &mesh, &o).unwrap();
        assert!(std::fs::read(&path).unwrap() == bytes, "{o:?}");
    }
    let before = std::fs::read(&path).unwrap();
    let mut bad = mesh.clone();
    bad.vertex_properties.push(algesurf_mesh::Property {
        name: "two words".into(),
        values: PropertyValues::Float(vec![0.0; bad.vertex_count()]),
    });
    let err = write(&path, &bad, &WriteOptions::default()).unwrap_err();
    assert!(err.to_string().contains("two words"), "{err}");
    assert_kept_and_cleaned(&dir, &path, &before);
}

/// A GLB is streamed to the file in blocks (its binary chunk after a JSON chunk made from the
/// lengths alone): on disk it is the bytes `write_bytes` gives, for a polygon mesh (written
/// as fans) and a triangle mesh several blocks long; the header's length is the file's, and
/// it reads back as the fans with every position, normal and patch id. A position that `f32`
/// cannot hold is reported with its vertex before anything is written, and the old file is
/// left as it was with no temporary file behind.
#[test]
fn glb_streamed_to_disk_reads_back_as_the_mesh() {
    let dir = std::env::temp_dir().join(format!("algesurf-io-glb-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("big.glb");
    let polygons = grid(400, 300, true);
    for mesh in [fan(&polygons), polygons] {
        let bytes = write_bytes(&mesh, Format::Glb, &WriteOptions::default()).unwrap();
        assert!(
            bytes.len() > 3 << 20,
            "{} bytes: several blocks",
            bytes.len()
        );
        let total = u32::from_le_bytes(bytes[8..12].try_into().unwrap());
        assert_eq!(total as usize, bytes.len());
        write(&path, &mesh, &WriteOptions::default()).unwrap();
        assert!(std::fs::read(&path).unwrap() == bytes);
        assert_reads_back_as_fans(&read(&path).unwrap(), &mesh);
    }
    let before = std::fs::read(&path).unwrap();
    let mut bad = grid(40, 30, false);
    bad.positions[77].y = 1e39; // finite in f64, infinite in f32
    let err = write(&path, &bad, &WriteOptions::default()).unwrap_err();
    assert!(err.to_string().contains("vertex 77"), "{err}");
    assert_kept_and_cleaned(&dir, &path, &before);
}

/// After a failed write: `path` still holds `before`, no temporary file is left in `dir`;
/// then `dir` is removed.
fn assert_kept_and_cleaned(dir: &std::path::Path, path: &std::path::Path, before: &[u8]) {
    assert!(std::fs::read(path).unwrap() == before);
    let leftovers: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().ends_with(".tmp"))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");
    std::fs::remove_dir_all(dir).unwrap();
}

fn fan_or_not(mesh: &PolygonMesh, f: Format) -> PolygonMesh {
    match f {
        Format::Stl | Format::Gltf | Format::Glb => fan(mesh),
        _ => mesh.clone(),
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    #[test]
    fn random_meshes_round_trip_exactly_in_ply(mesh in arb_mesh()) {
        for o in ply_options() {
            prop_assert_eq!(&rt(&mesh, Format::Ply, o), &mesh);
        }
    }

    #[test]
    fn random_meshes_round_trip_in_obj_and_off(mesh in arb_mesh()) {
        let want = strip(&mesh, true, &[], &[]);
        prop_assert_eq!(&rt(&mesh, Format::Off, WriteOptions::default()), &want);
        // OBJ: a vertex's normal is that of its first corner; ours are per vertex, so exact.
        prop_assert_eq!(&rt(&mesh, Format::Obj, WriteOptions::default()), &want);
    }

    #[test]
    fn random_meshes_round_trip_as_f32_triangles(mut mesh in arb_mesh()) {
        // Keep coordinates inside the f32 range.
        for p in &mut mesh.positions {
            *p = p.clamp(glam::DVec3::splat(-1e30), glam::DVec3::splat(1e30));
        }
        let tris = corner_positions_f32(&fan(&mesh));
        for o in [WriteOptions::default(), WriteOptions { ascii: true, ..Default::default() }] {
            let back = rt(&mesh, Format::Stl, o);
            prop_assert_eq!(corner_positions_f32(&back), tris.clone());
        }
        let back = rt(&mesh, Format::Glb, WriteOptions::default());
        prop_assert_eq!(corner_positions_f32(&back), tris);
    }
}
