//! Wavefront OBJ: an order-preserving reader and a full-precision writer, both hand-written.
//!
//! Why not tobj for reading: tobj renumbers vertices per group/material in order of first use
//! and drops unused vertices, while later stages report element ids that must match the file.
//! tobj is kept as the oracle of the reader's tests.

use algesurf_mesh::{PolygonMesh, Property, PropertyValues};
use glam::DVec3;

use crate::error::Ctx;
use crate::{IoError, OBJ_GROUP, WriteOptions, number};

fn parse_f64(tok: Option<&str>) -> Option<f64> {
    tok?.parse::<f64>().ok()
}

/// Resolves a 1-based (or negative, relative) OBJ index against `count` elements read so far.
fn resolve(tok: &str, count: usize) -> Option<usize> {
    let i: i64 = tok.parse().ok()?;
    let idx = if i > 0 {
        (i - 1) as usize
    } else if i < 0 {
        (count as i64).checked_add(i)?.try_into().ok()?
    } else {
        return None;
    };
    (idx < count).then_some(idx)
}

/// A vector's bits, for comparing and ordering normals exactly.
fn bits(n: DVec3) -> [u64; 3] {
    n.to_array().map(f64::to_bits)
}

/// The per-vertex normal of a vertex whose corners name normals of different values (a hard
/// edge or a corner of the exporter's smoothing groups): the mean of their directions, with
/// the mean of their lengths (file normals are unit as a rule; the lengths matter only to
/// gradients read from the file). Each value counts once, however many corners name it, and
/// they are summed in the order of their bits, so the result does not depend on the order of
/// the faces. Opposite normals cancel to zero, which later stages treat as a missing normal.
fn corner_mean(mut values: Vec<DVec3>) -> DVec3 {
    values.sort_unstable_by_key(|&n| bits(n));
    values.dedup_by_key(|n| bits(*n));
    let directions: DVec3 = values.iter().map(|n| n.normalize_or_zero()).sum();
    let length = values.iter().map(|n| n.length()).sum::<f64>() / values.len() as f64;
    directions.normalize_or_zero() * length
}

pub(crate) fn read(bytes: &[u8], ctx: Ctx<'_>) -> Result<PolygonMesh, IoError> {
    let text = String::from_utf8_lossy(bytes);
    let mut mesh = PolygonMesh::new();
    let mut normals: Vec<DVec3> = Vec::new();
    // For each vertex: the file normal index of the first corner that referenced one.
    let mut vertex_normal: Vec<Option<u32>> = Vec::new();
    // Corners naming a normal of another value than their vertex's first one: `(vertex,
    // normal index)` (exporters write one normal per vertex and smoothing group, so a vertex
    // on a hard edge has one per side).
    let mut other_corner_normals: Vec<(u32, u32)> = Vec::new();
    let mut any_corner_normal = false;
    let mut groups: Vec<u32> = Vec::new();
    // Group ids are given in order of the groups' first face, so that ids written back as
    // `g group_<id>` read back the same.
    let mut group_ids: std::collections::HashMap<String, u32> = Default::default();
    let mut current_name = String::new();
    let mut current_group: Option<u32> = None;
    let mut corners: Vec<u32> = Vec::new();
    let mut pending = String::new();
    for (i, raw) in text.split('\n').enumerate() {
        let lineno = i + 1;
        let raw = raw.strip_suffix('\r').unwrap_or(raw);
        // Line continuation with a trailing backslash.
        if let Some(head) = raw.strip_suffix('\\') {
            pending.push_str(head);
            pending.push(' ');
            continue;
        }
        let joined;
        let line = if pending.is_empty() {
            raw
        } else {
            pending.push_str(raw);
            joined = std::mem::take(&mut pending);
            joined.as_str()
        };
        let line = line.split('#').next().unwrap_or("");
        let mut toks = line.split_whitespace();
        match toks.next() {
            Some("v") => {
                let (Some(x), Some(y), Some(z)) = (
                    parse_f64(toks.next()),
                    parse_f64(toks.next()),
                    parse_f64(toks.next()),
                ) else {
                    return Err(ctx.line(lineno, "three numbers after 'v'"));
                };
                let mut p = DVec3::new(x, y, z);
                // An optional weight w (exactly one more number) divides the position; three more
                // numbers are a vertex colour, ignored.
                let rest: Vec<&str> = toks.collect();
                if rest.len() == 1
                    && let Ok(w) = rest[0].parse::<f64>()
                    && w != 0.0
                    && w != 1.0
                {
                    p /= w;
                }
                mesh.positions.push(p);
                vertex_normal.push(None);
            }
            Some("vn") => {
                let (Some(x), Some(y), Some(z)) = (
                    parse_f64(toks.next()),
                    parse_f64(toks.next()),
                    parse_f64(toks.next()),
                ) else {
                    return Err(ctx.line(lineno, "three numbers after 'vn'"));
                };
                normals.push(DVec3::new(x, y, z));
            }
            Some("f") | Some("fo") => {
                corners.clear();
                let nv = mesh.positions.len();
                for tok in toks {
                    let mut parts = tok.split('/');
                    let v = parts.next().and_then(|t| resolve(t, nv)).ok_or_else(|| {
                        ctx.line(
                            lineno,
                            format!(
                                "a vertex reference between 1 and {nv} (or -1 to -{nv}), found '{tok}'"
                            ),
                        )
                    })?;
                    let _vt = parts.next();
                    if let Some(nt) = parts.next().filter(|t| !t.is_empty()) {
                        let n = resolve(nt, normals.len()).ok_or_else(|| {
                            ctx.line(
                                lineno,
                                format!(
                                    "a normal reference between 1 and {}, found '{tok}'",
                                    normals.len()
                                ),
                            )
                        })?;
                        any_corner_normal = true;
                        match vertex_normal[v] {
                            None => vertex_normal[v] = Some(n as u32),
                            Some(first) if bits(normals[first as usize]) != bits(normals[n]) => {
                                other_corner_normals.push((v as u32, n as u32));
                            }
                            Some(_) => {}
                        }
                    }
                    corners.push(v as u32);
                }
                if corners.len() < 3 {
                    return Err(ctx.line(lineno, "a face with at least 3 vertices"));
                }
                if mesh.positions.len() > u32::MAX as usize {
                    return Err(ctx.line(lineno, "fewer than 2^32 vertices"));
                }
                mesh.push_face(&corners);
                let next = group_ids.len() as u32;
                let g = *current_group
                    .get_or_insert_with(|| *group_ids.entry(current_name.clone()).or_insert(next));
                groups.push(g);
            }
            Some("g") | Some("o") => {
                current_name = toks.collect::<Vec<_>>().join(" ");
                current_group = None;
            }
            _ => {} // vt, l, p, s, usemtl, mtllib, comments, unknown statements
        }
    }
    if any_corner_normal {
        let by_order = normals.len() == mesh.positions.len();
        // A vertex takes the normal its corners name (the mean direction of their different
        // values, see [`corner_mean`]); vertices no corner gives a normal take the file's
        // normal of the same index when the counts match, else zero.
        let mut per_vertex: Vec<DVec3> = vertex_normal
            .iter()
            .enumerate()
            .map(|(v, n)| match n {
                Some(n) => normals[*n as usize],
                None if by_order => normals[v],
                None => DVec3::ZERO,
            })
            .collect();
        other_corner_normals.sort_unstable();
        for run in other_corner_normals.chunk_by(|a, b| a.0 == b.0) {
            let v = run[0].0 as usize;
            let values: Vec<DVec3> = std::iter::once(per_vertex[v])
                .chain(run.iter().map(|&(_, n)| normals[n as usize]))
                .collect();
            per_vertex[v] = corner_mean(values);
        }
        mesh.normals = Some(per_vertex);
    } else if !normals.is_empty() && normals.len() == mesh.positions.len() {
        mesh.normals = Some(normals);
    }
    let distinct: std::collections::BTreeSet<u32> = groups.iter().copied().collect();
    if distinct.len() > 1 {
        mesh.face_properties.push(Property {
            name: OBJ_GROUP.into(),
            values: PropertyValues::Int(groups.into_iter().map(i64::from).collect()),
        });
    }
    Ok(mesh)
}

pub(crate) fn write(mesh: &PolygonMesh, options: &WriteOptions) -> Vec<u8> {
    let mut out = String::with_capacity(mesh.vertex_count() * 60 + mesh.face_count() * 30);
    out.push_str("# written by algesurf\n");
    for p in &mesh.positions {
        out.push_str("v ");
        number::push3(&mut out, *p, options.f32);
        out.push('\n');
    }
    let normals = mesh.normals.as_ref().filter(|_| options.normals);
    if let Some(ns) = normals {
        for n in ns {
            out.push_str("vn ");
            number::push3(&mut out, *n, options.f32);
            out.push('\n');
        }
    }
    let groups = mesh.face_properties.iter().find_map(|p| match &p.values {
        PropertyValues::Int(v) if p.name == OBJ_GROUP => Some(v),
        _ => None,
    });
    let mut last_group = None;
    for (f, face) in mesh.faces().enumerate() {
        if let Some(g) = groups {
            let g = g[f];
            if last_group != Some(g) {
                out.push_str(&format!("g group_{g}\n"));
                last_group = Some(g);
            }
        }
        out.push('f');
        for &v in face {
            let k = v + 1;
            if normals.is_some() {
                out.push_str(&format!(" {k}//{k}"));
            } else {
                out.push_str(&format!(" {k}"));
            }
        }
        out.push('\n');
    }
    out.into_bytes()
}
