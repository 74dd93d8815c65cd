//! Writes one sample mesh (a triangulated torus with normals and a per-vertex patch id) in every
//! format and flavour into the folder given as the first argument, and prints one line per
//! file: `path<TAB>vertices<TAB>triangles`. Used by `cargo xtask ci` (xtask/src/interop.rs) to
//! check that other tools (trimesh, the Khronos glTF validator) read our output.
//!
//! ```text
//! cargo run -p algesurf-io --example write_samples -- target/interop/samples
//! ```

use std::f64::consts::TAU;
use std::path::PathBuf;

use algesurf_io::{Format, PATCH_ID, WriteOptions, write_as};
use algesurf_mesh::{PolygonMesh, Property, PropertyValues};
use glam::DVec3;

fn torus(n: u32, m: u32) -> PolygonMesh {
    let (big, small) = (1.0, 0.35);
    let mut mesh = PolygonMesh::new();
    let mut normals = Vec::new();
    for i in 0..n {
        for j in 0..m {
            let (u, v) = (TAU * i as f64 / n as f64, TAU * j as f64 / m as f64);
            let c = DVec3::new(u.cos(), u.sin(), 0.0);
            let nrm = c * v.cos() + DVec3::Z * v.sin();
            mesh.positions.push(c * big + nrm * small);
            normals.push(nrm);
        }
    }
    let id = |i: u32, j: u32| (i % n) * m + (j % m);
    for i in 0..n {
        for j in 0..m {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            mesh.push_face(&[a, b, c]);
            mesh.push_face(&[a, c, d]);
        }
    }
    mesh.normals = Some(normals);
    mesh.vertex_properties.push(Property {
        name: PATCH_ID.into(),
        values: PropertyValues::Int((0..(n * m) as i64).map(|v| v / 16).collect()),
    });
    mesh
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = PathBuf::from(std::env::args().nth(1).ok_or("usage: write_samples DIR")?);
    std::fs::create_dir_all(&dir)?;
    let mesh = torus(24, 12);
    let d = WriteOptions::default();
    let ascii = WriteOptions { ascii: true, ..d };
    for (name, format, options) in [
        ("torus.obj", Format::Obj, d),
        (
            "torus_f32.obj",
            Format::Obj,
            WriteOptions { f32: true, ..d },
        ),
        ("torus.ply", Format::Ply, d),
        ("torus_ascii.ply", Format::Ply, ascii),
        (
            "torus_be.ply",
            Format::Ply,
            WriteOptions {
                big_endian: true,
                ..d
            },
        ),
        ("torus.stl", Format::Stl, d),
        ("torus_ascii.stl", Format::Stl, ascii),
        ("torus.off", Format::Off, d),
        ("torus.glb", Format::Glb, d),
        ("torus.gltf", Format::Gltf, d),
    ] {
        let path = dir.join(name);
        write_as(&path, &mesh, format, &options)?;
        println!(
            "{}\t{}\t{}",
            path.display(),
            mesh.vertex_count(),
            mesh.face_count()
        );
    }
    Ok(())
}
