//! STL, ascii and binary: read with `stl_io`, binary written with `stl_io`, ascii written by hand.
//!
//! STL stores unconnected triangles; the reader merges bit-identical corner positions into one
//! vertex, numbered in order of first appearance, and keeps the triangle order.

use std::borrow::Cow;
use std::io::Cursor;

use algesurf_mesh::PolygonMesh;
use glam::DVec3;

use crate::error::{Ctx, Location};
use crate::{IoError, WriteOptions, fan_triangles, number};

pub(crate) fn read(bytes: &[u8], ctx: Ctx<'_>) -> Result<PolygonMesh, IoError> {
    let binary_len = |b: &[u8]| -> Option<u64> {
        (b.len() >= 84).then(|| 84 + 50 * u32::from_le_bytes([b[80], b[81], b[82], b[83]]) as u64)
    };
    let exact_binary = binary_len(bytes) == Some(bytes.len() as u64);
    // An ascii file may start with a UTF-8 byte order mark ([`crate::without_bom`]); it is
    // looked past only for the ascii probe, as a binary header may start with any bytes.
    let text = crate::without_bom(bytes);
    let start = text
        .iter()
        .position(|b| !b.is_ascii_whitespace())
        .unwrap_or(text.len());
    let looks_ascii = text[start..].starts_with(b"solid")
        && text[start..text.len().min(start + 1024)]
            .windows(5)
            .any(|w| w == b"facet" || w == b"endso");
    let data: Cow<'_, [u8]> = if !exact_binary && looks_ascii {
        // stl_io wants the first line to start with "solid " (with a space).
        let body = &text[start..];
        if body.get(5) == Some(&b' ') {
            Cow::Borrowed(body)
        } else {
            let mut v = b"solid ".to_vec();
            v.extend_from_slice(&body[5..]);
            Cow::Owned(v)
        }
    } else {
        let Some(expected) = binary_len(bytes) else {
            return Err(ctx.parse(
                Location::Byte(bytes.len() as u64),
                "an 80-byte header and a 4-byte triangle count (binary STL) or 'solid' (ascii STL)",
            ));
        };
        if (bytes.len() as u64) < expected {
            return Err(ctx.parse(
                Location::Byte(bytes.len() as u64),
                format!(
                    "{} bytes for {} triangles, but the file ends",
                    expected,
                    (expected - 84) / 50
                ),
            ));
        }
        // Binary: hide a header that starts with "solid" from stl_io's ascii probe, and ignore
        // trailing bytes after the last triangle.
        let mut v = bytes[..expected as usize].to_vec();
        if v.starts_with(b"solid") {
            v[..5].copy_from_slice(b"SOLID");
        }
        Cow::Owned(v)
    };
    let indexed = stl_io::read_stl(&mut Cursor::new(&data[..]))
        .map_err(|e| ctx.parse(Location::File, format!("valid STL ({e})")))?;
    let mut mesh = PolygonMesh::new();
    mesh.positions = indexed
        .vertices
        .iter()
        .map(|v| DVec3::new(v.0[0] as f64, v.0[1] as f64, v.0[2] as f64))
        .collect();
    for t in &indexed.faces {
        mesh.push_face(&t.vertices.map(|v| v as u32));
    }
    Ok(mesh)
}

fn face_normal(mesh: &PolygonMesh, t: &[u32; 3]) -> DVec3 {
    let [a, b, c] = t.map(|v| mesh.positions[v as usize]);
    (b - a).cross(c - a).normalize_or_zero()
}

pub(crate) fn write(mesh: &PolygonMesh, options: &WriteOptions) -> Vec<u8> {
    let tris = fan_triangles(mesh);
    if options.ascii {
        let mut out = String::with_capacity(tris.len() * 250);
        out.push_str("solid algesurf\n");
        for t in &tris {
            out.push_str("facet normal ");
            number::push3(&mut out, face_normal(mesh, t), true);
            out.push_str("\n  outer loop\n");
            for &v in t {
                out.push_str("    vertex ");
                number::push3(&mut out, mesh.positions[v as usize], true);
                out.push('\n');
            }
            out.push_str("  endloop\nendfacet\n");
        }
        out.push_str("endsolid algesurf\n");
        out.into_bytes()
    } else {
        let f3 = |v: DVec3| stl_io::Vector::new([v.x as f32, v.y as f32, v.z as f32]);
        let triangles: Vec<stl_io::Triangle> = tris
            .iter()
            .map(|t| stl_io::Triangle {
                normal: f3(face_normal(mesh, t)),
                vertices: t.map(|v| f3(mesh.positions[v as usize])),
            })
            .collect();
        let mut out = Vec::with_capacity(84 + 50 * triangles.len());
        // Writing to a Vec cannot fail.
        let _ = stl_io::write_stl(&mut out, triangles.iter());
        out
    }
}
