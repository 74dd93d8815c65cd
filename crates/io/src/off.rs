//! Object File Format (OFF), read and written by hand.
//!
//! Header keywords `OFF`, `COFF`, `NOFF`, `CNOFF`, `STOFF`, ... (with or without the counts on
//! the same line); one vertex per line (`x y z`, then normals when the keyword has `N`, then
//! anything, ignored); one face per line (`n i_1 ... i_n`, then an optional colour, ignored);
//! `#` comments. Binary OFF and 4-D (`4OFF`, `nOFF`) are reported as unsupported.

use algesurf_mesh::PolygonMesh;
use glam::DVec3;

use crate::error::{Ctx, Location};
use crate::{IoError, WriteOptions, number};

pub(crate) fn is_off_keyword(k: &str) -> bool {
    let Some(prefix) = k.strip_suffix("OFF") else {
        return false;
    };
    let mut rest = prefix;
    for flag in ["ST", "C", "N", "4", "n"] {
        rest = rest.strip_prefix(flag).unwrap_or(rest);
    }
    rest.is_empty()
}

pub(crate) fn read(bytes: &[u8], ctx: Ctx<'_>) -> Result<PolygonMesh, IoError> {
    let text = String::from_utf8_lossy(bytes);
    // Non-empty, comment-stripped lines with their 1-based numbers.
    let mut lines = text.split('\n').enumerate().filter_map(|(i, l)| {
        let l = l.split('#').next().unwrap_or("").trim();
        (!l.is_empty()).then_some((i + 1, l))
    });
    let (hl, header) = lines
        .next()
        .ok_or_else(|| ctx.line(1, "an OFF header keyword"))?;
    let mut toks = header.split_whitespace();
    let keyword = toks.next().unwrap_or("");
    if !is_off_keyword(keyword) {
        return Err(ctx.line(hl, format!("an OFF header keyword, found '{keyword}'")));
    }
    if keyword.contains('4') || keyword.contains('n') {
        return Err(ctx.unsupported(Location::Line(hl), "OFF with other than 3 dimensions"));
    }
    let has_normals = keyword.contains('N');
    let mut rest: Vec<&str> = toks.collect();
    if rest.first() == Some(&"BINARY") {
        return Err(ctx.unsupported(Location::Line(hl), "binary OFF"));
    }
    let mut counts_line = hl;
    if rest.is_empty() {
        let (l, c) = lines
            .next()
            .ok_or_else(|| ctx.line(hl + 1, "vertex, face and edge counts"))?;
        counts_line = l;
        rest = c.split_whitespace().collect();
    }
    let parse_count = |t: Option<&&str>| t.and_then(|t| t.parse::<usize>().ok());
    let (Some(nv), Some(nf)) = (parse_count(rest.first()), parse_count(rest.get(1))) else {
        return Err(ctx.line(counts_line, "vertex and face counts"));
    };
    // Each element needs its own line: counts beyond the file size are lies.
    if nv.saturating_add(nf) > bytes.len() {
        return Err(ctx.line(
            counts_line,
            format!(
                "at most one element per line, but the counts {nv} + {nf} exceed the file size"
            ),
        ));
    }
    let mut mesh = PolygonMesh::new();
    mesh.positions.reserve(nv);
    let mut normals = Vec::new();
    for k in 0..nv {
        let (l, line) = lines.next().ok_or_else(|| {
            ctx.parse(
                Location::Element("vertex", k),
                "a vertex line before end of file",
            )
        })?;
        let nums: Vec<f64> = line
            .split_whitespace()
            .take(if has_normals { 6 } else { 3 })
            .map(|t| t.parse::<f64>())
            .collect::<Result<_, _>>()
            .map_err(|_| ctx.line(l, "numeric vertex coordinates"))?;
        let need = if has_normals { 6 } else { 3 };
        if nums.len() < need {
            return Err(ctx.line(l, format!("{need} numbers for vertex {k}")));
        }
        mesh.positions.push(DVec3::new(nums[0], nums[1], nums[2]));
        if has_normals {
            normals.push(DVec3::new(nums[3], nums[4], nums[5]));
        }
    }
    let mut corners = Vec::new();
    for f in 0..nf {
        let (l, line) = lines.next().ok_or_else(|| {
            ctx.parse(
                Location::Element("face", f),
                "a face line before end of file",
            )
        })?;
        let mut toks = line.split_whitespace();
        let n: usize = toks
            .next()
            .and_then(|t| t.parse().ok())
            .ok_or_else(|| ctx.line(l, "a corner count"))?;
        if n < 3 {
            return Err(ctx.line(l, format!("at least 3 corners for face {f}, found {n}")));
        }
        corners.clear();
        for _ in 0..n {
            let v = toks
                .next()
                .and_then(|t| t.parse::<u32>().ok())
                .filter(|&v| (v as usize) < nv)
                .ok_or_else(|| {
                    ctx.line(l, format!("{n} vertex indices below {nv} for face {f}"))
                })?;
            corners.push(v);
        }
        mesh.push_face(&corners);
    }
    if has_normals {
        mesh.normals = Some(normals);
    }
    Ok(mesh)
}

pub(crate) fn write(mesh: &PolygonMesh, options: &WriteOptions) -> Vec<u8> {
    let normals = mesh.normals.as_ref().filter(|_| options.normals);
    let mut out = String::with_capacity(mesh.vertex_count() * 60 + mesh.face_count() * 20);
    out.push_str(if normals.is_some() { "NOFF\n" } else { "OFF\n" });
    out.push_str("# written by algesurf\n");
    out.push_str(&format!(
        "{} {} 0\n",
        mesh.vertex_count(),
        mesh.face_count()
    ));
    for (i, p) in mesh.positions.iter().enumerate() {
        number::push3(&mut out, *p, options.f32);
        if let Some(ns) = normals {
            out.push(' ');
            number::push3(&mut out, ns[i], options.f32);
        }
        out.push('\n');
    }
    for face in mesh.faces() {
        out.push_str(&face.len().to_string());
        for v in face {
            out.push(' ');
            out.push_str(&v.to_string());
        }
        out.push('\n');
    }
    out.into_bytes()
}
