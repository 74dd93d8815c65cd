//! Our order-preserving OBJ reader agrees with tobj (the reference parser) on every face's
//! corner positions, in file order, for generated files and (with `ALGESURF_CORPUS`) the corpus.

mod common;

use algesurf_io::{Format, WriteOptions, read_bytes, write_bytes};

/// Face corner positions as tobj sees them (models concatenated in file order).
fn tobj_faces(bytes: &[u8]) -> Vec<Vec<[f64; 3]>> {
    let options = tobj::LoadOptions {
        triangulate: false,
        single_index: false,
        ignore_points: true,
        ignore_lines: true,
    };
    let (models, _) = tobj::load_obj_buf(&mut std::io::Cursor::new(bytes), &options, |_| {
        Err(tobj::LoadError::OpenFileFailed)
    })
    .expect("tobj loads the file");
    let mut out = Vec::new();
    for m in models {
        let mesh = &m.mesh;
        let arities: Vec<u32> = if mesh.face_arities.is_empty() {
            vec![3; mesh.indices.len() / 3]
        } else {
            mesh.face_arities.clone()
        };
        let mut k = 0;
        for a in arities {
            let face = (0..a as usize)
                .map(|c| {
                    let v = mesh.indices[k + c] as usize;
                    [
                        mesh.positions[3 * v],
                        mesh.positions[3 * v + 1],
                        mesh.positions[3 * v + 2],
                    ]
                })
                .collect();
            k += a as usize;
            out.push(face);
        }
    }
    out
}

fn our_faces(bytes: &[u8]) -> Vec<Vec<[f64; 3]>> {
    let mesh = read_bytes(bytes, Format::Obj).expect("we load the file");
    mesh.faces()
        .map(|f| {
            f.iter()
                .map(|&v| mesh.positions[v as usize].to_array())
                .collect()
        })
        .collect()
}

#[test]
fn agrees_with_tobj_on_generated_files() {
    let mesh = common::grid(6, 5, true);
    for normals in [true, false] {
        let o = WriteOptions {
            normals,
            ..Default::default()
        };
        let bytes = write_bytes(&mesh, Format::Obj, &o).unwrap();
        assert_eq!(our_faces(&bytes), tobj_faces(&bytes));
    }
    let wild =
        b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\ng a\nf -4 -3 -2\ng b\nf 2 4 3\ng a\nf 1 2 4 3\n";
    assert_eq!(our_faces(wild), tobj_faces(wild));
}

#[test]
fn agrees_with_tobj_on_the_corpus() {
    let Some(files) = algesurf_mesh::test_corpus::corpus_files() else {
        return;
    };
    for path in files {
        if path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("obj"))
        {
            let bytes = std::fs::read(&path).unwrap();
            assert_eq!(our_faces(&bytes), tobj_faces(&bytes), "{}", path.display());
            println!("{}: same faces as tobj", path.display());
        }
    }
}
