//! Stanford PLY, ascii and binary (both byte orders), through `ply-rs-bw`.
//!
//! Reads `vertex` (`x y z`, optional `nx ny nz`, any other scalar property kept by name),
//! `face` (a list named `vertex_indices` or `vertex_index`, any count and index type, other
//! scalar properties kept by name) and `tristrips` (lists with `-1` restarts); other elements,
//! `obj_info` and comments are skipped. Writes `double` (or `float` with
//! [`WriteOptions::f32`]) coordinates, normals and float properties; integer properties as
//! `int` when they fit, else `double`.

use std::io::Cursor;

use algesurf_mesh::{PolygonMesh, Property, PropertyValues};
use glam::DVec3;
use ply_rs_bw::parser::{Parser, Reader};
use ply_rs_bw::ply::{
    self, DefaultElement, ElementDef, Encoding, Header, PropertyType, ScalarType,
};

use crate::blocks::write_blocks;
use crate::error::{Ctx, Location};
use crate::{IoError, WriteOptions};

/// The first line of a `ply-rs-bw` error, without its `Line N: ` prefix (the location is
/// reported separately).
fn short(e: &ply_rs_bw::parser::ParseError) -> String {
    let text = e.to_string();
    let first = text.lines().next().unwrap_or("").trim();
    match first.split_once(": ") {
        Some((head, rest)) if head.starts_with("Line ") => rest.to_string(),
        _ => first.to_string(),
    }
}

fn scalar_f64(p: &ply::Property) -> Option<f64> {
    use ply::Property as P;
    Some(match *p {
        P::Char(v) => v.into(),
        P::UChar(v) => v.into(),
        P::Short(v) => v.into(),
        P::UShort(v) => v.into(),
        P::Int(v) => v.into(),
        P::UInt(v) => v.into(),
        P::Float(v) => v.into(),
        P::Double(v) => v,
        _ => return None,
    })
}

fn scalar_i64(p: &ply::Property) -> Option<i64> {
    use ply::Property as P;
    Some(match *p {
        P::Char(v) => v.into(),
        P::UChar(v) => v.into(),
        P::Short(v) => v.into(),
        P::UShort(v) => v.into(),
        P::Int(v) => v.into(),
        P::UInt(v) => v.into(),
        _ => return None,
    })
}

fn list_i64(p: &ply::Property) -> Option<Vec<i64>> {
    use ply::Property as P;
    Some(match p {
        P::ListChar(v) => v.iter().map(|&x| x.into()).collect(),
        P::ListUChar(v) => v.iter().map(|&x| x.into()).collect(),
        P::ListShort(v) => v.iter().map(|&x| x.into()).collect(),
        P::ListUShort(v) => v.iter().map(|&x| x.into()).collect(),
        P::ListInt(v) => v.iter().map(|&x| x.into()).collect(),
        P::ListUInt(v) => v.iter().map(|&x| x.into()).collect(),
        _ => return None,
    })
}

fn is_int(t: &ScalarType) -> bool {
    !matches!(t, ScalarType::Float | ScalarType::Double)
}

fn scalar_size(t: &ScalarType) -> u64 {
    match t {
        ScalarType::Char | ScalarType::UChar => 1,
        ScalarType::Short | ScalarType::UShort => 2,
        ScalarType::Int | ScalarType::UInt | ScalarType::Float => 4,
        ScalarType::Double => 8,
    }
}

/// The index list of a face-like element: `vertex_indices`, `vertex_index`, or else the only
/// integer list.
fn index_list_name(def: &ElementDef) -> Option<String> {
    for name in ["vertex_indices", "vertex_index"] {
        if matches!(def.properties.get(name).map(|p| &p.data_type), Some(PropertyType::List(_, t)) if is_int(t))
        {
            return Some(name.to_string());
        }
    }
    let mut lists = def
        .properties
        .values()
        .filter(|p| matches!(&p.data_type, PropertyType::List(_, t) if is_int(t)));
    match (lists.next(), lists.next()) {
        (Some(p), None) => Some(p.name.clone()),
        _ => None,
    }
}

/// Scalar properties of an element, except `skip`, as named columns.
fn collect_properties(def: &ElementDef, elems: &[DefaultElement], skip: &[&str]) -> Vec<Property> {
    let mut out = Vec::new();
    for p in def.properties.values() {
        let PropertyType::Scalar(t) = &p.data_type else {
            continue;
        };
        if skip.contains(&p.name.as_str()) {
            continue;
        }
        let values = if is_int(t) {
            PropertyValues::Int(
                elems
                    .iter()
                    .map(|e| e.get(&p.name).and_then(scalar_i64).unwrap_or(0))
                    .collect(),
            )
        } else {
            PropertyValues::Float(
                elems
                    .iter()
                    .map(|e| e.get(&p.name).and_then(scalar_f64).unwrap_or(f64::NAN))
                    .collect(),
            )
        };
        out.push(Property {
            name: p.name.clone(),
            values,
        });
    }
    out
}

/// Rejects element counts that the remaining bytes cannot hold (so that a lying header cannot
/// make the parser allocate or loop without bound).
fn check_counts(
    header: &Header,
    remaining: u64,
    ctx: Ctx<'_>,
    header_end: u64,
) -> Result<(), IoError> {
    let mut need: u64 = 0;
    for def in header.elements.values() {
        let per = match header.encoding {
            // At least a line break per element.
            Encoding::Ascii => 1,
            _ => def
                .properties
                .values()
                .map(|p| match &p.data_type {
                    PropertyType::Scalar(t) => scalar_size(t),
                    PropertyType::List(c, _) => scalar_size(c),
                })
                .sum::<u64>()
                .max(1),
        };
        need = need.saturating_add(per.saturating_mul(def.count as u64));
        // The last ascii line may lack its line break.
        let slack = u64::from(header.encoding == Encoding::Ascii);
        if need > remaining.saturating_add(slack) {
            return Err(ctx.parse(
                Location::Byte(header_end),
                format!(
                    "{} '{}' elements, but only {remaining} bytes follow the header",
                    def.count, def.name
                ),
            ));
        }
    }
    Ok(())
}

pub(crate) fn read(bytes: &[u8], ctx: Ctx<'_>) -> Result<PolygonMesh, IoError> {
    let parser = Parser::<DefaultElement>::new();
    let mut reader = Reader::new(Cursor::new(bytes));
    let header = parser.read_header(&mut reader).map_err(|e| {
        ctx.parse(
            e.line().map_or(Location::File, Location::Line),
            format!("a valid PLY header ({})", short(&e)),
        )
    })?;
    let header_end = reader.get_ref().position();
    check_counts(
        &header,
        (bytes.len() as u64).saturating_sub(header_end),
        ctx,
        header_end,
    )?;
    let payload = parser.read_payload(&mut reader, &header).map_err(|e| {
        let loc = match header.encoding {
            Encoding::Ascii => e.line().map_or(Location::File, Location::Line),
            _ => Location::Byte(reader.get_ref().position()),
        };
        ctx.parse(
            loc,
            format!("element data as declared in the header ({})", short(&e)),
        )
    })?;

    let vdef = header
        .elements
        .get("vertex")
        .ok_or_else(|| ctx.parse(Location::File, "a 'vertex' element"))?;
    let verts = payload.get("vertex").map(Vec::as_slice).unwrap_or(&[]);
    for c in ["x", "y", "z"] {
        if !matches!(
            vdef.properties.get(c).map(|p| &p.data_type),
            Some(PropertyType::Scalar(_))
        ) {
            return Err(ctx.parse(Location::File, format!("a scalar vertex property '{c}'")));
        }
    }
    let get = |e: &DefaultElement, k: &str| e.get(k).and_then(scalar_f64).unwrap_or(f64::NAN);
    let mut mesh = PolygonMesh::new();
    mesh.positions = verts
        .iter()
        .map(|e| DVec3::new(get(e, "x"), get(e, "y"), get(e, "z")))
        .collect();
    let has_normals = ["nx", "ny", "nz"].iter().all(|c| {
        matches!(
            vdef.properties.get(*c).map(|p| &p.data_type),
            Some(PropertyType::Scalar(_))
        )
    });
    let mut skip = vec!["x", "y", "z"];
    if has_normals {
        mesh.normals = Some(
            verts
                .iter()
                .map(|e| DVec3::new(get(e, "nx"), get(e, "ny"), get(e, "nz")))
                .collect(),
        );
        skip.extend(["nx", "ny", "nz"]);
    }
    mesh.vertex_properties = collect_properties(vdef, verts, &skip);

    let nv = mesh.positions.len();
    let check = |v: i64, kind: &'static str, id: usize| -> Result<u32, IoError> {
        if v >= 0 && (v as u64) < nv as u64 {
            Ok(v as u32)
        } else {
            Err(ctx.parse(
                Location::Element(kind, id),
                format!("vertex indices in 0..{nv}, found {v}"),
            ))
        }
    };
    let mut corners = Vec::new();
    if let Some(fdef) = header.elements.get("face") {
        let faces = payload.get("face").map(Vec::as_slice).unwrap_or(&[]);
        let name = index_list_name(fdef)
            .ok_or_else(|| ctx.parse(Location::File, "a face list property 'vertex_indices'"))?;
        for (f, e) in faces.iter().enumerate() {
            let list = e.get(&name).and_then(list_i64).unwrap_or_default();
            if list.len() < 3 {
                return Err(ctx.parse(
                    Location::Element("face", f),
                    format!("at least 3 vertex indices, found {}", list.len()),
                ));
            }
            corners.clear();
            for v in list {
                corners.push(check(v, "face", f)?);
            }
            mesh.push_face(&corners);
        }
        mesh.face_properties = collect_properties(fdef, faces, &[name.as_str()]);
    }
    if let Some(sdef) = header.elements.get("tristrips") {
        let strips = payload.get("tristrips").map(Vec::as_slice).unwrap_or(&[]);
        let name = index_list_name(sdef).ok_or_else(|| {
            ctx.parse(Location::File, "a tristrips list property 'vertex_indices'")
        })?;
        let before = mesh.face_count();
        for (s, e) in strips.iter().enumerate() {
            let list = e.get(&name).and_then(list_i64).unwrap_or_default();
            for run in list.split(|&v| v == -1) {
                for i in 0..run.len().saturating_sub(2) {
                    let (a, b, c) = (run[i], run[i + 1], run[i + 2]);
                    // Strips stitch with repeated indices: those triangles are not faces.
                    if a == b || b == c || a == c {
                        continue;
                    }
                    let t = if i % 2 == 0 { [a, b, c] } else { [b, a, c] };
                    for v in t {
                        corners.push(check(v, "tristrips", s)?);
                    }
                    mesh.push_face(&corners);
                    corners.clear();
                }
            }
        }
        if mesh.face_count() > before && before > 0 {
            // Face properties cannot describe strip triangles.
            mesh.face_properties.clear();
        }
    }
    Ok(mesh)
}

/// How one value is stored: the PLY scalar types the writer uses.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Scalar {
    Int,
    Float,
    Double,
}

impl Scalar {
    fn name(self) -> &'static str {
        match self {
            Scalar::Int => "int",
            Scalar::Float => "float",
            Scalar::Double => "double",
        }
    }
}

/// Appends values in one of the three PLY encodings. Ascii values are separated by single
/// spaces, one element per line, floats in Rust's shortest round-trip form (so `f64` values
/// read back bit-identical).
struct Encoder {
    /// The encoded bytes.
    out: Vec<u8>,
    encoding: Encoding,
    first: bool,
}

/// Encodes elements `0..n` by `encode` (one element per call) and writes them to `sink` in
/// order, [`BLOCK`](crate::blocks::BLOCK)s of them encoded in parallel ([`write_blocks`]):
/// the same bytes as one loop over the elements (each element ends a line in ascii, so blocks
/// join without separators). Encoding was all of the write stage's own work on one core
/// (~80 ms of the bunny's 88 MB PLY, the rest the kernel's copy into the page cache).
fn write_elements(
    n: usize,
    encoding: Encoding,
    sink: &mut dyn std::io::Write,
    encode: &(dyn Fn(usize, &mut Encoder) + Sync),
) -> std::io::Result<()> {
    write_blocks(n, sink, &|range, buffer| {
        let mut e = Encoder {
            out: std::mem::take(buffer),
            encoding,
            first: true,
        };
        for i in range {
            encode(i, &mut e);
        }
        *buffer = e.out;
    })
}

impl Encoder {
    fn sep(&mut self) {
        if !self.first {
            self.out.push(b' ');
        }
        self.first = false;
    }
    fn end(&mut self) {
        if self.encoding == Encoding::Ascii {
            self.out.push(b'\n');
        }
        self.first = true;
    }
    fn bytes<const N: usize>(&mut self, le: [u8; N], be: [u8; N]) {
        if self.encoding == Encoding::BinaryBigEndian {
            self.out.extend_from_slice(&be);
        } else {
            self.out.extend_from_slice(&le);
        }
    }
    fn value(&mut self, t: Scalar, x: f64) {
        use std::io::Write;
        if self.encoding == Encoding::Ascii {
            self.sep();
            let _ = match t {
                Scalar::Int => write!(self.out, "{}", x as i32),
                Scalar::Float => write!(self.out, "{}", x as f32),
                Scalar::Double => write!(self.out, "{x}"),
            };
            return;
        }
        match t {
            Scalar::Int => self.bytes((x as i32).to_le_bytes(), (x as i32).to_be_bytes()),
            Scalar::Float => self.bytes((x as f32).to_le_bytes(), (x as f32).to_be_bytes()),
            Scalar::Double => self.bytes(x.to_le_bytes(), x.to_be_bytes()),
        }
    }
    fn int(&mut self, x: i32) {
        use std::io::Write;
        if self.encoding == Encoding::Ascii {
            self.sep();
            let _ = write!(self.out, "{x}");
        } else {
            self.bytes(x.to_le_bytes(), x.to_be_bytes());
        }
    }
    /// A list length: `uchar` when `small`, else `uint`.
    fn count(&mut self, n: usize, small: bool) {
        use std::io::Write;
        if self.encoding == Encoding::Ascii {
            self.sep();
            let _ = write!(self.out, "{n}");
        } else if small {
            self.out.push(n as u8);
        } else {
            self.bytes((n as u32).to_le_bytes(), (n as u32).to_be_bytes());
        }
    }
}

/// Encodes `mesh` as PLY in memory ([`write_to`] a vector).
pub(crate) fn write(
    mesh: &PolygonMesh,
    options: &WriteOptions,
    ctx: Ctx<'_>,
) -> Result<Vec<u8>, IoError> {
    let mut bytes = Vec::new();
    write_to(mesh, options, ctx, &mut bytes)?;
    Ok(bytes)
}

/// Encodes `mesh` as PLY into `sink`, [`BLOCK`](crate::blocks::BLOCK)s of elements at a time
/// ([`write_elements`]).
/// Written directly (header text, then the values) rather than through `ply_rs_bw`'s element
/// maps, which allocate a hash map with string keys per element: that made writing a
/// 1.3 M-triangle tessellation take seconds. The reader still parses with `ply_rs_bw`, and the
/// round-trip tests check both agree.
pub(crate) fn write_to(
    mesh: &PolygonMesh,
    options: &WriteOptions,
    ctx: Ctx<'_>,
    sink: &mut dyn std::io::Write,
) -> Result<(), IoError> {
    use std::fmt::Write;
    let float = if options.f32 {
        Scalar::Float
    } else {
        Scalar::Double
    };
    let encoding = if options.ascii {
        Encoding::Ascii
    } else if options.big_endian {
        Encoding::BinaryBigEndian
    } else {
        Encoding::BinaryLittleEndian
    };
    // Integer columns that do not fit an `int` are written as `double` (exact to 2^53).
    let prop_type = |p: &Property| match &p.values {
        PropertyValues::Int(v) if v.iter().all(|&x| i32::try_from(x).is_ok()) => Scalar::Int,
        PropertyValues::Int(_) => Scalar::Double,
        PropertyValues::Float(_) => float,
    };
    let value = |p: &Property, i: usize| match &p.values {
        PropertyValues::Int(v) => v[i] as f64,
        PropertyValues::Float(v) => v[i],
    };
    let normals = mesh.normals.as_ref().filter(|_| options.normals);
    let vprops = extra_properties(
        &mesh.vertex_properties,
        &["x", "y", "z", "nx", "ny", "nz"],
        &prop_type,
        ctx,
    )?;
    let fprops = extra_properties(&mesh.face_properties, &["vertex_indices"], &prop_type, ctx)?;
    let max_len = mesh.faces().map(<[u32]>::len).max().unwrap_or(3);
    let small = max_len <= 255;

    let mut h = String::new();
    let format = match encoding {
        Encoding::Ascii => "ascii",
        Encoding::BinaryBigEndian => "binary_big_endian",
        Encoding::BinaryLittleEndian => "binary_little_endian",
    };
    let _ = writeln!(h, "ply\nformat {format} 1.0\ncomment written by algesurf");
    let _ = writeln!(h, "element vertex {}", mesh.vertex_count());
    let mut columns = vec!["x", "y", "z"];
    if normals.is_some() {
        columns.extend(["nx", "ny", "nz"]);
    }
    for c in &columns {
        let _ = writeln!(h, "property {} {c}", float.name());
    }
    for (p, t) in &vprops {
        let _ = writeln!(h, "property {} {}", t.name(), p.name);
    }
    let _ = writeln!(h, "element face {}", mesh.face_count());
    let count = if small { "uchar" } else { "uint" };
    let _ = writeln!(h, "property list {count} int vertex_indices");
    for (p, t) in &fprops {
        let _ = writeln!(h, "property {} {}", t.name(), p.name);
    }
    h.push_str("end_header\n");

    let io_err = |source| ctx.io(source);
    sink.write_all(h.as_bytes()).map_err(io_err)?;
    let encode_vertex = |i: usize, e: &mut Encoder| {
        let p = mesh.positions[i];
        for x in [p.x, p.y, p.z] {
            e.value(float, x);
        }
        if let Some(ns) = normals {
            for x in [ns[i].x, ns[i].y, ns[i].z] {
                e.value(float, x);
            }
        }
        for (p, t) in &vprops {
            e.value(*t, value(p, i));
        }
        e.end();
    };
    write_elements(mesh.vertex_count(), encoding, sink, &encode_vertex).map_err(io_err)?;
    let encode_face = |f: usize, e: &mut Encoder| {
        let face = mesh.face(f);
        e.count(face.len(), small);
        for &v in face {
            e.int(v as i32);
        }
        for (p, t) in &fprops {
            e.value(*t, value(p, f));
        }
        e.end();
    };
    write_elements(mesh.face_count(), encoding, sink, &encode_face).map_err(io_err)?;
    sink.flush().map_err(io_err)
}

/// The extra scalar properties of an element (all but the `reserved` names), each with the
/// type it is written as.
fn extra_properties<'a>(
    props: &'a [Property],
    reserved: &[&str],
    prop_type: &dyn Fn(&Property) -> Scalar,
    ctx: Ctx<'_>,
) -> Result<Vec<(&'a Property, Scalar)>, IoError> {
    let list: Vec<(&Property, Scalar)> = props
        .iter()
        .filter(|p| !reserved.contains(&p.name.as_str()))
        .map(|p| (p, prop_type(p)))
        .collect();
    for (p, _) in &list {
        check_name(&p.name, ctx)?;
    }
    Ok(list)
}

fn check_name(name: &str, ctx: Ctx<'_>) -> Result<(), IoError> {
    if name.is_empty() || name.chars().any(|c| c.is_whitespace() || c.is_control()) {
        return Err(ctx.invalid(format!(
            "property name '{name}' is empty or contains white space"
        )));
    }
    Ok(())
}
