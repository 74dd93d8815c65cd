//! `--flat-regions`: what the commands that build a surface do with flat regions of skinny
//! faces after repair (`algesurf_mesh::flat`): the fan caps CAD exporters write, and the fans
//! repair's ear clipping makes of an n-gon, on which the simplicial hull's refinement fails.

use algesurf_mesh::TriMesh;
use algesurf_mesh::flat::{FlatRemeshOptions, FlatRemeshReport, remesh_flat_regions};
use serde_json::json;

/// How `--flat-regions` treats flat regions with skinny faces.
#[derive(clap::ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
pub enum FlatRegionsArg {
    /// Retriangulate each flat region that has a face with an angle below 10° (a refined
    /// constrained Delaunay triangulation of the same polygon: every vertex and boundary edge
    /// kept, vertices added inside); the summary says which.
    Remesh,
    /// Build on the faces as they are.
    Keep,
}

impl FlatRegionsArg {
    /// The name the report gives.
    pub(crate) fn name(self) -> &'static str {
        match self {
            FlatRegionsArg::Remesh => "remesh",
            FlatRegionsArg::Keep => "keep",
        }
    }
}

/// What `--flat-regions remesh` did, for the summary and the report.
#[derive(Debug, Clone, Default)]
pub(crate) struct FlatOutcome {
    /// The remesher's report (`None` with `keep` and for the built-in mesh).
    pub report: Option<FlatRemeshReport>,
}

impl FlatOutcome {
    /// True when some region was replaced.
    pub(crate) fn changed(&self) -> bool {
        self.report.as_ref().is_some_and(FlatRemeshReport::changed)
    }

    /// One line for the summary, or `None` when there is nothing to say.
    pub(crate) fn summary(&self) -> Option<String> {
        let r = self.report.as_ref()?;
        let mut parts = Vec::new();
        if !r.remeshed.is_empty() {
            let before: usize = r.remeshed.iter().map(|x| x.faces.len()).sum();
            let after: u32 = r.remeshed.iter().map(|x| x.new_faces).sum();
            let skinny: u32 = r.remeshed.iter().map(|x| x.skinny_before).sum();
            let left: u32 = r.remeshed.iter().map(|x| x.skinny_after).sum();
            let least = |f: fn(&algesurf_mesh::flat::RemeshedRegion) -> f64| {
                r.remeshed.iter().map(f).fold(f64::INFINITY, f64::min)
            };
            let split = if r.split_edges > 0 {
                format!(
                    ", {} of narrow strips split at creases",
                    plural(r.split_edges as usize, "edge")
                )
            } else {
                String::new()
            };
            parts.push(format!(
                "remeshed {} with {skinny} skinny faces ({before} faces → {after}, {} vertices \
                 added{split}; least angle {:.1}° → {:.1}°{})",
                plural(r.remeshed.len(), "region"),
                r.added_vertices,
                least(|x| x.min_angle_before),
                least(|x| x.min_angle_after),
                if left > 0 {
                    format!(", {left} skinny faces left at the boundary")
                } else {
                    String::new()
                },
            ));
        }
        // A flat quad split into two skinny triangles (the teapot has 500) is a region no
        // triangulation improves: the report lists it, the summary does not.
        let skipped: Vec<_> = r.skipped.iter().filter(|x| x.faces.len() > 2).collect();
        if let Some(first) = skipped.first() {
            parts.push(format!(
                "kept {} with skinny faces as they are (first: faces {}…, as {})",
                plural(skipped.len(), "region"),
                first.faces[0],
                first.reason
            ));
        }
        (!parts.is_empty()).then(|| format!("flat regions: {}", parts.join("; ")))
    }

    /// The report's `flat_regions` object.
    pub(crate) fn json(&self, arg: FlatRegionsArg) -> serde_json::Value {
        let Some(r) = &self.report else {
            return json!({ "mode": arg.name(), "remeshed": [], "skipped": [] });
        };
        json!({
            "mode": arg.name(),
            "added_vertices": r.added_vertices,
            "split_edges": r.split_edges,
            "remeshed": r.remeshed.iter().map(|x| json!({
                "first_face": x.faces[0],
                "faces": x.faces.len(),
                "new_faces": x.new_faces,
                "added_vertices": x.added_vertices,
                "boundary_vertices": x.boundary_vertices,
                "skinny_before": x.skinny_before,
                "skinny_after": x.skinny_after,
                "min_angle_before_degrees": x.min_angle_before,
                "min_angle_after_degrees": x.min_angle_after,
            })).collect::<Vec<_>>(),
            "skipped": r.skipped.iter().map(|x| json!({
                "first_face": x.faces[0],
                "faces": x.faces.len(),
                "reason": x.reason.to_string(),
            })).collect::<Vec<_>>(),
        })
    }
}

fn plural(n: usize, what: &str) -> String {
    if n == 1 {
        format!("1 {what}")
    } else {
        format!("{n} {what}s")
    }
}

/// `tri` with its flat regions of skinny faces remeshed (`remesh`), or as it is (`keep`).
///
/// # Errors
/// The remesher's, which only a mesh beyond 32-bit indices gives (the options are the
/// defaults).
pub(crate) fn apply(
    tri: TriMesh,
    arg: FlatRegionsArg,
) -> Result<(TriMesh, FlatOutcome), algesurf_mesh::MeshError> {
    match arg {
        FlatRegionsArg::Keep => Ok((tri, FlatOutcome::default())),
        FlatRegionsArg::Remesh => {
            let out = remesh_flat_regions(&tri, &FlatRemeshOptions::default())?;
            Ok((
                out.mesh,
                FlatOutcome {
                    report: Some(out.report),
                },
            ))
        }
    }
}
