//! No input makes a reader panic: random bytes, and valid files truncated, flipped, spliced.

mod common;

use algesurf_io::{Format, WriteOptions, read_bytes, write_bytes};
use proptest::prelude::*;

/// Valid files of every format and flavour, plus hand-written in-the-wild samples.
fn seeds() -> Vec<(Format, Vec<u8>)> {
    let mesh = common::grid(2, 2, true);
    let d = WriteOptions::default();
    let mut out = vec![];
    for (f, o) in [
        (Format::Obj, d),
        (Format::Off, d),
        (Format::Ply, d),
        (Format::Ply, WriteOptions { ascii: true, ..d }),
        (
            Format::Ply,
            WriteOptions {
                big_endian: true,
                ..d
            },
        ),
        (Format::Stl, d),
        (Format::Stl, WriteOptions { ascii: true, ..d }),
        (Format::Glb, d),
        (Format::Gltf, d),
    ] {
        out.push((f, write_bytes(&mesh, f, &o).unwrap()));
    }
    out.push((Format::Ply, WILD_PLY.as_bytes().to_vec()));
    out.push((Format::Obj, WILD_OBJ.as_bytes().to_vec()));
    out
}

const WILD_PLY: &str = "ply\nformat ascii 1.0\ncomment x\nelement vertex 4\nproperty float x\n\
property float y\nproperty float z\nproperty uchar red\nelement tristrips 1\n\
property list int int vertex_indices\nelement edge 1\nproperty int vertex1\nproperty int vertex2\n\
end_header\n0 0 0 1\n1 0 0 2\n0 1 0 3\n1 1 0 4\n6 0 1 2 -1 1 2 3\n0 1\n";

const WILD_OBJ: &str = "g a\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf -3//1 -2//1 -1//1\n\
g b\nv 1 1 0 1\nf 2 4 3 1\n";

fn read_all_formats(bytes: &[u8]) {
    for f in Format::ALL {
        let _ = read_bytes(bytes, f);
    }
    let _ = Format::sniff(bytes);
}

#[derive(Debug, Clone)]
enum Mutation {
    Truncate(prop::sample::Index),
    Flip(prop::sample::Index, u8),
    Insert(prop::sample::Index, Vec<u8>),
    Delete(prop::sample::Index, usize),
    /// Overwrite with a "dangerous" number as text or binary.
    Number(prop::sample::Index, u32),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        any::<prop::sample::Index>().prop_map(Mutation::Truncate),
        (any::<prop::sample::Index>(), 1..=255u8).prop_map(|(i, b)| Mutation::Flip(i, b)),
        (
            any::<prop::sample::Index>(),
            prop::collection::vec(any::<u8>(), 1..8)
        )
            .prop_map(|(i, v)| Mutation::Insert(i, v)),
        (any::<prop::sample::Index>(), 1..16usize).prop_map(|(i, n)| Mutation::Delete(i, n)),
        (
            any::<prop::sample::Index>(),
            prop_oneof![
                Just(0u32),
                Just(u32::MAX),
                Just(0x7fff_ffff),
                Just(0x8000_0000),
                any::<u32>()
            ]
        )
            .prop_map(|(i, n)| Mutation::Number(i, n)),
    ]
}

fn apply(bytes: &mut Vec<u8>, m: &Mutation) {
    if bytes.is_empty() {
        return;
    }
    match m {
        Mutation::Truncate(i) => bytes.truncate(i.index(bytes.len())),
        Mutation::Flip(i, b) => {
            let k = i.index(bytes.len());
            bytes[k] ^= b;
        }
        Mutation::Insert(i, v) => {
            let k = i.index(bytes.len());
            bytes.splice(k..k, v.iter().copied());
        }
        Mutation::Delete(i, n) => {
            let k = i.index(bytes.len());
            let e = (k + n).min(bytes.len());
            bytes.drain(k..e);
        }
        Mutation::Number(i, n) => {
            let k = i.index(bytes.len());
            if k % 2 == 0 {
                let text = format!("{}", *n as i32);
                bytes.splice(k..(k + 1).min(bytes.len()), text.bytes());
            } else {
                for (j, b) in n.to_le_bytes().into_iter().enumerate() {
                    if let Some(x) = bytes.get_mut(k + j) {
                        *x = b;
                    }
                }
            }
        }
    }
}

#[test]
fn every_prefix_of_every_seed_is_handled() {
    let mut total = 0;
    for (format, seed) in seeds() {
        let mesh = read_bytes(&seed, format).unwrap_or_else(|e| panic!("seed {format}: {e}"));
        assert!(mesh.face_count() > 0);
        total += seed.len();
        for n in 0..seed.len() {
            read_all_formats(&seed[..n]);
        }
    }
    assert!(total > 5000, "{total}");
}

#[test]
fn lying_headers_are_rejected_without_allocating() {
    let huge = "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\n\
                property float y\nproperty float z\nend_header\n";
    assert!(read_bytes(huge.as_bytes(), Format::Ply).is_err());
    let empty_elem = "ply\nformat ascii 1.0\nelement junk 4000000000\nend_header\n";
    assert!(read_bytes(empty_elem.as_bytes(), Format::Ply).is_err());
    let off = "OFF\n4000000000 4000000000 0\n";
    assert!(read_bytes(off.as_bytes(), Format::Off).is_err());
    let mut stl = vec![0u8; 84];
    stl[80..84].copy_from_slice(&u32::MAX.to_le_bytes());
    assert!(read_bytes(&stl, Format::Stl).is_err());
}

proptest! {
    // 512 cases per property in `cargo test`; `PROPTEST_CASES=100000` for a long run.
    #![proptest_config(ProptestConfig {
        cases: std::env::var("PROPTEST_CASES").ok().and_then(|s| s.parse().ok()).unwrap_or(512),
        ..ProptestConfig::default()
    })]

    #[test]
    fn random_bytes(bytes in prop::collection::vec(any::<u8>(), 0..2048)) {
        read_all_formats(&bytes);
    }

    #[test]
    fn random_bytes_after_a_magic(magic in prop::sample::select(vec![
            &b"ply\nformat ascii 1.0\n"[..], b"ply\nformat binary_little_endian 1.0\nelement vertex 3\n",
            b"glTF\x02\x00\x00\x00", b"solid x\n", b"OFF\n", b"v 1 2 3\nf ", b"{\"asset\":{\"version\":\"2.0\"},"]),
        tail in prop::collection::vec(any::<u8>(), 0..512)) {
        let mut bytes = magic.to_vec();
        bytes.extend(tail);
        read_all_formats(&bytes);
    }

    #[test]
    fn mutated_valid_files(seed in prop::sample::select(seeds()), ms in prop::collection::vec(mutation(), 1..4)) {
        let (_, mut bytes) = seed;
        for m in &ms {
            apply(&mut bytes, m);
        }
        read_all_formats(&bytes);
    }
}

/// Found by a long proptest run: gltf-json's validation indexed a primitive's POSITION
/// accessor without a bounds check.
#[test]
fn gltf_position_accessor_out_of_range() {
    let json =
        r#"{"asset":{"version":"2.0"},"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}]}"#;
    let e = read_bytes(json.as_bytes(), Format::Gltf).unwrap_err();
    assert!(e.to_string().contains("mesh 0"), "{e}");
}
