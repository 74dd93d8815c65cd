//! `algesurf info IN [--json]`: what is in a mesh file and what `convert --repair` would do.

use std::path::PathBuf;

use algesurf_mesh::validate::finding_kind;
use algesurf_mesh::{Finding, RepairOptions, RepairReport, ValidationReport, repair, validate};

/// Arguments of `algesurf info`.
#[derive(clap::Args, Debug, Clone)]
pub struct InfoArgs {
    /// The mesh file (OBJ, PLY, STL, OFF, glTF or GLB; format by extension, else by content).
    pub input: PathBuf,
    /// Print one JSON object instead of text.
    #[arg(long)]
    pub json: bool,
}

/// Reads `args.input`, validates it, dry-runs the default repair, and prints the findings.
///
/// # Errors
/// The file cannot be read or parsed (the message names the file and the place), or the
/// mesh is too large for 32-bit indices.
pub fn run(args: &InfoArgs) -> Result<(), Box<dyn std::error::Error>> {
    let mesh = algesurf_io::read(&args.input)?;
    let report = validate(&mesh);
    let repaired = repair(&mesh, &RepairOptions::default())?;
    let text = if args.json {
        let value = to_json(&args.input, &mesh, &report, &repaired.report);
        serde_json::to_string_pretty(&value)? + "\n"
    } else {
        to_text(&args.input, &mesh, &report, &repaired.report)
    };
    // A closed pipe (`algesurf info big.ply | head`) is not an error.
    use std::io::Write;
    match std::io::stdout().lock().write_all(text.as_bytes()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(e.into()),
        _ => Ok(()),
    }
}

fn genus_text(g: Option<u32>) -> String {
    g.map_or_else(
        || "n/a (not an orientable manifold)".into(),
        |g| g.to_string(),
    )
}

/// The human-readable report.
pub fn to_text(
    input: &std::path::Path,
    mesh: &algesurf_mesh::PolygonMesh,
    report: &ValidationReport,
    repairs: &RepairReport,
) -> String {
    use std::fmt::Write;
    let mut s = String::new();
    let _ = writeln!(s, "{}", input.display());
    let _ = writeln!(s, "vertices: {}", report.vertex_count);
    let _ = writeln!(s, "faces: {}", report.face_count);
    let sizes: Vec<String> = report
        .polygon_sizes
        .iter()
        .map(|(k, n)| format!("{k}-gons: {n}"))
        .collect();
    let _ = writeln!(s, "polygon sizes: {}", sizes.join(", "));
    let _ = writeln!(
        s,
        "normals from file: {}",
        if mesh.normals.is_some() { "yes" } else { "no" }
    );
    for p in &mesh.vertex_properties {
        let _ = writeln!(s, "vertex property: {}", p.name);
    }
    for p in &mesh.face_properties {
        let _ = writeln!(s, "face property: {}", p.name);
    }
    let _ = writeln!(s, "components: {}", report.components.len());
    for (i, c) in report.components.iter().enumerate() {
        let _ = writeln!(
            s,
            "  component {i}: {} faces, {} vertices, {} edges, {} boundary edges, {} boundary loops, \
             Euler characteristic {}, genus {}, {}{}{}",
            c.faces.len(),
            c.vertex_count,
            c.edge_count,
            c.boundary_edge_count,
            c.boundary_loop_count,
            c.euler_characteristic,
            genus_text(c.genus),
            if c.manifold {
                "manifold"
            } else {
                "non-manifold"
            },
            if c.orientable { ", orientable" } else { "" },
            if c.consistently_oriented {
                ", consistently oriented"
            } else {
                ""
            },
        );
    }
    let _ = writeln!(s, "boundary loops: {}", report.boundary_loops.len());
    let _ = writeln!(s, "boundary edges: {}", report.boundary_edge_count());
    if report.findings.is_empty() {
        let _ = writeln!(s, "findings: none");
    } else {
        let counts: Vec<String> = report
            .counts()
            .iter()
            .map(|(k, n)| format!("{k} {n}"))
            .collect();
        let _ = writeln!(
            s,
            "findings: {} ({})",
            report.findings.len(),
            counts.join(", ")
        );
        for f in &report.findings {
            let _ = writeln!(s, "  {f}");
        }
    }
    let _ = write!(s, "convert --repair would: ");
    if repairs.changed() {
        let _ = writeln!(s);
        for line in repairs.to_string().lines() {
            let _ = writeln!(s, "  {line}");
        }
    } else {
        let _ = writeln!(s, "change nothing");
    }
    s
}

fn finding_json(f: &Finding) -> serde_json::Value {
    use serde_json::json;
    let mut v = match f {
        Finding::IndexOutOfRange {
            face,
            corner,
            index,
        } => {
            json!({"face": face, "corner": corner, "index": index})
        }
        Finding::TooFewCorners { face, corners } => json!({"face": face, "corners": corners}),
        Finding::RepeatedVertex { face, vertex } => json!({"face": face, "vertex": vertex}),
        Finding::NonFiniteVertex { vertex } => json!({"vertex": vertex}),
        Finding::DegenerateFace { face, area } => json!({"face": face, "area": area}),
        Finding::DuplicateFace { face, duplicate_of } => {
            json!({"face": face, "duplicate_of": duplicate_of})
        }
        Finding::UnusedVertex { vertex } => json!({"vertex": vertex}),
        Finding::NonManifoldEdge { vertices, faces } => {
            json!({"vertices": vertices, "faces": faces})
        }
        Finding::NonManifoldVertex { vertex, fans } => json!({"vertex": vertex, "fans": fans}),
        Finding::InconsistentOrientation { vertices, faces } => {
            json!({"vertices": vertices, "faces": faces})
        }
    };
    v["kind"] = json!(finding_kind(f));
    v["message"] = json!(f.to_string());
    v
}

/// The machine-readable report (what `--json` prints).
pub fn to_json(
    input: &std::path::Path,
    mesh: &algesurf_mesh::PolygonMesh,
    report: &ValidationReport,
    repairs: &RepairReport,
) -> serde_json::Value {
    use serde_json::json;
    let components: Vec<_> = report
        .components
        .iter()
        .map(|c| {
            json!({
                "faces": c.faces.len(),
                "vertices": c.vertex_count,
                "edges": c.edge_count,
                "boundary_edges": c.boundary_edge_count,
                "boundary_loops": c.boundary_loop_count,
                "euler_characteristic": c.euler_characteristic,
                "genus": c.genus,
                "manifold": c.manifold,
                "orientable": c.orientable,
                "consistently_oriented": c.consistently_oriented,
            })
        })
        .collect();
    let sizes: serde_json::Map<String, serde_json::Value> = report
        .polygon_sizes
        .iter()
        .map(|(k, n)| (k.to_string(), json!(n)))
        .collect();
    json!({
        "file": input.display().to_string(),
        "vertices": report.vertex_count,
        "faces": report.face_count,
        "polygon_sizes": sizes,
        "normals_from_file": mesh.normals.is_some(),
        "vertex_properties": mesh.vertex_properties.iter().map(|p| p.name.clone()).collect::<Vec<_>>(),
        "face_properties": mesh.face_properties.iter().map(|p| p.name.clone()).collect::<Vec<_>>(),
        "components": components,
        "boundary_loops": report.boundary_loops.len(),
        "boundary_edges": report.boundary_edge_count(),
        "valid": report.is_valid(),
        "findings": report.findings.iter().map(finding_json).collect::<Vec<_>>(),
        "repairs": {
            "changed": repairs.changed(),
            "dropped_invalid_faces": repairs.dropped_invalid_faces,
            "welded": repairs.welded,
            "collapsed_faces": repairs.collapsed_faces,
            "triangulated_faces": repairs.triangulated_faces,
            "dropped_degenerate_faces": repairs.dropped_degenerate_faces,
            "dropped_duplicate_faces": repairs.dropped_duplicate_faces,
            "flipped_faces": repairs.flipped_faces,
            "non_orientable_components": repairs.non_orientable_components,
            "dropped_unused_vertices": repairs.dropped_unused_vertices,
        },
    })
}
