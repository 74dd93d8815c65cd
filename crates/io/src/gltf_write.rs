//! Writing glTF 2.0 and GLB: the document through `gltf-json` types, the binary buffer by
//! hand. One buffer holds, in this order, the positions (`VEC3` of `f32`), the normals (unit
//! `f32`, when written), the patch ids (`_PATCH_ID`, `f32`) and the triangle indices (`u32`),
//! each a buffer view of its own; polygons are written as fans ([`crate::fan_triangles`]).
//!
//! A GLB's binary chunk is streamed to the file in blocks encoded in parallel
//! ([`crate::blocks`]), after a JSON chunk made from the arrays' lengths alone: the whole
//! file was built in memory first (each array, then the buffer, then the GLB, growing by
//! doubling), and on the `smooth` command's 1.36 M-triangle output of spot those ~35 MB of
//! copies into fresh pages were most of the write stage's own work. A `.gltf` embeds the
//! buffer as base64 in its JSON, so it is still encoded in memory.

use std::collections::BTreeMap;

use algesurf_mesh::{PolygonMesh, PropertyValues};
use glam::DVec3;
use gltf::mesh::Mode;
use gltf_json::accessor::{ComponentType, Type};
use gltf_json::buffer::Target;
use gltf_json::validation::Checked::Valid;

use crate::blocks::write_blocks;
use crate::error::Ctx;
use crate::gltf_io::PATCH_ATTRIBUTE;
use crate::{IoError, PATCH_ID, WriteOptions, fan_triangles};

fn base64_encode(data: &[u8]) -> String {
    const T: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(data.len().div_ceil(3) * 4);
    for chunk in data.chunks(3) {
        let b = [
            chunk[0],
            *chunk.get(1).unwrap_or(&0),
            *chunk.get(2).unwrap_or(&0),
        ];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(T[((n >> (18 - 6 * k)) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

/// The triangles written: the faces themselves when every face is a triangle (the `smooth`
/// command's output), else the fans of the polygons.
enum Triangles<'a> {
    Faces(&'a PolygonMesh),
    Fans(Vec<[u32; 3]>),
}

impl Triangles<'_> {
    fn len(&self) -> usize {
        match self {
            Triangles::Faces(mesh) => mesh.face_count(),
            Triangles::Fans(t) => t.len(),
        }
    }

    fn get(&self, t: usize) -> [u32; 3] {
        match self {
            Triangles::Faces(mesh) => {
                let f = mesh.face(t);
                [f[0], f[1], f[2]]
            }
            Triangles::Fans(tris) => tris[t],
        }
    }
}

/// The patch ids as the `f32` glTF stores, read from the property's own column.
enum PatchIds<'a> {
    Int(&'a [i64]),
    Float(&'a [f64]),
}

impl PatchIds<'_> {
    fn get(&self, i: usize) -> f64 {
        match self {
            PatchIds::Int(v) => v[i] as f64,
            PatchIds::Float(v) => v[i],
        }
    }
}

/// What goes into the binary buffer, checked: every position finite in `f32`, every patch id
/// exact in `f32`.
struct Content<'a> {
    mesh: &'a PolygonMesh,
    /// The positions' `f32` bounding box (the accessor's `min` and `max`); `None` without
    /// vertices.
    bounds: Option<([f32; 3], [f32; 3])>,
    normals: Option<&'a [DVec3]>,
    patch: Option<PatchIds<'a>>,
    triangles: Triangles<'a>,
}

/// Byte length of the binary buffer's views, in their order: 12 bytes per position and
/// normal, 4 per patch id, 12 per triangle, so every view starts 4-byte aligned as glTF
/// requires and no padding is ever needed.
const POSITION_BYTES: usize = 12;
const NORMAL_BYTES: usize = 12;
const PATCH_BYTES: usize = 4;
const TRIANGLE_BYTES: usize = 12;

impl<'a> Content<'a> {
    fn of(mesh: &'a PolygonMesh, options: &WriteOptions, ctx: Ctx<'_>) -> Result<Self, IoError> {
        let n = mesh.vertex_count();
        // One pass in vertex order: `f32::min` and `max` may answer either zero for
        // `0.0` against `-0.0`, so another order could write another sign in the box.
        let mut lo = [f32::INFINITY; 3];
        let mut hi = [f32::NEG_INFINITY; 3];
        for (i, p) in mesh.positions.iter().enumerate() {
            let q = [p.x as f32, p.y as f32, p.z as f32];
            if q.iter().any(|x| !x.is_finite()) {
                return Err(ctx.invalid(format!(
                    "vertex {i} has a position that is not finite in f32: {p}"
                )));
            }
            for k in 0..3 {
                lo[k] = lo[k].min(q[k]);
                hi[k] = hi[k].max(q[k]);
            }
        }
        let normals = mesh.normals.as_deref().filter(|_| options.normals && n > 0);
        let patch = match mesh.vertex_properties.iter().find(|p| p.name == PATCH_ID) {
            Some(p) if n > 0 => Some(match &p.values {
                PropertyValues::Int(v) => PatchIds::Int(v),
                PropertyValues::Float(v) => PatchIds::Float(v),
            }),
            _ => None,
        };
        if let Some(ids) = &patch {
            // FLOAT: vertex attributes must be 4-byte aligned per element, and UNSIGNED_INT
            // is for indices only; f32 holds integer ids exactly up to 2^24.
            if let Some(i) = (0..n).find(|&i| (ids.get(i) as f32) as f64 != ids.get(i)) {
                return Err(ctx.invalid(format!(
                    "patch id {} of vertex {i} is not exactly representable as the f32 of \
                     glTF's _PATCH_ID",
                    ids.get(i)
                )));
            }
        }
        let triangles = if mesh.faces().all(|f| f.len() == 3) {
            Triangles::Faces(mesh)
        } else {
            Triangles::Fans(fan_triangles(mesh))
        };
        Ok(Content {
            mesh,
            bounds: (n > 0).then_some((lo, hi)),
            normals,
            patch,
            triangles,
        })
    }

    /// The views' byte lengths, in buffer order (zero for a view not written).
    fn view_lengths(&self) -> [usize; 4] {
        let n = self.mesh.vertex_count();
        [
            if self.bounds.is_some() {
                n * POSITION_BYTES
            } else {
                0
            },
            self.normals.map_or(0, |_| n * NORMAL_BYTES),
            self.patch.as_ref().map_or(0, |_| n * PATCH_BYTES),
            self.triangles.len() * TRIANGLE_BYTES,
        ]
    }

    /// The binary buffer's length: its views', back to back.
    fn bin_len(&self) -> usize {
        self.view_lengths().iter().sum()
    }

    /// Streams the binary buffer to `sink`, view after view.
    fn write_bin(&self, sink: &mut dyn std::io::Write) -> std::io::Result<()> {
        let n = self.mesh.vertex_count();
        let f32s = |out: &mut Vec<u8>, xs: [f64; 3]| {
            for x in xs {
                out.extend_from_slice(&(x as f32).to_le_bytes());
            }
        };
        if self.bounds.is_some() {
            let ps = &self.mesh.positions;
            write_blocks(n, sink, &|range, out| {
                for p in &ps[range] {
                    f32s(out, [p.x, p.y, p.z]);
                }
            })?;
        }
        if let Some(ns) = self.normals {
            // glTF normals must be unit length: zero or non-finite normals become +Z.
            write_blocks(n, sink, &|range, out| {
                for v in &ns[range] {
                    let u = v.normalize_or_zero();
                    let u = if u == DVec3::ZERO { DVec3::Z } else { u };
                    f32s(out, [u.x, u.y, u.z]);
                }
            })?;
        }
        if let Some(ids) = &self.patch {
            write_blocks(n, sink, &|range, out| {
                for i in range {
                    out.extend_from_slice(&(ids.get(i) as f32).to_le_bytes());
                }
            })?;
        }
        write_blocks(self.triangles.len(), sink, &|range, out| {
            for t in range {
                for v in self.triangles.get(t) {
                    out.extend_from_slice(&v.to_le_bytes());
                }
            }
        })
    }

    /// The glTF document for a buffer of `bin_len` bytes (embedded as `uri` for `.gltf`).
    fn document(&self, uri: Option<String>) -> gltf_json::Root {
        let mut root = gltf_json::Root::default();
        root.asset.generator = Some("algesurf".into());
        let mut attributes = BTreeMap::new();
        let mut offset = 0;
        let mut view = |root: &mut gltf_json::Root, len: usize, target: Target| {
            let v = push_view(root, offset, len, target);
            offset += len;
            v
        };
        let [positions, normals, patch, indices] = self.view_lengths();
        let n = self.mesh.vertex_count();
        if let Some((lo, hi)) = self.bounds {
            let v = view(&mut root, positions, Target::ArrayBuffer);
            let minmax = Some((lo.to_vec(), hi.to_vec()));
            let acc = push_accessor(&mut root, v, n, ComponentType::F32, Type::Vec3, minmax);
            attributes.insert(Valid(gltf::Semantic::Positions), acc);
        }
        if self.normals.is_some() {
            let v = view(&mut root, normals, Target::ArrayBuffer);
            let acc = push_accessor(&mut root, v, n, ComponentType::F32, Type::Vec3, None);
            attributes.insert(Valid(gltf::Semantic::Normals), acc);
        }
        if self.patch.is_some() {
            let v = view(&mut root, patch, Target::ArrayBuffer);
            let acc = push_accessor(&mut root, v, n, ComponentType::F32, Type::Scalar, None);
            let name = gltf::Semantic::Extras(PATCH_ATTRIBUTE.into());
            attributes.insert(Valid(name), acc);
        }
        let mut nodes = Vec::new();
        let tris = self.triangles.len();
        if tris > 0 {
            let v = view(&mut root, indices, Target::ElementArrayBuffer);
            let indices = push_accessor(
                &mut root,
                v,
                tris * 3,
                ComponentType::U32,
                Type::Scalar,
                None,
            );
            let primitive = gltf_json::mesh::Primitive {
                attributes,
                extensions: None,
                extras: Default::default(),
                indices: Some(indices),
                material: None,
                mode: Valid(Mode::Triangles),
                targets: None,
            };
            let mesh_index = root.push(gltf_json::Mesh {
                extensions: None,
                extras: Default::default(),
                name: None,
                primitives: vec![primitive],
                weights: None,
            });
            nodes.push(root.push(gltf_json::Node {
                mesh: Some(mesh_index),
                ..Default::default()
            }));
        }
        if !nodes.is_empty() {
            let scene = root.push(gltf_json::Scene {
                extensions: None,
                extras: Default::default(),
                name: None,
                nodes,
            });
            root.scene = Some(scene);
        }
        let bin_len = self.bin_len();
        if bin_len > 0 {
            root.push(gltf_json::Buffer {
                byte_length: bin_len.into(),
                extensions: None,
                extras: Default::default(),
                name: None,
                uri,
            });
        }
        root
    }
}

/// Adds the buffer view of `len` bytes at `offset` and returns its index.
fn push_view(
    root: &mut gltf_json::Root,
    offset: usize,
    len: usize,
    target: Target,
) -> gltf_json::Index<gltf_json::buffer::View> {
    debug_assert!(offset.is_multiple_of(4), "views are 4-byte aligned");
    root.push(gltf_json::buffer::View {
        buffer: gltf_json::Index::new(0),
        byte_length: len.into(),
        byte_offset: Some(offset.into()),
        byte_stride: None,
        extensions: None,
        extras: Default::default(),
        name: None,
        target: Some(Valid(target)),
    })
}

fn push_accessor(
    root: &mut gltf_json::Root,
    view: gltf_json::Index<gltf_json::buffer::View>,
    count: usize,
    component: ComponentType,
    type_: Type,
    min_max: Option<(Vec<f32>, Vec<f32>)>,
) -> gltf_json::Index<gltf_json::Accessor> {
    let (min, max) = match min_max {
        Some((lo, hi)) => (Some(lo.into()), Some(hi.into())),
        None => (None, None),
    };
    root.push(gltf_json::Accessor {
        buffer_view: Some(view),
        byte_offset: None,
        count: count.into(),
        component_type: Valid(gltf_json::accessor::GenericComponentType(component)),
        extensions: None,
        extras: Default::default(),
        type_: Valid(type_),
        min,
        max,
        name: None,
        normalized: false,
        sparse: None,
    })
}

/// Writes `mesh` as glTF (`ctx.format` [`crate::Format::Gltf`]: one JSON file, the buffer
/// embedded as base64) or GLB (a JSON chunk and a binary chunk, the latter streamed) to
/// `sink`.
///
/// # Errors
/// [`IoError::InvalidMesh`] for a position not finite in `f32`, a patch id not exact in `f32`,
/// or a GLB over the 4 GiB its 32-bit lengths allow, all found before anything is written;
/// [`IoError::Io`] when `sink` fails.
pub(crate) fn write_to(
    mesh: &PolygonMesh,
    options: &WriteOptions,
    ctx: Ctx<'_>,
    sink: &mut dyn std::io::Write,
) -> Result<(), IoError> {
    let io_err = |source| ctx.io(source);
    let content = Content::of(mesh, options, ctx)?;
    let json = |root: &gltf_json::Root| {
        gltf_json::serialize::to_vec(root)
            .map_err(|e| ctx.invalid(format!("JSON serialisation failed: {e}")))
    };
    if ctx.format != crate::Format::Glb {
        let mut bin = Vec::with_capacity(content.bin_len());
        content.write_bin(&mut bin).map_err(io_err)?;
        let uri = (!bin.is_empty()).then(|| {
            format!(
                "data:application/octet-stream;base64,{}",
                base64_encode(&bin)
            )
        });
        drop(bin);
        let text = json(&content.document(uri))?;
        sink.write_all(&text).map_err(io_err)?;
        return sink.flush().map_err(io_err);
    }
    let mut text = json(&content.document(None))?;
    // GLB 2.0 (glTF spec §4.4): a 12-byte header (magic, version, total length), then chunks
    // of an 8-byte header (length, type) and data padded to 4 bytes: the JSON with spaces,
    // the binary buffer with zeros (never needed here: its views are multiples of 4 bytes).
    while !text.len().is_multiple_of(4) {
        text.push(b' ');
    }
    let bin_len = content.bin_len();
    let total = 12 + 8 + text.len() + if bin_len > 0 { 8 + bin_len } else { 0 };
    // Every other length is smaller than the total, so one check covers them all.
    let total32 = u32::try_from(total).map_err(|_| {
        ctx.invalid(format!(
            "the GLB would be {total} bytes; its 32-bit lengths allow at most {} \
             (write .ply for larger meshes)",
            u32::MAX
        ))
    })?;
    let mut head = Vec::with_capacity(20);
    head.extend_from_slice(b"glTF");
    head.extend_from_slice(&2u32.to_le_bytes());
    head.extend_from_slice(&total32.to_le_bytes());
    head.extend_from_slice(&(text.len() as u32).to_le_bytes());
    head.extend_from_slice(b"JSON");
    sink.write_all(&head).map_err(io_err)?;
    sink.write_all(&text).map_err(io_err)?;
    if bin_len > 0 {
        let mut chunk = Vec::with_capacity(8);
        chunk.extend_from_slice(&(bin_len as u32).to_le_bytes());
        chunk.extend_from_slice(b"BIN\0");
        sink.write_all(&chunk).map_err(io_err)?;
        content.write_bin(sink).map_err(io_err)?;
    }
    sink.flush().map_err(io_err)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Format;
    use std::path::Path;

    /// A mesh of triangles and quads with normals (one zero) and patch ids, `n × n` quads.
    fn mesh(n: u32) -> PolygonMesh {
        let mut m = PolygonMesh::new();
        for j in 0..=n {
            for i in 0..=n {
                m.positions
                    .push(DVec3::new(i as f64, j as f64, (i * j) as f64 / 7.0) / 3.0);
            }
        }
        let id = |i: u32, j: u32| j * (n + 1) + i;
        for j in 0..n {
            for i in 0..n {
                let q = [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)];
                if (i + j) % 3 == 0 {
                    m.push_face(&q);
                } else {
                    m.push_face(&[q[0], q[1], q[2]]);
                    m.push_face(&[q[0], q[2], q[3]]);
                }
            }
        }
        let nv = m.vertex_count();
        let mut normals = vec![DVec3::new(0.1, -0.2, 1.0); nv];
        normals[3] = DVec3::ZERO;
        m.normals = Some(normals);
        m.vertex_properties.push(algesurf_mesh::Property {
            name: PATCH_ID.into(),
            values: PropertyValues::Int((0..nv as i64).map(|v| v % 97).collect()),
        });
        m
    }

    /// The streamed GLB is the `gltf` crate's packing (`Glb::to_vec`) of the same document
    /// and binary buffer, byte for byte: header length, the JSON chunk padded with spaces,
    /// the binary chunk; for a mesh several blocks long and for an empty one.
    #[test]
    fn streamed_glb_is_the_gltf_crates_packing() {
        let ctx = Ctx {
            path: Path::new("t.glb"),
            format: Format::Glb,
        };
        for m in [mesh(150), mesh(2), PolygonMesh::new()] {
            let options = WriteOptions::default();
            let mut streamed = Vec::new();
            write_to(&m, &options, ctx, &mut streamed).unwrap();
            let content = Content::of(&m, &options, ctx).unwrap();
            let mut bin = Vec::new();
            content.write_bin(&mut bin).unwrap();
            let json = gltf_json::serialize::to_vec(&content.document(None)).unwrap();
            let packed = gltf::binary::Glb {
                header: gltf::binary::Header {
                    magic: *b"glTF",
                    version: 2,
                    length: 0,
                },
                json: std::borrow::Cow::Owned(json),
                bin: (!bin.is_empty()).then_some(std::borrow::Cow::Owned(bin)),
            }
            .to_vec()
            .unwrap();
            assert!(streamed == packed, "{} vertices", m.vertex_count());
        }
    }
}
