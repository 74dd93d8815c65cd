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
    self, DefaultElement, ElementDef, Encoding, Header, Ply, PropertyDef, PropertyType, ScalarType,
};

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

fn scalar(name: &str, t: ScalarType) -> PropertyDef {
    PropertyDef::new(name.to_string(), PropertyType::Scalar(t))
}

pub(crate) fn write(
    mesh: &PolygonMesh,
    options: &WriteOptions,
    ctx: Ctx<'_>,
) -> Result<Vec<u8>, IoError> {
    let float_type = || {
        if options.f32 {
            ScalarType::Float
        } else {
            ScalarType::Double
        }
    };
    let float = |x: f64| {
        if options.f32 {
            ply::Property::Float(x as f32)
        } else {
            ply::Property::Double(x)
        }
    };
    let mut ply = Ply::<DefaultElement>::new();
    ply.header.encoding = if options.ascii {
        Encoding::Ascii
    } else if options.big_endian {
        Encoding::BinaryBigEndian
    } else {
        Encoding::BinaryLittleEndian
    };
    ply.header.comments.push("written by algesurf".into());

    // Integer columns that do not fit an `int` are written as `double` (exact to 2^53).
    let prop_type = |p: &Property| match &p.values {
        PropertyValues::Int(v) if v.iter().all(|&x| i32::try_from(x).is_ok()) => ScalarType::Int,
        PropertyValues::Int(_) => ScalarType::Double,
        PropertyValues::Float(_) => float_type(),
    };
    let prop_value = |p: &Property, t: &ScalarType, i: usize| match (&p.values, t) {
        (PropertyValues::Int(v), ScalarType::Int) => ply::Property::Int(v[i] as i32),
        (PropertyValues::Int(v), _) => ply::Property::Double(v[i] as f64),
        (PropertyValues::Float(v), _) => float(v[i]),
    };

    let normals = mesh.normals.as_ref().filter(|_| options.normals);
    let mut vdef = ElementDef::new("vertex".into());
    for c in ["x", "y", "z"] {
        vdef.properties.insert(c.into(), scalar(c, float_type()));
    }
    if normals.is_some() {
        for c in ["nx", "ny", "nz"] {
            vdef.properties.insert(c.into(), scalar(c, float_type()));
        }
    }
    let vprops = extra_properties(
        &mesh.vertex_properties,
        &["x", "y", "z", "nx", "ny", "nz"],
        &mut vdef,
        &prop_type,
        ctx,
    )?;
    let mut verts = Vec::with_capacity(mesh.vertex_count());
    for (i, p) in mesh.positions.iter().enumerate() {
        let mut e = DefaultElement::new();
        e.insert("x".into(), float(p.x));
        e.insert("y".into(), float(p.y));
        e.insert("z".into(), float(p.z));
        if let Some(ns) = normals {
            e.insert("nx".into(), float(ns[i].x));
            e.insert("ny".into(), float(ns[i].y));
            e.insert("nz".into(), float(ns[i].z));
        }
        for (p, t) in &vprops {
            e.insert(p.name.clone(), prop_value(p, t, i));
        }
        verts.push(e);
    }
    ply.header.elements.insert("vertex".into(), vdef);
    ply.payload.insert("vertex".into(), verts);

    let max_len = mesh.faces().map(<[u32]>::len).max().unwrap_or(3);
    let count_type = if max_len <= 255 {
        ScalarType::UChar
    } else {
        ScalarType::UInt
    };
    let mut fdef = ElementDef::new("face".into());
    fdef.properties.insert(
        "vertex_indices".into(),
        PropertyDef::new(
            "vertex_indices".into(),
            PropertyType::List(count_type, ScalarType::Int),
        ),
    );
    let fprops = extra_properties(
        &mesh.face_properties,
        &["vertex_indices"],
        &mut fdef,
        &prop_type,
        ctx,
    )?;
    let mut faces = Vec::with_capacity(mesh.face_count());
    for (f, face) in mesh.faces().enumerate() {
        let mut e = DefaultElement::new();
        e.insert(
            "vertex_indices".into(),
            ply::Property::ListInt(face.iter().map(|&v| v as i32).collect()),
        );
        for (p, t) in &fprops {
            e.insert(p.name.clone(), prop_value(p, t, f));
        }
        faces.push(e);
    }
    ply.header.elements.insert("face".into(), fdef);
    ply.payload.insert("face".into(), faces);

    let mut out = Vec::new();
    ply_rs_bw::writer::Writer::new()
        .write_ply(&mut out, &mut ply)
        .map_err(|e| ctx.invalid(e.to_string()))?;
    Ok(out)
}

/// The extra scalar properties of an element (all but the `reserved` names), declared in its
/// header definition `def`, each with the type it is written as.
fn extra_properties<'a>(
    props: &'a [Property],
    reserved: &[&str],
    def: &mut ElementDef,
    prop_type: &dyn Fn(&Property) -> ScalarType,
    ctx: Ctx<'_>,
) -> Result<Vec<(&'a Property, ScalarType)>, IoError> {
    let list: Vec<(&Property, ScalarType)> = props
        .iter()
        .filter(|p| !reserved.contains(&p.name.as_str()))
        .map(|p| (p, prop_type(p)))
        .collect();
    for (p, t) in &list {
        check_name(&p.name, ctx)?;
        def.properties
            .insert(p.name.clone(), scalar(&p.name, t.clone()));
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
