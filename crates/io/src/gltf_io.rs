//! Reading glTF 2.0 and GLB: documents parsed with the `gltf` crate, accessor data read by
//! hand with checked bounds (the crate's own readers may panic on malformed accessors).
//!
//! Reading walks the default scene (or the first, or every root node when there is no scene),
//! applies node transforms to positions and normals (flipping the winding of mirrored nodes),
//! and concatenates the triangle primitives (`TRIANGLES`, `TRIANGLE_STRIP`, `TRIANGLE_FAN`) in
//! that order. The custom attribute `_PATCH_ID` becomes the vertex property
//! [`crate::PATCH_ID`]. Writing is `crate::gltf_write`'s.

use std::borrow::Cow;
use std::path::Path;

use algesurf_mesh::{PolygonMesh, Property, PropertyValues};
use glam::{DMat3, DMat4, DVec3};
use gltf::accessor::{DataType, Dimensions};
use gltf::mesh::Mode;

use crate::error::{Ctx, Location};
use crate::{IoError, PATCH_ID};

/// The glTF name of the [`PATCH_ID`] vertex attribute: `_PATCH_ID` without the leading
/// underscore, which the `gltf` crate's `Semantic::Extras` adds.
pub(crate) const PATCH_ATTRIBUTE: &str = "PATCH_ID";

fn base64_decode(s: &str) -> Option<Vec<u8>> {
    let mut out = Vec::with_capacity(s.len() / 4 * 3);
    let mut acc = 0u32;
    let mut bits = 0;
    for c in s.bytes() {
        let v = match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' | b'-' => 62,
            b'/' | b'_' => 63,
            b'=' | b'\n' | b'\r' | b' ' => continue,
            _ => return None,
        };
        acc = (acc << 6) | u32::from(v);
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
            acc &= (1 << bits) - 1;
        }
    }
    Some(out)
}

/// Reads accessor `acc` as `f64` components (`dims` per element), with bounds checked.
fn read_accessor(
    acc: &gltf::Accessor<'_>,
    buffers: &[Cow<'_, [u8]>],
    ctx: Ctx<'_>,
) -> Result<(Vec<f64>, usize), IoError> {
    let id = acc.index();
    let loc = Location::Element("accessor", id);
    let bad = |what: &str| ctx.parse(loc, what.to_string());
    if acc.sparse().is_some() {
        return Err(ctx.unsupported(loc, "sparse accessors"));
    }
    let dims = match acc.dimensions() {
        Dimensions::Scalar => 1,
        Dimensions::Vec2 => 2,
        Dimensions::Vec3 => 3,
        Dimensions::Vec4 => 4,
        _ => return Err(ctx.unsupported(loc, "matrix accessors for vertex data")),
    };
    let dt = acc.data_type();
    let csize = dt.size();
    let count = acc.count();
    let Some(view) = acc.view() else {
        // No buffer view: all zeros (the data could only come from a sparse part).
        let n = count
            .checked_mul(dims)
            .filter(|&n| n <= 1 << 28)
            .ok_or_else(|| bad("a sane element count"))?;
        return Ok((vec![0.0; n], dims));
    };
    let buffer = buffers
        .get(view.buffer().index())
        .ok_or_else(|| bad("a buffer for its buffer view"))?;
    let elem = csize * dims;
    let stride = view.stride().unwrap_or(elem);
    if stride < elem {
        return Err(bad("a byte stride of at least the element size"));
    }
    let view_end = view
        .offset()
        .checked_add(view.length())
        .filter(|&e| e <= buffer.len())
        .ok_or_else(|| bad("a buffer view inside its buffer"))?;
    let start = view
        .offset()
        .checked_add(acc.offset())
        .ok_or_else(|| bad("an offset inside its buffer view"))?;
    if count == 0 {
        return Ok((Vec::new(), dims));
    }
    let end = (count - 1)
        .checked_mul(stride)
        .and_then(|x| x.checked_add(elem))
        .and_then(|x| x.checked_add(start))
        .filter(|&e| e <= view_end)
        .ok_or_else(|| bad("count × stride inside its buffer view"))?;
    let data = &buffer[start..end];
    let norm = acc.normalized();
    let mut out = Vec::with_capacity(count * dims);
    for i in 0..count {
        for c in 0..dims {
            let o = i * stride + c * csize;
            let b = &data[o..o + csize];
            let v = match dt {
                DataType::I8 => {
                    let x = f64::from(b[0] as i8);
                    if norm { (x / 127.0).max(-1.0) } else { x }
                }
                DataType::U8 => {
                    let x = f64::from(b[0]);
                    if norm { x / 255.0 } else { x }
                }
                DataType::I16 => {
                    let x = f64::from(i16::from_le_bytes([b[0], b[1]]));
                    if norm { (x / 32767.0).max(-1.0) } else { x }
                }
                DataType::U16 => {
                    let x = f64::from(u16::from_le_bytes([b[0], b[1]]));
                    if norm { x / 65535.0 } else { x }
                }
                DataType::U32 => f64::from(u32::from_le_bytes([b[0], b[1], b[2], b[3]])),
                DataType::F32 => f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            };
            out.push(v);
        }
    }
    Ok((out, dims))
}

fn load_buffers<'a>(
    doc: &gltf::Document,
    blob: Option<&'a [u8]>,
    ctx: Ctx<'_>,
    base_dir: Option<&Path>,
) -> Result<Vec<Cow<'a, [u8]>>, IoError> {
    let mut out = Vec::new();
    for buffer in doc.buffers() {
        let loc = Location::Element("buffer", buffer.index());
        let data: Cow<'a, [u8]> = match buffer.source() {
            gltf::buffer::Source::Bin => {
                Cow::Borrowed(blob.ok_or_else(|| ctx.parse(loc, "a GLB binary chunk"))?)
            }
            gltf::buffer::Source::Uri(uri) => {
                if let Some(rest) = uri.strip_prefix("data:") {
                    let (_, b64) = rest
                        .split_once(";base64,")
                        .ok_or_else(|| ctx.parse(loc, "a base64 data URI"))?;
                    Cow::Owned(base64_decode(b64).ok_or_else(|| ctx.parse(loc, "valid base64"))?)
                } else {
                    let dir = base_dir.ok_or_else(|| {
                        ctx.unsupported(loc, "external buffer files when reading from memory")
                    })?;
                    let file = dir.join(uri.replace("%20", " "));
                    Cow::Owned(std::fs::read(&file).map_err(|source| IoError::Io {
                        path: file.clone(),
                        source,
                    })?)
                }
            }
        };
        if data.len() < buffer.length() {
            return Err(ctx.parse(
                loc,
                format!(
                    "{} bytes of buffer data, found {}",
                    buffer.length(),
                    data.len()
                ),
            ));
        }
        out.push(data);
    }
    Ok(out)
}

/// Bounds on what instancing can make of a small file (a node graph may share children).
const MAX_NODE_VISITS: usize = 100_000;
const MAX_VERTICES: usize = 1 << 25;

struct Builder {
    visits: usize,
    mesh: PolygonMesh,
    normals: Vec<DVec3>,
    all_normals: bool,
    patch: Vec<i64>,
    any_patch: bool,
}

fn add_primitive(
    b: &mut Builder,
    prim: &gltf::Primitive<'_>,
    transform: DMat4,
    buffers: &[Cow<'_, [u8]>],
    ctx: Ctx<'_>,
) -> Result<(), IoError> {
    let tri_mode = matches!(
        prim.mode(),
        Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
    );
    if !tri_mode {
        return Ok(());
    }
    let Some(pos_acc) = prim.get(&gltf::Semantic::Positions) else {
        return Ok(());
    };
    let (pos, dims) = read_accessor(&pos_acc, buffers, ctx)?;
    if dims != 3 {
        return Err(ctx.parse(
            Location::Element("accessor", pos_acc.index()),
            "VEC3 positions",
        ));
    }
    let n = pos.len() / 3;
    let base = b.mesh.positions.len();
    if base + n > MAX_VERTICES {
        return Err(ctx.unsupported(
            Location::File,
            format!("more than {MAX_VERTICES} vertices after instancing"),
        ));
    }
    for p in pos.chunks_exact(3) {
        b.mesh
            .positions
            .push(transform.transform_point3(DVec3::new(p[0], p[1], p[2])));
    }
    let normal_matrix = DMat3::from_mat4(transform).inverse().transpose();
    match prim.get(&gltf::Semantic::Normals) {
        Some(acc) => {
            let (ns, d) = read_accessor(&acc, buffers, ctx)?;
            if d != 3 || ns.len() != pos.len() {
                return Err(ctx.parse(
                    Location::Element("accessor", acc.index()),
                    "one VEC3 normal per position",
                ));
            }
            b.normals.extend(
                ns.chunks_exact(3)
                    .map(|v| (normal_matrix * DVec3::new(v[0], v[1], v[2])).normalize_or_zero()),
            );
        }
        None => {
            b.all_normals = false;
            b.normals.extend(std::iter::repeat_n(DVec3::ZERO, n));
        }
    }
    match prim.get(&gltf::Semantic::Extras(PATCH_ATTRIBUTE.into())) {
        Some(acc) => {
            let (ids, d) = read_accessor(&acc, buffers, ctx)?;
            if d != 1 || ids.len() != n {
                return Err(ctx.parse(
                    Location::Element("accessor", acc.index()),
                    "one SCALAR _PATCH_ID per position",
                ));
            }
            b.any_patch = true;
            b.patch.extend(ids.iter().map(|&x| x as i64));
        }
        None => b.patch.extend(std::iter::repeat_n(-1, n)),
    }
    let indices: Vec<usize> = match prim.indices() {
        Some(acc) => {
            let (ix, d) = read_accessor(&acc, buffers, ctx)?;
            if d != 1 {
                return Err(ctx.parse(Location::Element("accessor", acc.index()), "SCALAR indices"));
            }
            let mut out = Vec::with_capacity(ix.len());
            for x in ix {
                if x < 0.0 || x >= n as f64 {
                    return Err(ctx.parse(
                        Location::Element("accessor", acc.index()),
                        format!("indices below the vertex count {n}, found {x}"),
                    ));
                }
                out.push(x as usize);
            }
            out
        }
        None => (0..n).collect(),
    };
    let flip = transform.determinant() < 0.0;
    let mut push = |t: [usize; 3]| {
        let [a, bb, c] = t.map(|v| (base + v) as u32);
        if flip {
            b.mesh.push_face(&[a, c, bb]);
        } else {
            b.mesh.push_face(&[a, bb, c]);
        }
    };
    match prim.mode() {
        Mode::Triangles => indices
            .chunks_exact(3)
            .for_each(|t| push([t[0], t[1], t[2]])),
        Mode::TriangleStrip => {
            for i in 0..indices.len().saturating_sub(2) {
                let t = [indices[i], indices[i + 1], indices[i + 2]];
                push(if i % 2 == 0 { t } else { [t[1], t[0], t[2]] });
            }
        }
        _ => {
            for i in 1..indices.len().saturating_sub(1) {
                push([indices[0], indices[i], indices[i + 1]]);
            }
        }
    }
    Ok(())
}

fn visit(
    b: &mut Builder,
    node: gltf::Node<'_>,
    parent: DMat4,
    depth: usize,
    buffers: &[Cow<'_, [u8]>],
    ctx: Ctx<'_>,
) -> Result<(), IoError> {
    b.visits += 1;
    if b.visits > MAX_NODE_VISITS {
        return Err(ctx.unsupported(
            Location::File,
            format!("more than {MAX_NODE_VISITS} node instances"),
        ));
    }
    if depth > 64 {
        return Err(ctx.parse(
            Location::Element("node", node.index()),
            "a node hierarchy at most 64 deep (without cycles)",
        ));
    }
    let m = node.transform().matrix();
    let local = DMat4::from_cols_array_2d(&m.map(|c| c.map(f64::from)));
    let world = parent * local;
    if let Some(mesh) = node.mesh() {
        for prim in mesh.primitives() {
            add_primitive(b, &prim, world, buffers, ctx)?;
        }
    }
    for child in node.children() {
        visit(b, child, world, depth + 1, buffers, ctx)?;
    }
    Ok(())
}

pub(crate) fn read(
    bytes: &[u8],
    ctx: Ctx<'_>,
    base_dir: Option<&Path>,
) -> Result<PolygonMesh, IoError> {
    let invalid = |e: &dyn std::fmt::Display| {
        ctx.parse(Location::File, format!("a valid glTF 2.0 document ({e})"))
    };
    let raw = gltf::Gltf::from_slice_without_validation(bytes).map_err(|e| invalid(&e))?;
    // gltf-json's validation indexes the accessor of a primitive's POSITION without a bounds
    // check (a panic on hostile input): check primitive accessor references first.
    let root = raw.document.into_json();
    let n_acc = root.accessors.len();
    for (m, mesh) in root.meshes.iter().enumerate() {
        for p in &mesh.primitives {
            let refs = p.attributes.values().chain(p.indices.iter());
            if let Some(bad) = refs.map(|i| i.value()).find(|&i| i >= n_acc) {
                return Err(ctx.parse(
                    Location::Element("mesh", m),
                    format!("accessor references below {n_acc}, found {bad}"),
                ));
            }
        }
    }
    let document = gltf::Document::from_json(root).map_err(|e| invalid(&e))?;
    let blob = raw.blob;
    let buffers = load_buffers(&document, blob.as_deref(), ctx, base_dir)?;
    let doc = &document;
    let mut b = Builder {
        visits: 0,
        mesh: PolygonMesh::new(),
        normals: Vec::new(),
        all_normals: true,
        patch: Vec::new(),
        any_patch: false,
    };
    let scene = doc.default_scene().or_else(|| doc.scenes().next());
    match scene {
        Some(scene) => {
            for node in scene.nodes() {
                visit(&mut b, node, DMat4::IDENTITY, 0, &buffers, ctx)?;
            }
        }
        None => {
            let mut is_child = vec![false; doc.nodes().len()];
            for n in doc.nodes() {
                for c in n.children() {
                    is_child[c.index()] = true;
                }
            }
            for n in doc.nodes().filter(|n| !is_child[n.index()]) {
                visit(&mut b, n, DMat4::IDENTITY, 0, &buffers, ctx)?;
            }
        }
    }
    let mut mesh = b.mesh;
    if b.all_normals && !mesh.positions.is_empty() {
        mesh.normals = Some(b.normals);
    }
    if b.any_patch {
        mesh.vertex_properties.push(Property {
            name: PATCH_ID.into(),
            values: PropertyValues::Int(b.patch),
        });
    }
    Ok(mesh)
}
