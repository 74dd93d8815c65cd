//! Files as found in the wild, sniffing, and error messages.

use algesurf_io::{Format, IoError, Location, OBJ_GROUP, PATCH_ID, read, read_bytes};
use algesurf_mesh::PropertyValues;
use glam::DVec3;

fn faces(m: &algesurf_mesh::PolygonMesh) -> Vec<Vec<u32>> {
    m.faces().map(<[u32]>::to_vec).collect()
}

#[test]
fn ply_tristrips_unknown_elements_comments_and_uchar_colours() {
    let text = "ply\nformat ascii 1.0\ncomment made by hand\nobj_info x\nelement vertex 5\n\
        property float x\nproperty float y\nproperty float z\nproperty uchar red\n\
        element tristrips 1\nproperty list int int vertex_indices\n\
        element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n\
        0 0 0 10\n1 0 0 20\n0 1 0 30\n1 1 0 40\n2 2 0 50\n8 0 1 2 3 -1 2 3 4\n0 1\n";
    let m = read_bytes(text.as_bytes(), Format::Ply).unwrap();
    assert_eq!(m.vertex_count(), 5);
    // Strip 0 1 2 3 -> (0,1,2), (2,1,3); strip 2 3 4 -> (2,3,4).
    assert_eq!(faces(&m), vec![vec![0, 1, 2], vec![2, 1, 3], vec![2, 3, 4]]);
    assert_eq!(m.vertex_properties[0].name, "red");
    assert_eq!(
        m.vertex_properties[0].values,
        PropertyValues::Int(vec![10, 20, 30, 40, 50])
    );
}

#[test]
fn ply_vertex_index_int_counts_and_big_endian() {
    let mut bytes = b"ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty double x\n\
        property double y\nproperty double z\nelement face 1\nproperty list int uint vertex_index\n\
        property int patch_id\nend_header\n"
        .to_vec();
    for v in [[0.0f64, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 1.0 / 3.0]] {
        for c in v {
            bytes.extend(c.to_be_bytes());
        }
    }
    bytes.extend(3i32.to_be_bytes());
    for i in [0u32, 1, 2] {
        bytes.extend(i.to_be_bytes());
    }
    bytes.extend(42i32.to_be_bytes());
    let m = read_bytes(&bytes, Format::Ply).unwrap();
    assert_eq!(m.positions[2], DVec3::new(0.0, 1.0, 1.0 / 3.0));
    assert_eq!(faces(&m), vec![vec![0, 1, 2]]);
    assert_eq!(m.face_properties[0].name, "patch_id");
    assert_eq!(m.face_properties[0].values, PropertyValues::Int(vec![42]));
}

#[test]
fn ply_errors_name_the_place() {
    let text = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
        property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n\
        0 0 0\n1 0 0\n0 1\n3 0 1 2\n";
    let e = read_bytes(text.as_bytes(), Format::Ply).unwrap_err();
    assert!(
        matches!(
            e,
            IoError::Parse {
                location: Location::Line(_),
                ..
            }
        ),
        "{e}"
    );
    let text = text.replace("0 1\n3 0 1 2", "0 1 0\n3 0 1 7");
    let e = read_bytes(text.as_bytes(), Format::Ply).unwrap_err();
    assert!(
        matches!(
            e,
            IoError::Parse {
                location: Location::Element("face", 0),
                ..
            }
        ),
        "{e}"
    );
    assert!(e.to_string().contains("found 7"), "{e}");
}

#[test]
fn obj_negative_indices_groups_polygons_normals_and_order() {
    let text = "# comment\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 9 9 9\nvn 0 0 1\nvt 0 0\n\
        g first\nf -4/1/1 -3/1/1 -2/1/1\ng second\nv 1 1 0 2\nf 2 5 3 1\ng first\nf 1 2 3\n";
    let m = read_bytes(text.as_bytes(), Format::Obj).unwrap();
    // File order kept, the unused vertex 3 included; `w` divides.
    assert_eq!(m.vertex_count(), 5);
    assert_eq!(m.positions[3], DVec3::splat(9.0));
    assert_eq!(m.positions[4], DVec3::new(0.5, 0.5, 0.0));
    assert_eq!(
        faces(&m),
        vec![vec![0, 1, 2], vec![1, 4, 2, 0], vec![0, 1, 2]]
    );
    assert_eq!(m.normals.as_ref().unwrap()[0], DVec3::Z);
    let g = m
        .face_properties
        .iter()
        .find(|p| p.name == OBJ_GROUP)
        .unwrap();
    assert_eq!(g.values, PropertyValues::Int(vec![0, 1, 0]));
}

/// The cube as exporters write it with hard edges: eight vertices, one normal per face, so
/// every vertex's three corners name three different normals.
fn hard_edged_cube(face_order: &[usize], normal_order: &[usize]) -> String {
    let mut text = String::new();
    for k in 0..8 {
        let c = |bit: usize| if k & bit != 0 { 1 } else { -1 };
        text += &format!("v {} {} {}\n", c(1), c(2), c(4));
    }
    let normals = ["1 0 0", "-1 0 0", "0 1 0", "0 -1 0", "0 0 1", "0 0 -1"];
    for &n in normal_order {
        text += &format!("vn {}\n", normals[n]);
    }
    // Faces (outward, counter-clockwise) with the index of their normal in `normals`.
    let quads = [
        ([2, 4, 8, 6], 0),
        ([1, 5, 7, 3], 1),
        ([3, 7, 8, 4], 2),
        ([1, 2, 6, 5], 3),
        ([5, 6, 8, 7], 4),
        ([1, 3, 4, 2], 5),
    ];
    for &f in face_order {
        let (q, n) = quads[f];
        let vn = normal_order.iter().position(|&m| m == n).unwrap() + 1;
        let corners: Vec<String> = q.iter().map(|v| format!("{v}//{vn}")).collect();
        text += &format!("f {}\n", corners.join(" "));
    }
    text
}

#[test]
fn obj_hard_edge_normals_are_averaged_whatever_the_face_order() {
    // Each cube corner's three face normals average to its diagonal, the direction of its
    // position; before, a vertex kept the normal of the first face that named it, one of the
    // three axes, depending on the order of the faces.
    let read_cube = |faces: &[usize], normals: &[usize]| {
        read_bytes(hard_edged_cube(faces, normals).as_bytes(), Format::Obj).unwrap()
    };
    let m = read_cube(&[0, 1, 2, 3, 4, 5], &[0, 1, 2, 3, 4, 5]);
    let normals = m.normals.clone().unwrap();
    for (p, n) in m.positions.iter().zip(&normals) {
        assert_eq!(*n, p.normalize(), "vertex at {p}");
    }
    // The same bits in other orders of the faces and of the normals.
    for (faces, ns) in [
        ([5, 4, 3, 2, 1, 0], [0, 1, 2, 3, 4, 5]),
        ([2, 0, 5, 1, 3, 4], [4, 2, 0, 5, 3, 1]),
    ] {
        assert_eq!(read_cube(&faces, &ns).normals.unwrap(), normals);
    }
    // A value named by several corners (or several `vn` lines) counts once, and a vertex
    // whose corners agree keeps the file's value exactly.
    let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvn 0 0 1\nvn 0 0 1\nvn 0.6 0 0.8\n\
        f 1//1 2//3 3//1\nf 3//2 2//3 4//2\n";
    let m = read_bytes(text.as_bytes(), Format::Obj).unwrap();
    let n = m.normals.unwrap();
    assert_eq!(n[0], DVec3::Z);
    assert_eq!(n[1], DVec3::new(0.6, 0.0, 0.8));
    assert_eq!(n[2], DVec3::Z);
    assert_eq!(n[3], DVec3::Z);
    // Opposite normals cancel: no usable normal (zero), which the commands replace.
    let text =
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nvn 0 0 -1\nf 1//1 2//1 3//1\nf 1//2 3//2 2//2\n";
    let m = read_bytes(text.as_bytes(), Format::Obj).unwrap();
    assert_eq!(m.normals.unwrap(), vec![DVec3::ZERO; 3]);
}

#[test]
fn obj_errors_carry_line_numbers() {
    let e = read_bytes(b"v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 4\n", Format::Obj).unwrap_err();
    assert!(
        matches!(
            e,
            IoError::Parse {
                location: Location::Line(5),
                ..
            }
        ),
        "{e}"
    );
    assert!(e.to_string().contains("'4'"), "{e}");
    let e = read_bytes(b"v 0 0\n", Format::Obj).unwrap_err();
    assert!(e.to_string().contains("line 1"), "{e}");
}

#[test]
fn off_variants() {
    let m = read_bytes(
        b"OFF 4 2 0\n# c\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n3 0 1 2 255 0 0\n3 2 1 3\n",
        Format::Off,
    )
    .unwrap();
    assert_eq!(faces(&m), vec![vec![0, 1, 2], vec![2, 1, 3]]);
    let m = read_bytes(
        b"COFF\n3 1 0\n0 0 0 1 1 1 1\n1 0 0 1 1 1 1\n0 1 0 1 1 1 1\n3 0 1 2\n",
        Format::Off,
    )
    .unwrap();
    assert_eq!(m.vertex_count(), 3);
    let e = read_bytes(b"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 5\n", Format::Off).unwrap_err();
    assert!(e.to_string().contains("line 6"), "{e}");
}

#[test]
fn stl_in_the_wild() {
    // Ascii without a solid name; binary whose header starts with "solid".
    let ascii = "solid\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n\
        endloop\nendfacet\nendsolid\n";
    let m = read_bytes(ascii.as_bytes(), Format::Stl).unwrap();
    assert_eq!((m.vertex_count(), m.face_count()), (3, 1));
    let mut bin = b"solid but binary".to_vec();
    bin.resize(80, b' ');
    bin.extend(2u32.to_le_bytes());
    for tri in [
        [[0f32, 0., 0.], [1., 0., 0.], [0., 1., 0.]],
        [[1., 0., 0.], [1., 1., 0.], [0., 1., 0.]],
    ] {
        bin.extend([0u8; 12]);
        for p in tri {
            for c in p {
                bin.extend(c.to_le_bytes());
            }
        }
        bin.extend([0u8; 2]);
    }
    let m = read_bytes(&bin, Format::Stl).unwrap();
    assert_eq!((m.vertex_count(), m.face_count()), (4, 2));
    assert_eq!(faces(&m), vec![vec![0, 1, 2], vec![1, 3, 2]]);
    assert_eq!(Format::sniff(&bin), Some(Format::Stl));
    let e = read_bytes(&bin[..150], Format::Stl).unwrap_err();
    assert!(e.to_string().contains("byte 150"), "{e}");
}

#[test]
fn gltf_node_transforms_and_patch_ids() {
    // One triangle, drawn by two nodes: one translated, one mirrored (winding flips).
    let mut bin = Vec::new();
    for c in [0f32, 0., 0., 1., 0., 0., 0., 1., 0.] {
        bin.extend(c.to_le_bytes());
    }
    for i in [0u16, 1, 2, 0] {
        bin.extend(i.to_le_bytes());
    }
    for id in [5u8, 6, 7, 0] {
        bin.push(id);
    }
    let b64 = base64(&bin);
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0,1]}}],
        "nodes":[{{"mesh":0,"translation":[0,0,5]}},{{"mesh":0,"scale":[-1,1,1]}}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0,"_PATCH_ID":2}},"indices":1}}]}}],
        "accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}},
                     {{"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}},
                     {{"bufferView":2,"componentType":5121,"count":3,"type":"SCALAR"}}],
        "bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":36}},{{"buffer":0,"byteOffset":36,"byteLength":6}},
                       {{"buffer":0,"byteOffset":44,"byteLength":3}}],
        "buffers":[{{"byteLength":{},"uri":"data:application/octet-stream;base64,{}"}}]}}"#,
        bin.len(),
        b64
    );
    let m = read_bytes(json.as_bytes(), Format::Gltf).unwrap();
    assert_eq!(m.vertex_count(), 6);
    assert_eq!(m.positions[1], DVec3::new(1.0, 0.0, 5.0));
    assert_eq!(m.positions[4], DVec3::new(-1.0, 0.0, 0.0));
    assert_eq!(faces(&m), vec![vec![0, 1, 2], vec![3, 5, 4]]);
    let ids = m
        .vertex_properties
        .iter()
        .find(|p| p.name == PATCH_ID)
        .unwrap();
    assert_eq!(ids.values, PropertyValues::Int(vec![5, 6, 7, 5, 6, 7]));
    assert_eq!(Format::sniff(json.as_bytes()), Some(Format::Gltf));
}

fn base64(data: &[u8]) -> String {
    const T: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::new();
    for c in data.chunks(3) {
        let b = [c[0], *c.get(1).unwrap_or(&0), *c.get(2).unwrap_or(&0)];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for k in 0..4 {
            s.push(if k <= c.len() {
                T[((n >> (18 - 6 * k)) & 63) as usize] as char
            } else {
                '='
            });
        }
    }
    s
}

#[test]
fn format_by_extension_then_sniff() {
    let dir = std::env::temp_dir().join(format!("algesurf-io-sniff-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let obj = dir.join("mesh.data");
    std::fs::write(&obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    assert_eq!(read(&obj).unwrap().face_count(), 1);
    let ply = dir.join("mesh");
    std::fs::write(
        &ply,
        "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\nend_header\n",
    )
    .unwrap();
    assert_eq!(read(&ply).unwrap().vertex_count(), 0);
    let junk = dir.join("junk.bin");
    std::fs::write(&junk, [0u8, 1, 2, 3]).unwrap();
    assert!(matches!(read(&junk), Err(IoError::UnknownFormat { .. })));
    let missing = dir.join("missing.obj");
    let e = read(&missing).unwrap_err();
    assert!(matches!(e, IoError::Io { .. }) && e.to_string().contains("missing.obj"));
    assert_eq!(Format::sniff(b"OFF\n3 1 0\n"), Some(Format::Off));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A UTF-8 byte order mark (`EF BB BF`), as Windows editors write it, before text files.
fn with_bom(text: &[u8]) -> Vec<u8> {
    [b"\xEF\xBB\xBF".as_slice(), text].concat()
}

#[test]
fn text_files_with_a_byte_order_mark_read_as_without() {
    // OBJ: the mark once hid the first `v` (an unknown statement), so the file read one
    // vertex short and failed at its face "expected a vertex reference between 1 and 3".
    let obj = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\n";
    let plain = read_bytes(obj, Format::Obj).unwrap();
    let marked = read_bytes(&with_bom(obj), Format::Obj).unwrap();
    assert_eq!(marked.positions, plain.positions);
    assert_eq!(faces(&marked), faces(&plain));
    // Errors keep their line numbers (the mark is on line 1).
    let e = read_bytes(&with_bom(b"v 0 0 0\nv 1 0 0\nf 1 2 7\n"), Format::Obj).unwrap_err();
    assert!(e.to_string().contains("line 3"), "{e}");
    let off = b"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    assert_eq!(
        faces(&read_bytes(&with_bom(off), Format::Off).unwrap()),
        vec![vec![0, 1, 2]]
    );
    let stl = b"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n\
        vertex 0 1 0\nendloop\nendfacet\nendsolid x\n";
    let m = read_bytes(&with_bom(stl), Format::Stl).unwrap();
    assert_eq!((m.vertex_count(), m.face_count()), (3, 1));
    let gltf = algesurf_io::write_bytes(&plain, Format::Gltf, &Default::default()).unwrap();
    let m = read_bytes(&with_bom(&gltf), Format::Gltf).unwrap();
    assert_eq!((m.vertex_count(), m.face_count()), (4, 2));
    // Sniffed without an extension, too.
    for (text, format) in [
        (&obj[..], Format::Obj),
        (&off[..], Format::Off),
        (&stl[..], Format::Stl),
        (&gltf[..], Format::Gltf),
    ] {
        assert_eq!(Format::sniff(&with_bom(text)), Some(format));
    }
}
