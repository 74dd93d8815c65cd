//! `algesurf smooth [INPUT] -o OUTPUT`: a C1 A-patch surface (Xu–Huang–Bajaj 2001) through a
//! triangle mesh and its vertex normals, tessellated and written as a mesh.
//!
//! Stages: read → repair (default steps) → triangle mesh → vertex normals → simplicial hull
//! → the function F (together: construction) → tessellation → check (deviation from the
//! input) → write. Each stage is timed; a spinner shows on stderr for stages longer than a
//! second when stderr is a terminal.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicU32, Ordering};
use std::time::Instant;

use crate::flat::{FlatOutcome, FlatRegionsArg};
use crate::frame::LocalFrame;
use crate::grid::{GridArgs, Resolution};
use crate::hints;
use crate::stage::{Timings, measured, stage};
use algesurf_apatch::{
    ApatchError, ApatchSurface, FaceFunction, FreeParameterRule, GradientMagnitudes, PatchKind,
    SurfaceOptions, Tessellation,
};
use algesurf_io::{PATCH_ID, WriteOptions};
use algesurf_mesh::{
    NormalMethod, PolygonMesh, Property, PropertyValues, RepairOptions, RepairReport, TriMesh,
    repair, shapes, vertex_normals,
};
use glam::DVec3;
use rayon::prelude::*;
use serde_json::json;

/// Exit status when the surface was written but some rays missed or had multiple roots.
pub const EXIT_SURFACE_DEFECTS: u8 = 3;

/// Name of the per-face property holding each output triangle's patch kind (PLY).
pub const PATCH_KIND: &str = "patch_kind";

/// The built-in mesh smoothed when no INPUT is given: the icosahedron. With its Loop normals
/// (radial, by symmetry) and the default quadric free parameters the surface is exactly the
/// unit sphere: 20 flat triangles in, a round sphere out, closed and watertight. (A coarse
/// torus, `torus(12, 8, 1.5, 0.6)`, shows more of the method, saddle regions and nonconvex
/// faces, and is valid and closed too, but has visible dents along its two parabolic circles.)
const DEFAULT_MESH: &str = "built-in icosahedron (12 vertices, 20 triangles)";

/// How `--normals` gives the vertex normals (the gradients of F at the vertices).
#[derive(clap::ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
pub enum SmoothNormals {
    /// Loop normals, and the Butterfly limit normal at vertices where the Loop normal is
    /// steeper than 60° against a face (sharp rims and folds, where hull refinement needs it);
    /// where refinement cannot separate the hull with these (meshes of long thin faces),
    /// angle-weighted normals, and the summary says so.
    Auto,
    /// Normals of the Loop subdivision limit surface (the paper's choice).
    Loop,
    /// Normals of the modified Butterfly limit surface, the scheme hull refinement splits by.
    Butterfly,
    /// Area-weighted face normals.
    Area,
    /// Angle-weighted face normals.
    Angle,
    /// The normals stored in the input file (OBJ `vn`, PLY nx/ny/nz, glTF NORMAL; an OBJ vertex whose corners name different normals takes their mean direction).
    File,
}

impl SmoothNormals {
    fn method(self) -> NormalMethod {
        match self {
            SmoothNormals::Loop => NormalMethod::Loop,
            SmoothNormals::Butterfly => NormalMethod::Butterfly,
            SmoothNormals::Auto => NormalMethod::LoopButterfly,
            SmoothNormals::Area => NormalMethod::Area,
            SmoothNormals::Angle => NormalMethod::Angle,
            SmoothNormals::File => NormalMethod::FromFile,
        }
    }
    pub(crate) fn name(self) -> &'static str {
        match self {
            SmoothNormals::Loop => "loop",
            SmoothNormals::Butterfly => "butterfly",
            SmoothNormals::Auto => "auto",
            SmoothNormals::Area => "area",
            SmoothNormals::Angle => "angle",
            SmoothNormals::File => "file",
        }
    }
}

/// How `--free-parameters` chooses the value of F at each tetrahedron apex.
#[derive(clap::ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
pub enum FreeParametersArg {
    /// From a local quadric fit: reproduces spheres, ellipsoids and other quadrics exactly.
    Quadric,
    /// From a linear fit (the paper's Step 8): valid, but loses quadric precision.
    Linear,
}

/// Where `--apex` puts the apexes of the face tetrahedra.
#[derive(clap::ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
pub enum ApexArg {
    /// The point nearest the face's centroid that satisfies the paper's conditions: low
    /// tetrahedra at sharp rims, where the paper's stand several face widths high.
    Nearest,
    /// The paper's: on the face normal through the centroid (§3.1).
    Normal,
}

impl ApexArg {
    fn placement(self) -> algesurf_hull::ApexPlacement {
        match self {
            ApexArg::Nearest => algesurf_hull::ApexPlacement::Nearest,
            ApexArg::Normal => algesurf_hull::ApexPlacement::FaceNormal,
        }
    }
}

/// How `--gradients` reads the lengths of the vertex normals.
#[derive(clap::ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
pub enum GradientsArg {
    /// As given (unit normals, or gradients read from the file).
    Given,
    /// Recovered from local quadric fits of the normals' directions: ellipsoids, cylinders
    /// and saddles sampled with unit normals are then reproduced exactly.
    Quadric,
}

impl GradientsArg {
    fn magnitudes(self) -> GradientMagnitudes {
        match self {
            GradientsArg::Given => GradientMagnitudes::AsGiven,
            GradientsArg::Quadric => GradientMagnitudes::QuadricConsistent,
        }
    }
}

impl FreeParametersArg {
    fn rule(self) -> FreeParameterRule {
        match self {
            FreeParametersArg::Quadric => FreeParameterRule::Quadric,
            FreeParametersArg::Linear => FreeParameterRule::Linear,
        }
    }
    pub(crate) fn name(self) -> &'static str {
        match self {
            FreeParametersArg::Quadric => "quadric",
            FreeParametersArg::Linear => "linear",
        }
    }
}

/// Arguments of `algesurf smooth`.
#[derive(clap::Args, Debug, Clone)]
#[command(after_help = "\
With no INPUT, smooths a built-in icosahedron (20 triangles) with Loop normals and writes \
smooth.glb in the current directory (or -o): the result is the unit sphere, exactly (quadric \
precision of the default free parameters).

Output: positions, normals from ∇F, and per-vertex `patch_id` (PLY property, glTF _PATCH_ID; \
a vertex shared by several patches gets the smallest of their ids); PLY also gets per-face \
`patch_id` and `patch_kind` (0 face, 1 edge, 2 planar).

Exit status: 0 done; 3 the surface was written, but some rays missed or had a multiple root \
(see the warning); 1 an error (bad input, a surface that cannot be built); 130 or 143 \
stopped by Ctrl-C or SIGTERM (nothing written: an existing output file is left as it was).")]
pub struct SmoothArgs {
    /// Input mesh (OBJ, PLY, STL, OFF, glTF or GLB). Omit to smooth the built-in icosahedron.
    pub input: Option<PathBuf>,
    /// Output mesh; the format follows the extension (.obj .ply .stl .off .gltf .glb).
    /// Required with INPUT; default `smooth.glb` without.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Tessellation resolution.
    #[command(flatten)]
    pub grid: GridArgs,
    /// How the surface is built.
    #[command(flatten)]
    pub surface: SurfaceArgs,
    /// Also write the summary as JSON to this file.
    #[arg(long)]
    pub report: Option<PathBuf>,
}

/// The options that decide the surface built on a mesh (shared by `smooth` and `check`).
#[derive(clap::Args, Debug, Clone)]
pub struct SurfaceArgs {
    /// Vertex normals (the gradients of the surface's function at the vertices).
    #[arg(long, value_enum, default_value_t = SmoothNormals::Auto)]
    pub normals: SmoothNormals,
    /// Rule for the free parameters (the function's value at the tetrahedron apexes).
    #[arg(long, value_enum, default_value_t = FreeParametersArg::Quadric)]
    pub free_parameters: FreeParametersArg,
    /// What the lengths of the normals mean (the gradients of the surface's function).
    #[arg(long, value_enum, default_value_t = GradientsArg::Given)]
    pub gradients: GradientsArg,
    /// Where the apexes of the face tetrahedra go.
    #[arg(long, value_enum, default_value_t = ApexArg::Nearest)]
    pub apex: ApexArg,
    /// Flat regions with skinny faces (the fan caps CAD exporters write, ear-clipped
    /// n-gons), on which the hull's refinement fails: retriangulated after repair, or kept.
    #[arg(long, value_enum, default_value_t = FlatRegionsArg::Remesh)]
    pub flat_regions: FlatRegionsArg,
}

type BoxError = Box<dyn std::error::Error>;

/// `path` made absolute and resolved as far as it exists (for comparing input and output).
pub(crate) fn resolved(path: &Path) -> PathBuf {
    if let Ok(p) = path.canonicalize() {
        return p;
    }
    let abs = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
    match (abs.parent(), abs.file_name()) {
        (Some(dir), Some(name)) => dir.canonicalize().map(|d| d.join(name)).unwrap_or(abs),
        _ => abs,
    }
}

/// `Err` naming `path` and the folder when the folder `path` would be written in does not
/// exist (or is not a folder), or takes no new file ([`algesurf_io::probe_writable`]).
pub(crate) fn folder_exists(path: &Path, what: &str) -> Result<(), BoxError> {
    let folder = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    if folder.is_dir() {
        // A folder that takes no files (permissions, a read-only or pseudo file system)
        // failed only at the write too.
        algesurf_io::probe_writable(path).map_err(|e| {
            format!(
                "{}: cannot write the {what}: cannot create a file in the folder {}: {e}",
                path.display(),
                folder.display()
            )
            .into()
        })
    } else {
        Err(format!(
            "{}: cannot write the {what}: the folder {} does not exist",
            path.display(),
            folder.display()
        )
        .into())
    }
}

/// The error for a mesh with a non-orientable component (a Möbius strip, a Klein bottle),
/// naming an edge whose two faces meet in the same direction after repair's orientation.
fn non_orientable(source: &str, components: usize, mesh: &PolygonMesh) -> String {
    let edge = algesurf_mesh::validate(mesh)
        .findings
        .into_iter()
        .find_map(|f| match f {
            algesurf_mesh::Finding::InconsistentOrientation { vertices, faces } => Some(format!(
                ": faces {} and {} traverse edge ({}, {}) in the same direction however they are \
                 turned",
                faces[0], faces[1], vertices[0], vertices[1]
            )),
            _ => None,
        })
        .unwrap_or_default();
    let (count, them) = if components == 1 {
        ("a component", "it")
    } else {
        ("components", "them")
    };
    format!(
        "{source}: {count} of the mesh cannot be oriented ({components} non-orientable, a \
         Möbius strip or a Klein bottle){edge} (ids after repair). An A-patch surface is the \
         zero set of a function, which has two sides, so it needs an orientable mesh: cut \
         {them} open or remove {them}"
    )
}

/// One line naming what repair changed ("welded 403 vertices, flipped 2 faces").
fn repair_summary(r: &RepairReport) -> String {
    if !r.changed() {
        return "no repairs needed".into();
    }
    let mut parts = Vec::new();
    let mut add = |n: usize, what: &str| {
        if n > 0 {
            parts.push(format!("{what} {n}"));
        }
    };
    add(r.dropped_invalid_faces.len(), "dropped invalid faces:");
    add(r.welded.len(), "welded vertices:");
    add(r.collapsed_faces.len(), "collapsed faces:");
    add(r.triangulated_faces.len(), "triangulated polygons:");
    add(
        r.dropped_degenerate_faces.len(),
        "dropped degenerate faces:",
    );
    add(r.dropped_duplicate_faces.len(), "dropped duplicate faces:");
    add(
        r.detached_non_manifold_edges.len(),
        "detached non-manifold edges:",
    );
    add(r.split_vertices.len(), "split non-manifold vertices:");
    add(r.flipped_faces.len(), "flipped faces:");
    add(r.dropped_unused_vertices.len(), "dropped unused vertices:");
    add(r.non_orientable_components, "non-orientable components:");
    parts.join(", ")
}

/// Counts of the surface's patches.
#[derive(Debug, Default, Clone, Copy)]
struct PatchCounts {
    face: usize,
    edge: usize,
    planar: usize,
    /// Face patches on nonconvex faces (three cubics per side on the centroid split).
    split: usize,
}

fn patch_counts(surface: &ApatchSurface) -> PatchCounts {
    let planar = surface
        .faces()
        .iter()
        .filter(|f| matches!(f, FaceFunction::Planar))
        .count();
    PatchCounts {
        face: surface.faces().len() - planar,
        edge: surface
            .edges()
            .iter()
            .filter(|e| e[0].is_some() || e[1].is_some())
            .count(),
        planar,
        split: surface
            .faces()
            .iter()
            .filter(|f| matches!(f, FaceFunction::Split(_)))
            .count(),
    }
}

fn kind_code(k: PatchKind) -> i64 {
    match k {
        PatchKind::Face => 0,
        PatchKind::Edge => 1,
        PatchKind::Planar => 2,
    }
}

/// The output mesh: positions, ∇F normals, per-vertex patch id (the smallest patch id among
/// the triangles using the vertex, so the vertex of a patch's interior gets that patch), and
/// with `face_properties` (for a format that stores them) per-face patch id and kind. The
/// positions, normals and triangles are moved out of `t`, its first vertices renumbered as
/// the repaired mesh's (`numbering`).
fn output_mesh(
    t: &mut Tessellation,
    numbering: &crate::numbering::Numbering,
    face_properties: bool,
) -> PolygonMesh {
    // Moved, not copied: 35 MB of positions and 18 MB of triangles on the bunny's
    // tessellation, whose copies' fresh pages cost ~2.4 µs per 4 KiB page here.
    let (mut positions, mut normals, mut triangles) = (
        std::mem::take(&mut t.positions),
        std::mem::take(&mut t.normals),
        std::mem::take(&mut t.triangles),
    );
    numbering.restore_vertex_order(&mut positions, &mut normals, &mut triangles);
    let mut mesh = PolygonMesh::from_owned_triangles(positions, triangles);
    mesh.normals = Some(normals);
    // The least patch id at each vertex, over the triangles in parallel: `fetch_min` gives
    // the same minimum in any order. One thread scattering 4.4 M updates into the bunny's
    // 731 k vertices at random took ~0.1 s, most of it waiting on memory.
    let least: Vec<AtomicU32> = (0..mesh.vertex_count())
        .into_par_iter()
        .map(|_| AtomicU32::new(u32::MAX))
        .collect();
    (0..mesh.face_count())
        .into_par_iter()
        .zip(&t.triangle_patch)
        .for_each(|(f, &p)| {
            for &v in mesh.face(f) {
                least[v as usize].fetch_min(p, Ordering::Relaxed);
            }
        });
    // Vertices no triangle uses (none in a valid tessellation) get patch 0.
    let vertex_patch: Vec<i64> = least
        .into_par_iter()
        .map(|p| match p.into_inner() {
            u32::MAX => 0,
            p => i64::from(p),
        })
        .collect();
    mesh.vertex_properties.push(Property {
        name: PATCH_ID.into(),
        values: PropertyValues::Int(vertex_patch),
    });
    // Two columns of i64, 22 MB on spot's 1.36 M triangles, that only PLY writes.
    if face_properties {
        mesh.face_properties.push(Property {
            name: PATCH_ID.into(),
            values: PropertyValues::Int(
                t.triangle_patch.par_iter().map(|&p| i64::from(p)).collect(),
            ),
        });
        mesh.face_properties.push(Property {
            name: PATCH_KIND.into(),
            values: PropertyValues::Int(
                t.triangle_kind.par_iter().map(|&k| kind_code(k)).collect(),
            ),
        });
    }
    mesh
}

/// Writes the report `text` to `path` atomically ([`algesurf_io::write_atomic`]: a temporary
/// file in the same directory, synced, then renamed over `path`).
pub(crate) fn write_atomic(path: &Path, text: &str) -> Result<(), BoxError> {
    algesurf_io::write_atomic(path, text.as_bytes()).map_err(|e| match e {
        algesurf_io::IoError::Io { source, .. } => {
            format!("{}: cannot write the report: {source}", path.display()).into()
        }
        other => other.into(),
    })
}

/// A surface built on the input as `smooth` builds it, with what the report needs.
pub(crate) struct Built {
    /// The triangle mesh after repair, numbered as the surface was built on it (`numbering`).
    pub tri: TriMesh,
    /// The surface.
    pub surface: ApatchSurface,
    /// How `tri` is numbered against the repaired mesh: ids shown to the user are mapped back
    /// through it.
    pub numbering: crate::numbering::Numbering,
    /// With `--normals auto`: the failed build whose hull refinement could not separate,
    /// when the surface was then built with angle-weighted normals (`normals_fallback.rs`).
    pub normals_fallback: Option<crate::normals_fallback::NormalsFallback>,
    /// One line naming the repairs.
    pub repair_text: String,
    /// The repairs as JSON.
    pub repair_json: serde_json::Value,
    /// What `--flat-regions` did (after repair, before the normals).
    pub flat: FlatOutcome,
    /// Seconds of read, repair, normals, hull, function and construction.
    timings: Timings,
    /// With `--normals file`: the vertices whose file normals were zero or not finite
    /// (replaced by the area-weighted normal) and those pointing against their faces
    /// (reversed), [`algesurf_mesh::file_normal_changes`]; empty otherwise.
    pub file_normals: (Vec<u32>, Vec<u32>),
    /// Where `tri` and `surface` lie in the input's coordinates (`frame.rs`): the input
    /// scaled by a power of two when its coordinates are beyond `2^±64`, then moved to an
    /// exact local origin ([`algesurf_mesh::Aabb::exact_local_origin`]) when it lies far from
    /// the origin for its size; neither for most inputs. [`LocalFrame::move_to_input`] moves
    /// results back.
    pub frame: LocalFrame,
}

/// The name of the input in messages: its path, or the built-in mesh's description.
pub(crate) fn source_name(input: Option<&Path>) -> String {
    input.map_or_else(|| DEFAULT_MESH.to_string(), |p| p.display().to_string())
}

/// Reads and repairs `input` (or takes the built-in icosahedron), computes the vertex normals
/// and builds the surface: the stages `smooth` and `check` share.
///
/// # Errors
/// Unreadable input, a failed repair, no faces, no normals, or a mesh the surface cannot be
/// built on; each message names the input and the stage.
pub(crate) fn build(
    input: Option<&Path>,
    args: &SurfaceArgs,
    progress: bool,
) -> Result<Built, BoxError> {
    let source = source_name(input);
    let mut t = Timings::default();
    let mut exponent = 0;
    // Read and repair (the built-in mesh needs neither).
    let (tri, repair_text, repair_json, flat, repaired) = match input {
        Some(path) => {
            let (mesh, dt, usage) = measured("reading", progress, |_| crate::read_mesh(path));
            (t.read, t.usage.read) = (dt, usage);
            crate::interrupt::check()?;
            let mut mesh = mesh?;
            // Coordinates beyond 2^±64 are built at a power of two's scale (`frame.rs`), from
            // the repair on: its area threshold squares the bounding box's diagonal.
            exponent = algesurf_mesh::geometry::exact_scale_exponent(&mesh.positions);
            algesurf_mesh::geometry::scale_by_power_of_two(&mut mesh.positions, -exponent);
            let (repaired, dt, usage) = measured("repairing", progress, |_| {
                repair(&mesh, &RepairOptions::default())
            });
            (t.repair, t.usage.repair) = (dt, usage);
            crate::interrupt::check()?;
            let repaired =
                repaired.map_err(|e| format!("{}: repair failed: {e}", path.display()))?;
            let r = &repaired.report;
            let text = repair_summary(r);
            let rj = json!({
                "changed": r.changed(),
                "summary": text,
                "dropped_invalid_faces": r.dropped_invalid_faces.len(),
                "welded_vertices": r.welded.len(),
                "collapsed_faces": r.collapsed_faces.len(),
                "triangulated_polygons": r.triangulated_faces.len(),
                "dropped_degenerate_faces": r.dropped_degenerate_faces.len(),
                "dropped_duplicate_faces": r.dropped_duplicate_faces.len(),
                "detached_non_manifold_edges": r.detached_non_manifold_edges.len(),
                "split_vertices": r.split_vertices.len(),
                "flipped_faces": r.flipped_faces.len(),
                "dropped_unused_vertices": r.dropped_unused_vertices.len(),
                "non_orientable_components": r.non_orientable_components,
            });
            let tri = TriMesh::from_polygon_mesh(&repaired.mesh).map_err(|e| {
                format!("{}: not a triangle mesh after repair: {e}", path.display())
            })?;
            if tri.face_count() == 0 {
                // A file whose every face repair dropped (NaN or collinear corners,
                // coordinates so large or small that the areas overflow or underflow f64) is
                // not a file without faces: say what repair removed.
                let after = if mesh.face_count() > 0 {
                    format!(" after repair ({text})")
                } else {
                    String::new()
                };
                return Err(format!("{source}: the mesh has no faces{after}").into());
            }
            if r.non_orientable_components > 0 {
                return Err(
                    non_orientable(&source, r.non_orientable_components, &repaired.mesh).into(),
                );
            }
            // Kept for a second remeshing, should the hull on the first not separate
            // (`crate::flat::split_every_strip`): a copy of the positions and triangles.
            let repaired = (args.flat_regions == FlatRegionsArg::Remesh).then(|| tri.clone());
            // Part of the repair stage (its time and usage): the remesher's fast path, on a
            // mesh without flat regions of skinny faces, is a pass over the edges.
            let (flat, dt, usage) = measured("remeshing flat regions", progress, |_| {
                crate::flat::apply(tri, args.flat_regions)
            });
            t.repair += dt;
            t.usage.repair = t.usage.repair.plus(usage);
            let (tri, flat) = flat
                .map_err(|e| format!("{}: remeshing flat regions failed: {e}", path.display()))?;
            (tri, text, rj, flat, repaired)
        }
        None => (
            shapes::icosphere(0),
            "no repairs needed".to_string(),
            json!({ "changed": false, "summary": "no repairs needed" }),
            FlatOutcome::default(),
            None,
        ),
    };
    // A mesh far from the origin for its size is built about an origin near it, moved to
    // exactly (`Aabb::exact_local_origin`): its absolute coordinates' rounding, relative to
    // the mesh, grows with the distance, and the cow moved by 1000 failed to build. The
    // results are moved back by the callers (`LocalFrame::move_to_input`).
    let mut tri = tri;
    let origin = tri.bounding_box().exact_local_origin();
    if origin != DVec3::ZERO {
        for p in tri.positions_mut() {
            *p -= origin;
        }
    }
    let (normals, dt, usage) = measured("normals", progress, |_| {
        vertex_normals(&tri, args.normals.method())
    });
    (t.normals, t.usage.normals) = (dt, usage);
    crate::interrupt::check()?;
    let normals = normals.map_err(|e| {
        let hint = if args.normals == SmoothNormals::File {
            " (the file has no normals: use --normals loop)"
        } else {
            ""
        };
        format!("{source}: cannot compute normals: {e}{hint}")
    })?;
    let mut file_normals = if args.normals == SmoothNormals::File {
        algesurf_mesh::file_normal_changes(&tri).unwrap_or_default()
    } else {
        Default::default()
    };

    let options = SurfaceOptions {
        free_parameters: args.free_parameters.rule(),
        gradient_magnitudes: args.gradients.magnitudes(),
        hull: algesurf_hull::HullOptions {
            apex: args.apex.placement(),
            ..algesurf_hull::HullOptions::default()
        },
        ..SurfaceOptions::default()
    };
    // Ids in hull and surface errors are those of the repaired mesh.
    let ids_note = if flat.changed() {
        " (vertex and face ids are those after repair and the remeshing of flat regions; \
         `algesurf info` lists the repairs, and --flat-regions keep builds on the repaired faces)"
    } else if repair_json["changed"] == true {
        " (vertex and face ids are those after repair; `algesurf info` lists the repairs)"
    } else {
        ""
    };
    // On the spatial numbering (`numbering.rs`), falling back to `tri`'s own when that
    // fails, and with `--normals auto` to angle-weighted normals when refinement cannot
    // separate the hull (`normals_fallback.rs`): `tri` is the mesh the surface was built on
    // from here.
    let auto = args.normals == SmoothNormals::Auto;
    let ((mut surface, mut tri, mut numbering, mut attempts), dt, usage) =
        measured("building the hull and the surface", progress, |p| {
            crate::normals_fallback::build_surface_or_fall_back(tri, &normals, auto, &options, p)
        });
    (t.construction, t.usage.construction) = (dt, usage);
    // Before the error is read: a `Cancelled` one is the signal's doing.
    crate::interrupt::check()?;
    let mut flat = flat;
    // Where the hull did not separate (or had a degenerate tetrahedron) with every normals
    // choice, a second remeshing that splits narrow strips between any two flat regions (the
    // first keeps every region's boundary), and a second build on it
    // (`crate::flat::split_every_strip`).
    if let (Err(error), Some(repaired)) = (&surface, &repaired)
        && crate::flat::strips_may_help(error)
        && let Some((mut second, outcome)) = crate::flat::split_every_strip(repaired)
    {
        if origin != DVec3::ZERO {
            for p in second.positions_mut() {
                *p -= origin;
            }
        }
        if let Ok(normals) = vertex_normals(&second, args.normals.method()) {
            let first_error = error.to_string();
            let ((again, second, second_numbering, second_attempts), dt, usage) =
                measured("building the hull and the surface again", progress, |p| {
                    crate::normals_fallback::build_surface_or_fall_back(
                        second, &normals, auto, &options, p,
                    )
                });
            crate::interrupt::check()?;
            let first_seconds = t.construction;
            t.construction += dt;
            t.usage.construction = t.usage.construction.plus(usage);
            if again.is_ok() {
                if args.normals == SmoothNormals::File {
                    file_normals = algesurf_mesh::file_normal_changes(&second).unwrap_or_default();
                }
                (surface, tri, numbering, attempts) =
                    (again, second, second_numbering, second_attempts);
                flat = outcome.after_failure(first_error, first_seconds);
            }
        }
    }
    let surface = surface.map_err(|e| match e {
        ApatchError::Hull(e) => {
            let hint = match e {
                algesurf_hull::HullError::UnresolvedIntersection { .. } => format!(
                    "{}{}{}",
                    if attempts.fallback_failed {
                        " (built again with angle-weighted normals, which left overlapping \
                         tetrahedra too)"
                    } else {
                        ""
                    },
                    hints::sharp_rim(args.normals, args.apex),
                    hints::thin_faces(&tri)
                ),
                algesurf_hull::HullError::DegenerateTetrahedron { .. }
                    if attempts.fallback_failed =>
                {
                    " (built again with angle-weighted normals, which failed too)".to_string()
                }
                _ => String::new(),
            };
            format!("{source}: cannot build the simplicial hull: {e}{ids_note}{hint}")
        }
        e => {
            let hint = hints::sliver(&tri, &e);
            format!("{source}: cannot build the surface: {e}{ids_note}{hint}")
        }
    })?;
    t.hull = surface.timings().hull.as_secs_f64();
    t.function = surface.timings().function.as_secs_f64();
    Ok(Built {
        tri,
        surface,
        numbering,
        normals_fallback: attempts.fallback,
        repair_text,
        repair_json,
        flat,
        timings: t,
        file_normals,
        frame: LocalFrame { exponent, origin },
    })
}

/// Smooths the input (or the built-in icosahedron) and writes the surface.
///
/// Returns the exit code: success, or [`EXIT_SURFACE_DEFECTS`] when rays missed or had
/// multiple roots (the output is written all the same).
///
/// # Errors
/// Unreadable input, a mesh the surface cannot be built on (the message names the file and
/// the stage), an output or report path equal to the input, or a write failure.
pub fn run(args: &SmoothArgs) -> Result<ExitCode, BoxError> {
    let progress = std::io::stderr().is_terminal();
    let total_start = Instant::now();
    let source = source_name(args.input.as_deref());
    let output = match (&args.input, &args.output) {
        (_, Some(o)) => o.clone(),
        (None, None) => PathBuf::from("smooth.glb"),
        (Some(_), None) => {
            return Err("smooth: -o OUTPUT is required when an INPUT is given".into());
        }
    };
    if let Some(input) = &args.input {
        let inp = resolved(input);
        if resolved(&output) == inp {
            return Err(format!(
                "{}: refusing to overwrite the input with the output",
                input.display()
            )
            .into());
        }
        if args.report.as_deref().is_some_and(|r| resolved(r) == inp) {
            return Err(format!(
                "{}: refusing to overwrite the input with the report",
                input.display()
            )
            .into());
        }
    }
    if args
        .report
        .as_deref()
        .is_some_and(|r| resolved(r) == resolved(&output))
    {
        return Err(format!(
            "{}: the report and the output are the same file",
            output.display()
        )
        .into());
    }
    // An output name without a mesh format's extension, and folders that do not exist, fail
    // now, not after the surface is built (seconds on the bunny, minutes on larger meshes;
    // `-o out` failed after 2.8 s of work on the bunny).
    crate::known_format(&output)?;
    folder_exists(&output, "output")?;
    if let Some(report) = &args.report {
        folder_exists(report, "report")?;
    }
    let Built {
        mut tri,
        surface,
        numbering,
        normals_fallback,
        repair_text,
        repair_json,
        flat,
        timings,
        file_normals,
        frame,
    } = build(args.input.as_deref(), &args.surface, progress)?;
    let mut t = timings;
    let refinements = surface.hull().refinements().len();
    let rounds = surface
        .hull()
        .refinements()
        .iter()
        .map(|r| r.round + 1)
        .max()
        .unwrap_or(0);

    let (n, m) = args
        .grid
        .fitting_steps(&surface)
        .map_err(|e| format!("{source}: {e}"))?;
    let (tess, dt, usage) = measured("tessellating", progress, |p| {
        surface.tessellate_with_progress(n, m, p)
    });
    (t.tessellation, t.usage.tessellation) = (dt, usage);
    crate::interrupt::check()?;
    let mut tess =
        tess.map_err(|e| format!("{source}: cannot tessellate at resolution {n} × {m}: {e}"))?;
    // The output, and the deviation measured on it, in the input's coordinates; but for the
    // power of two of an input beyond 2^±64 (`frame.rs`), which is undone after the deviation
    // is measured: at the input's scale its squared distances would overflow or underflow.
    frame.restore_origin(&mut tri, &mut tess.positions);

    let min_margin = surface
        .free_parameters()
        .iter()
        .map(|p| p.relative_margin)
        .fold(f64::INFINITY, f64::min);
    let counts = patch_counts(&surface);
    let hull_faces = surface.hull().mesh().face_count();
    // Faces of the input that pass through each other: the surface does there too (their
    // tetrahedra are left overlapping, see `SimplicialHull::distant_intersections`).
    let crossings = numbering.repaired_faces(surface.hull().input_crossings());
    // Vertices whose normals were moved into their faces' cone, in the repaired numbering.
    let adjusted = numbering.repaired_vertices(surface.adjusted_normals());
    // A build on the spatial numbering that failed before this one (`numbering.rs`): its time
    // is part of construction's, so the summary and the report say so.
    let spatial = numbering.is_spatial();
    let spatial_failure = numbering.spatial_failure().cloned();

    let (out_vertices, out_triangles) = (tess.positions.len(), tess.triangles.len());
    // Per-face patch ids and kinds only where the format stores face properties (PLY).
    let face_properties = algesurf_io::Format::from_path(&output) == Some(algesurf_io::Format::Ply);
    let out_mesh = output_mesh(&mut tess, &numbering, face_properties);
    // What is written: the output at the input's scale (a copy only for a rescaled input).
    let written_mesh = if frame.exponent == 0 {
        std::borrow::Cow::Borrowed(&out_mesh)
    } else {
        let mut m = out_mesh.clone();
        frame.restore_scale(&mut m.positions);
        std::borrow::Cow::Owned(m)
    };
    let write_options = WriteOptions::default();
    // The check and the write at the same time: the write is mostly the kernel's (copying
    // into the page cache, `fsync`, and the rename freeing a replaced file's pages: 0.13 s and
    // 0.06 s of waiting on the bunny's 88 MB PLY, `strace -T`), the check computation on the
    // thread pool; one after the other they took 0.11 + 0.40 s there. The check reads the
    // output mesh's positions, the tessellation's moved there.
    let ((checked, written), dt, usage) = measured("checking and writing", progress, |_| {
        std::thread::scope(|scope| {
            // Each part timed on its own (no spinner: the pair has one).
            let writer = scope.spawn(|| {
                stage("writing", false, |p| {
                    algesurf_io::write_with_progress(&output, &written_mesh, &write_options, p)
                })
            });
            let checked = stage("checking", false, |_| {
                (
                    crate::deviation::max_deviation(
                        &tri,
                        &out_mesh.positions,
                        &crate::deviation::input_face_hints(
                            &surface,
                            &out_mesh,
                            &tess.triangle_patch,
                        ),
                    ),
                    crate::continuity::sampled_continuity(&surface),
                )
            });
            (checked, writer.join())
        })
    });
    let (((deviation, diagonal), continuity), check_time) = checked;
    let (deviation, diagonal) = (frame.length(deviation), frame.length(diagonal));
    let (written, write_time) = written.map_err(|_| "the thread writing the output panicked")?;
    (t.check, t.write, t.check_and_write) = (check_time, write_time, dt);
    t.usage.check_and_write = usage;
    // A write that Ctrl-C stopped has removed its temporary file; one that finished stands,
    // and the command goes on to its report and summary.
    if written.is_err() {
        crate::interrupt::check()?;
    }
    written?;
    let total = total_start.elapsed().as_secs_f64();
    let peak = crate::memory::peak_resident_bytes();
    let stage_usage = t.usage.named();

    let missed = tess.missed_rays.len();
    let multiple = tess.multiple_roots.len();
    let ok = missed == 0 && multiple == 0;
    let margin_json = if min_margin.is_finite() {
        json!(min_margin)
    } else {
        json!(null)
    };
    let rel_dev = if diagonal > 0.0 {
        deviation / diagonal
    } else {
        0.0
    };
    let report = json!({
        "input": source,
        "output": output.display().to_string(),
        "options": {
            "resolution": n,
            "resolution_auto": args.grid.resolution == Resolution::Auto,
            "across": m,
            "normals": args.surface.normals.name(),
            "free_parameters": args.surface.free_parameters.name(),
            "flat_regions": args.surface.flat_regions.name(),
        },
        "input_mesh": {
            "vertices": tri.vertex_count(),
            "faces": tri.face_count(),
            "euler_characteristic": tri.euler_characteristic(),
        },
        "adjusted_normals": &adjusted,
        "file_normals": {
            "replaced": &file_normals.0,
            "reversed": &file_normals.1,
        },
        "repair": repair_json,
        "flat_regions": flat.json(args.surface.flat_regions),
        "hull": {
            "faces": hull_faces,
            "refinements": refinements,
            "refinement_rounds": rounds,
            "input_crossings": crossings.len(),
        },
        // The numbering the surface was built on (`numbering.rs`): the spatial order, or the
        // repaired mesh's own after a failed build on the spatial order (its error and time).
        "numbering": {
            "spatial": spatial,
            "spatial_failure": spatial_failure.as_ref().map(|f| json!({
                "error": f.error,
                "seconds": f.seconds,
            })),
        },
        // With `--normals auto`: the build whose hull did not separate or had a degenerate
        // tetrahedron, when the surface was then built with angle-weighted normals
        // (`normals_fallback.rs`).
        "normals_fallback": normals_fallback.as_ref().map(|f| f.json()),
        "patches": {
            "face": counts.face,
            "edge": counts.edge,
            "planar": counts.planar,
            "split_faces": counts.split,
            "total": counts.face + counts.edge + counts.planar,
        },
        "output_mesh": {
            "vertices": out_vertices,
            "triangles": out_triangles,
        },
        "free_parameters": {
            "count": surface.free_parameters().len(),
            "min_relative_margin": margin_json,
        },
        "deviation": {
            "max": deviation,
            "max_relative": rel_dev,
            "bbox_diagonal": diagonal,
        },
        "continuity": {
            "faces_sampled": continuity.faces,
            "faces": continuity.of,
            "facets": continuity.facets,
            "samples": continuity.samples,
            "max_value_relative": continuity.value,
            "max_gradient_relative": continuity.gradient,
        },
        "missed_rays": missed,
        "multiple_roots": multiple,
        "ok": ok,
        "timings_s": {
            "read": t.read,
            "repair": t.repair,
            "normals": t.normals,
            "hull": t.hull,
            "function": t.function,
            "construction": t.construction,
            "tessellation": t.tessellation,
            "check": t.check,
            "write": t.write,
            "check_and_write": t.check_and_write,
            "total": total,
        },
        // Linux only (null elsewhere): see `memory.rs`.
        "memory": {
            "peak_resident_bytes": peak,
            "minor_page_faults": stage_usage
                .iter()
                .map(|&(k, u)| (k.to_string(), json!(u.faults)))
                .collect::<serde_json::Map<_, _>>(),
        },
        // CPU seconds of each stage, all threads (user + system; Linux only, null elsewhere:
        // see `cpu.rs`): beside `timings_s`, how many cores a stage kept busy.
        "cpu_s": stage_usage
            .iter()
            .map(|&(k, u)| (k.to_string(), json!(u.cpu)))
            .collect::<serde_json::Map<_, _>>(),
    });

    let ms = |s: f64| format!("{:.1} ms", s * 1e3);
    let mut s = String::new();
    {
        use std::fmt::Write;
        let _ = writeln!(s, "{source} → {}", output.display());
        let _ = writeln!(s, "repair: {repair_text}");
        if let Some(line) = flat.summary() {
            let _ = writeln!(s, "{line}");
        }
        let _ = writeln!(
            s,
            "faces in: {} ({} vertices); hull faces: {hull_faces} ({refinements} refinements in {rounds} rounds)",
            tri.face_count(),
            tri.vertex_count()
        );
        // Up to eight ids, then an ellipsis.
        let ids = |v: &[u32]| {
            let shown: Vec<String> = v.iter().take(8).map(u32::to_string).collect();
            format!(
                "{}{}",
                shown.join(", "),
                if v.len() > 8 { ", …" } else { "" }
            )
        };
        let (replaced, reversed) = &file_normals;
        if !replaced.is_empty() {
            let _ = writeln!(
                s,
                "file normals: {} zero or not finite, replaced by the area-weighted normal (vertices {})",
                replaced.len(),
                ids(replaced)
            );
        }
        if !reversed.is_empty() {
            let _ = writeln!(
                s,
                "file normals: {} pointing against their faces, reversed (vertices {})",
                reversed.len(),
                ids(reversed)
            );
        }
        if !adjusted.is_empty() {
            // A normal at or past 84° from a face at its vertex is moved into its faces' cone
            // before the hull is built: say so, as the surface no longer has that normal
            // there.
            let _ = writeln!(
                s,
                "normals: {} adjusted into their faces' cone (vertices {})",
                adjusted.len(),
                ids(&adjusted)
            );
        }
        if let Some(fallback) = &normals_fallback {
            let _ = writeln!(
                s,
                "normals: with the auto normals {} ({}; the error is in the report, \
                 `normals_fallback.auto_error`); built with angle-weighted normals, {} \
                 (construction's time includes both)",
                fallback.cause.failure(),
                ms(fallback.seconds),
                fallback.cause.success()
            );
        }
        if let Some(failure) = &spatial_failure {
            let _ = writeln!(
                s,
                "numbering: the build on the spatial numbering failed after {} (its error is \
                 in the report, `numbering.spatial_failure`); built again on the mesh's own \
                 numbering, which succeeded (construction's time includes both)",
                ms(failure.seconds)
            );
        }
        if let Some([f, g]) = crossings.first() {
            let _ = writeln!(
                s,
                "input self-crossings: {} face pairs (first: faces {f} and {g}); the surface passes \
                 through itself there too",
                crossings.len()
            );
        }
        let _ = writeln!(
            s,
            "patches out: {} ({} face, of which {} on split nonconvex faces; {} edge; {} planar)",
            counts.face + counts.edge + counts.planar,
            counts.face,
            counts.split,
            counts.edge,
            counts.planar
        );
        let _ = writeln!(
            s,
            "output: {} triangles, {} vertices (resolution {n}{}, across {m})",
            out_triangles,
            out_vertices,
            if args.grid.resolution == Resolution::Auto {
                " auto"
            } else {
                ""
            }
        );
        let _ = writeln!(
            s,
            "time: read {}, repair {}, normals {}, hull {} (+{rounds} refinement rounds), function {}, tessellation {}, check {} and write {} (concurrent: {}); total {}",
            ms(t.read),
            ms(t.repair),
            ms(t.normals),
            ms(t.hull),
            ms(t.function),
            ms(t.tessellation),
            ms(t.check),
            ms(t.write),
            ms(t.check_and_write),
            ms(total)
        );
        let margin_text = if min_margin.is_finite() {
            format!("{min_margin:.3e}")
        } else {
            "n/a (no free parameters)".into()
        };
        if let Some(peak) = peak {
            let faults: Vec<String> = stage_usage
                .iter()
                .filter_map(|&(k, u)| Some(format!("{k} {}", u.faults?)))
                .collect();
            let _ = writeln!(
                s,
                "memory: peak {:.0} MB resident; page faults: {}",
                peak as f64 / 1e6,
                faults.join(", ")
            );
        }
        // CPU seconds per stage, and for the timed pair the cores it kept busy on average
        // (when the stage is long enough for the 10 ms ticks: `cpu::cores_busy`).
        let cpu: Vec<String> = stage_usage
            .iter()
            .filter_map(|&(k, u)| {
                let cpu = u.cpu?;
                let wall = match k {
                    "construction" => t.construction,
                    "tessellation" => t.tessellation,
                    _ => return Some(format!("{k} {cpu:.2} s")),
                };
                Some(match crate::cpu::cores_busy(cpu, wall) {
                    Some(cores) => format!("{k} {cpu:.2} s ({cores:.1} cores)"),
                    None => format!("{k} {cpu:.2} s"),
                })
            })
            .collect();
        if !cpu.is_empty() {
            let _ = writeln!(s, "cpu (all threads): {}", cpu.join(", "));
        }
        let _ = writeln!(s, "min free-parameter margin: {margin_text}");
        let _ = writeln!(
            s,
            "max deviation from the input: {deviation:.3e} ({rel_dev:.3e} of the bbox diagonal)"
        );
        let _ = writeln!(
            s,
            "continuity (C1 on {} of {} hull faces, {} facets, {} points): value {:.1e}, gradient {:.1e} (relative; every facet: algesurf check)",
            continuity.faces,
            continuity.of,
            continuity.facets,
            continuity.samples,
            continuity.value,
            continuity.gradient
        );
        let _ = writeln!(s, "missed rays: {missed}, multiple roots: {multiple}");
    }
    crate::print_stdout(&s)?;
    if let Some(path) = &args.report {
        write_atomic(path, &(serde_json::to_string_pretty(&report)? + "\n"))?;
    }
    // `!(x <= t)`: a NaN (a gradient vanishing on a facet) warns too.
    if !(continuity.value <= algesurf_inspect::check::C1_VALUE
        && continuity.gradient <= algesurf_inspect::check::C1_GRADIENT)
    {
        crate::print_stderr(format_args!(
            "algesurf: warning: {source}: C1 on the sampled facets is above `algesurf check`'s \
             thresholds (value {:.1e} > {:.0e} or gradient {:.1e} > {:.0e}); run `algesurf check` \
             for every facet",
            continuity.value,
            algesurf_inspect::check::C1_VALUE,
            continuity.gradient,
            algesurf_inspect::check::C1_GRADIENT
        ));
    }
    // `main` returns next and the process exits: dropping the input mesh, the surface and
    // the tessellation would free their hundreds of megabytes block by block (about 0.1 s
    // of wall time after the summary on the bunny, `perf`: `mi_free`, `Vec::drop`,
    // `drop_in_place<ApatchSurface>`), which the kernel reclaims at exit anyway.
    std::mem::forget(written_mesh);
    std::mem::forget((tri, surface, tess, out_mesh));
    if ok {
        Ok(ExitCode::SUCCESS)
    } else {
        crate::print_stderr(format_args!(
            "algesurf: warning: {source}: the surface has {missed} missed rays and {multiple} rays with a multiple root \
             (single-sheet violations); {} was written, but those points are not on a valid A-patch",
            output.display()
        ));
        Ok(ExitCode::from(EXIT_SURFACE_DEFECTS))
    }
}
