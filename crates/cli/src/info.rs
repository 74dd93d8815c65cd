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
    let mesh = crate::read_mesh(&args.input)?;
    let report = validate(&mesh);
    let repaired = repair(&mesh, &RepairOptions::default())?;
    let after = validate(&repaired.mesh);
    let text = if args.json {
        let value = to_json(&args.input, &mesh, &report, &repaired.report, &after);
        serde_json::to_string_pretty(&value)? + "\n"
    } else {
        to_text(&args.input, &mesh, &report, &repaired.report, &after)
    };
    Ok(crate::print_stdout(&text)?)
}

/// At most this many components and findings of each kind are listed in the text report
/// (`--json` lists all).
const SHOW: usize = 20;

fn plural(n: usize, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

fn boundary_text(edges: usize, loops: usize) -> String {
    if edges == 0 {
        "none (closed)".into()
    } else {
        format!(
            "{} in {}",
            plural(edges, "edge", "edges"),
            plural(loops, "loop", "loops")
        )
    }
}

fn polygon_name(k: usize) -> String {
    match k {
        0..=2 => format!("{k}-corner faces"),
        3 => "triangles".into(),
        4 => "quads".into(),
        _ => format!("{k}-gons"),
    }
}

/// The human-readable report. `after` is the validation of the mesh `convert --repair` would
/// write.
pub fn to_text(
    input: &std::path::Path,
    mesh: &algesurf_mesh::PolygonMesh,
    report: &ValidationReport,
    repairs: &RepairReport,
    after: &ValidationReport,
) -> String {
    use std::fmt::Write;
    let mut s = String::new();
    let _ = writeln!(s, "file: {}", input.display());
    let _ = writeln!(s, "vertices: {}", report.vertex_count);
    let sizes: Vec<String> = report
        .polygon_sizes
        .iter()
        .map(|&(k, n)| format!("{n} {}", polygon_name(k)))
        .collect();
    let _ = writeln!(s, "faces: {} ({})", report.face_count, sizes.join(", "));
    let _ = writeln!(
        s,
        "normals from file: {}",
        if mesh.normals.is_some() { "yes" } else { "no" }
    );
    let names = |ps: &[algesurf_mesh::Property]| {
        ps.iter()
            .map(|p| p.name.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    };
    if !mesh.vertex_properties.is_empty() {
        let _ = writeln!(s, "vertex properties: {}", names(&mesh.vertex_properties));
    }
    if !mesh.face_properties.is_empty() {
        let _ = writeln!(s, "face properties: {}", names(&mesh.face_properties));
    }
    let _ = writeln!(
        s,
        "Euler characteristic V-E+F: {} (used vertices, edges and faces of the whole mesh)",
        report.euler_characteristic
    );
    let _ = writeln!(
        s,
        "boundary: {}",
        boundary_text(report.boundary_edge_count(), report.boundary_loops.len())
    );
    let _ = writeln!(s, "components: {}", report.components.len());
    for (i, c) in report.components.iter().enumerate().take(SHOW) {
        let shape = match c.genus {
            Some(g) => format!("genus {g}"),
            None if !c.manifold => "non-manifold, no genus".into(),
            None => "non-orientable, no genus".into(),
        };
        let _ = writeln!(
            s,
            "  {i}: {}, {}, {}; boundary: {}; V-E+F {}, {shape}{}",
            plural(c.faces.len(), "face", "faces"),
            plural(c.vertex_count, "vertex", "vertices"),
            plural(c.edge_count, "edge", "edges"),
            boundary_text(c.boundary_edge_count, c.boundary_loop_count),
            c.euler_characteristic,
            if c.manifold && !c.consistently_oriented {
                ", inconsistently oriented"
            } else {
                ""
            },
        );
    }
    if report.components.len() > SHOW {
        let _ = writeln!(s, "  ... and {} more", report.components.len() - SHOW);
    }
    if report.findings.is_empty() {
        let _ = writeln!(s, "findings: none");
    } else {
        let counts: Vec<String> = report
            .counts()
            .iter()
            .map(|(k, n)| format!("{n} {k}"))
            .collect();
        let _ = writeln!(
            s,
            "findings: {} ({})",
            report.findings.len(),
            counts.join(", ")
        );
        for (kind, n) in report.counts() {
            for f in report
                .findings
                .iter()
                .filter(|f| finding_kind(f) == kind)
                .take(SHOW)
            {
                let _ = writeln!(s, "  {f}");
            }
            if n > SHOW {
                let _ = writeln!(s, "  ... and {} more {kind} (see --json)", n - SHOW);
            }
        }
    }
    if repairs.changed() {
        let _ = writeln!(s, "convert --repair would:");
        for line in repairs.to_string().lines() {
            let _ = writeln!(s, "  {line}");
        }
        let tri = after.polygon_sizes.iter().all(|&(k, _)| k == 3);
        let _ = writeln!(
            s,
            "  giving {} vertices, {} {}, {}, V-E+F {}: {}",
            after.vertex_count,
            after.face_count,
            if tri { "triangles" } else { "faces" },
            plural(after.components.len(), "component", "components"),
            after.euler_characteristic,
            if after.is_valid() {
                "valid".to_string()
            } else {
                format!("still {} findings", after.findings.len())
            }
        );
    } else {
        let _ = writeln!(s, "convert --repair would: change nothing");
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
    after: &ValidationReport,
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
        "euler_characteristic": report.euler_characteristic,
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
            "detached_non_manifold_edges": repairs.detached_non_manifold_edges,
            "split_vertices": repairs.split_vertices,
            "flipped_faces": repairs.flipped_faces,
            "non_orientable_components": repairs.non_orientable_components,
            "dropped_unused_vertices": repairs.dropped_unused_vertices,
            "result": {
                "vertices": after.vertex_count,
                "faces": after.face_count,
                "components": after.components.len(),
                "euler_characteristic": after.euler_characteristic,
                "valid": after.is_valid(),
            },
        },
    })
}
