//! What is drawn: meshes ([`RenderMesh`]) and line sets ([`LineSet`]), and their
//! flattening into one list of triangles with per-triangle colours for a given mode.

use algesurf_apatch::{PatchKind, Tessellation};
use algesurf_mesh::TriMesh;
use glam::{DVec3, Vec3};

use super::colour::{Rgb, patch_colour, sequential};
use super::curvature::mean_curvature;
use super::{Mode, RenderOptions};
use crate::InspectError;

/// Segments between points, drawn as lines (e.g. the input/control mesh over a surface).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LineSet {
    /// Points.
    pub positions: Vec<DVec3>,
    /// Segments as index pairs into `positions`.
    pub edges: Vec<[u32; 2]>,
}

impl LineSet {
    /// The edges of a triangle mesh (each once).
    pub fn edges_of(mesh: &TriMesh) -> LineSet {
        LineSet::from_triangles(mesh.positions().to_vec(), mesh.triangles())
    }

    /// The edges of triangles over `positions` (each undirected edge once, in first-seen
    /// order, so the result is deterministic).
    pub fn from_triangles(positions: Vec<DVec3>, triangles: &[[u32; 3]]) -> LineSet {
        let mut keys: Vec<(u32, u32, usize)> = Vec::with_capacity(3 * triangles.len());
        for (i, t) in triangles.iter().enumerate() {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                keys.push((a.min(b), a.max(b), 3 * i + k));
            }
        }
        keys.sort_unstable();
        keys.dedup_by_key(|k| (k.0, k.1));
        keys.sort_unstable_by_key(|k| k.2);
        LineSet {
            positions,
            edges: keys.into_iter().map(|(a, b, _)| [a, b]).collect(),
        }
    }
}

/// A triangle mesh to render.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RenderMesh {
    /// Vertex positions.
    pub positions: Vec<DVec3>,
    /// Per-vertex normals (need not be unit); `None`: area-weighted face normals.
    pub normals: Option<Vec<DVec3>>,
    /// Triangles (index triples into `positions`); either orientation is drawn (two-sided).
    pub triangles: Vec<[u32; 3]>,
    /// Per-triangle patch id (the patches mode needs it).
    pub patch_ids: Option<Vec<u32>>,
    /// Per-triangle patch kind; `None`: all [`PatchKind::Face`].
    pub patch_kinds: Option<Vec<PatchKind>>,
    /// Edges drawn with [`RenderOptions::wire`](super::RenderOptions::wire).
    pub wire: Option<LineSet>,
    /// Indices of triangles drawn in [`RenderOptions::highlight_colour`](super::RenderOptions::highlight_colour).
    pub highlighted: Vec<u32>,
    /// Base colour in the shaded mode (default a light warm grey).
    pub colour: Option<Rgb>,
}

impl From<&TriMesh> for RenderMesh {
    /// Positions and triangles; the file's normals if it had them; each triangle's patch is
    /// the input face it came from (`source_faces`: the triangles of a triangulated polygon
    /// share its id); the wire is the mesh's own edges.
    fn from(m: &TriMesh) -> RenderMesh {
        RenderMesh {
            positions: m.positions().to_vec(),
            normals: m.file_normals().map(<[DVec3]>::to_vec),
            triangles: m.triangles().to_vec(),
            patch_ids: Some(m.source_faces().to_vec()),
            patch_kinds: None,
            wire: Some(LineSet::edges_of(m)),
            highlighted: Vec::new(),
            colour: None,
        }
    }
}

impl From<&Tessellation> for RenderMesh {
    /// Positions, ∇F normals, triangles, patch ids and kinds; the wire is the tessellation's
    /// own edges (set [`RenderMesh::wire`] to `LineSet::edges_of(input)` to overlay the
    /// input mesh instead).
    fn from(t: &Tessellation) -> RenderMesh {
        RenderMesh {
            positions: t.positions.clone(),
            normals: Some(t.normals.clone()),
            triangles: t.triangles.clone(),
            patch_ids: Some(t.triangle_patch.clone()),
            patch_kinds: Some(t.triangle_kind.clone()),
            wire: Some(LineSet::from_triangles(t.positions.clone(), &t.triangles)),
            highlighted: Vec::new(),
            colour: None,
        }
    }
}

const DEFAULT_COLOUR: Rgb = [0.82, 0.8, 0.74];

/// All meshes of a frame in one list.
pub(crate) struct Prepared {
    pub positions: Vec<DVec3>,
    /// Unit normals, f32: they only feed 8-bit colours, for which f32's 1e-7 relative
    /// precision is far more than enough, and they halve the memory traffic per sample.
    pub normals: Vec<Vec3>,
    pub triangles: Vec<[u32; 3]>,
    /// Base colour per triangle for the mode: the mesh's colour (shaded), the patch's
    /// ([`super::colour::patch_colour`]), white where the shading makes the colour, and the
    /// highlight colour on highlighted triangles.
    pub colours: Vec<Rgb>,
    /// Curvature mode: colour per vertex.
    pub vertex_colours: Option<Vec<Rgb>>,
    pub legend_range: Option<[f64; 2]>,
    pub segments: Vec<[DVec3; 2]>,
}

fn invalid(m: String) -> InspectError {
    InspectError::InvalidOption(m)
}

fn check_mesh(i: usize, m: &RenderMesh) -> Result<(), InspectError> {
    let n = m.positions.len();
    if let Some(p) = m.positions.iter().position(|p| !p.is_finite()) {
        return Err(invalid(format!("mesh {i}: position {p} is not finite")));
    }
    if let Some((t, _)) = m
        .triangles
        .iter()
        .enumerate()
        .find(|(_, t)| t.iter().any(|&v| v as usize >= n))
    {
        return Err(invalid(format!(
            "mesh {i}: triangle {t} indexes past the {n} vertices"
        )));
    }
    let per_tri = |name: &str, len: Option<usize>| match len {
        Some(l) if l != m.triangles.len() => Err(invalid(format!(
            "mesh {i}: {l} {name} for {} triangles",
            m.triangles.len()
        ))),
        _ => Ok(()),
    };
    per_tri("patch ids", m.patch_ids.as_ref().map(Vec::len))?;
    per_tri("patch kinds", m.patch_kinds.as_ref().map(Vec::len))?;
    if let Some(nr) = &m.normals
        && nr.len() != n
    {
        return Err(invalid(format!(
            "mesh {i}: {} normals for {n} vertices",
            nr.len()
        )));
    }
    if let Some(&h) = m
        .highlighted
        .iter()
        .find(|&&h| h as usize >= m.triangles.len())
    {
        return Err(invalid(format!(
            "mesh {i}: highlighted triangle {h} out of range"
        )));
    }
    if let Some(w) = &m.wire {
        check_lines(&format!("mesh {i} wire"), w)?;
    }
    Ok(())
}

fn check_lines(name: &str, l: &LineSet) -> Result<(), InspectError> {
    if l.positions.iter().any(|p| !p.is_finite()) {
        return Err(invalid(format!("{name}: a position is not finite")));
    }
    let n = l.positions.len();
    if l.edges.iter().any(|e| e.iter().any(|&v| v as usize >= n)) {
        return Err(invalid(format!(
            "{name}: an edge indexes past the {n} points"
        )));
    }
    Ok(())
}

/// Unit vertex normals: the given ones, or area-weighted face normals (the cross product's
/// length is twice the area). Zero normals stay zero (shaded as facing the viewer).
fn unit_normals(m: &RenderMesh) -> Vec<Vec3> {
    let raw = match &m.normals {
        Some(n) => n.clone(),
        None => {
            let mut acc = vec![DVec3::ZERO; m.positions.len()];
            for t in &m.triangles {
                let p = t.map(|i| m.positions[i as usize]);
                let n = (p[1] - p[0]).cross(p[2] - p[0]);
                for &v in t {
                    acc[v as usize] += n;
                }
            }
            acc
        }
    };
    raw.iter()
        .map(|n| n.try_normalize().unwrap_or(DVec3::ZERO).as_vec3())
        .collect()
}

/// Checks the scene and flattens it for `options.mode`.
pub(crate) fn prepare(
    meshes: &[&RenderMesh],
    lines: &[&LineSet],
    options: &RenderOptions,
) -> Result<Prepared, InspectError> {
    for (i, m) in meshes.iter().enumerate() {
        check_mesh(i, m)?;
        if options.mode == Mode::Patches && m.patch_ids.is_none() {
            return Err(invalid(format!(
                "mesh {i}: the patches mode needs per-triangle patch ids"
            )));
        }
    }
    for (i, l) in lines.iter().enumerate() {
        check_lines(&format!("line set {i}"), l)?;
    }
    let mut p = Prepared {
        positions: Vec::new(),
        normals: Vec::new(),
        triangles: Vec::new(),
        colours: Vec::new(),
        vertex_colours: None,
        legend_range: None,
        segments: Vec::new(),
    };
    let mut curvature = Vec::new();
    for m in meshes {
        let base = p.positions.len() as u32;
        let normals = unit_normals(m);
        if options.mode == Mode::Curvature {
            let dn: Vec<DVec3> = normals.iter().map(|n| n.as_dvec3()).collect();
            curvature.extend(mean_curvature(&m.positions, &m.triangles, &dn));
        }
        p.positions.extend_from_slice(&m.positions);
        p.normals.extend(normals);
        p.triangles
            .extend(m.triangles.iter().map(|t| t.map(|v| v + base)));
        let start = p.colours.len();
        for (i, _) in m.triangles.iter().enumerate() {
            let c = match options.mode {
                Mode::Shaded => m.colour.unwrap_or(DEFAULT_COLOUR),
                Mode::Patches => {
                    let id = m.patch_ids.as_ref().map_or(0, |ids| ids[i]);
                    let kind = m.patch_kinds.as_ref().map_or(PatchKind::Face, |k| k[i]);
                    patch_colour(kind, id)
                }
                Mode::Isophotes | Mode::Zebra | Mode::Curvature => [1.0; 3],
            };
            p.colours.push(c);
        }
        for &h in &m.highlighted {
            p.colours[start + h as usize] = options.highlight_colour;
        }
        if options.wire
            && let Some(w) = &m.wire
        {
            p.segments.extend(segments(w));
        }
    }
    for l in lines {
        p.segments.extend(segments(l));
    }
    if p.triangles.is_empty() && p.segments.is_empty() {
        return Err(invalid("nothing to draw: no triangles and no lines".into()));
    }
    if options.mode == Mode::Curvature {
        let [lo, hi] = match options.curvature_range {
            Some(r) => r,
            None => percentile_range(&curvature),
        };
        if !(lo.is_finite() && hi.is_finite() && lo <= hi) {
            return Err(invalid(format!("bad curvature range [{lo}, {hi}]")));
        }
        // A constant field (a sphere) gets a range of ±5 % (or ±1 when zero) around it, so
        // that the map is defined and the value sits mid-bar.
        let (lo, hi) = if hi > lo {
            (lo, hi)
        } else {
            let d = if lo == 0.0 { 1.0 } else { 0.05 * lo.abs() };
            (lo - d, hi + d)
        };
        p.vertex_colours = Some(
            curvature
                .iter()
                .map(|&h| sequential((h - lo) / (hi - lo)))
                .collect(),
        );
        p.legend_range = Some([lo, hi]);
    }
    Ok(p)
}

fn segments(l: &LineSet) -> impl Iterator<Item = [DVec3; 2]> + '_ {
    l.edges
        .iter()
        .map(|e| [l.positions[e[0] as usize], l.positions[e[1] as usize]])
}

/// The 2nd and 98th percentiles (nearest rank) of the finite values; `[0, 0]` when none.
fn percentile_range(v: &[f64]) -> [f64; 2] {
    let mut s: Vec<f64> = v.iter().copied().filter(|x| x.is_finite()).collect();
    if s.is_empty() {
        return [0.0, 0.0];
    }
    s.sort_by(f64::total_cmp);
    let at = |q: f64| s[((q * (s.len() - 1) as f64).round() as usize).min(s.len() - 1)];
    [at(0.02), at(0.98)]
}
