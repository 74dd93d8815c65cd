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
    /// Set when this remeshing is the second, [`split_every_strip`]'s, after the hull built on
    /// the first did not separate: that build's error and its seconds (part of construction's
    /// time).
    pub second_try: Option<(String, f64)>,
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
                    ", {} of narrow strips split",
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
        if let Some((_, seconds)) = &self.second_try {
            parts.push(format!(
                "a second remeshing, splitting narrow strips between any two flat regions: the \
                 hull on the first (every region's boundary kept) did not separate ({seconds:.2} \
                 s; the error is in the report, `flat_regions.second_try`)"
            ));
        }
        (!parts.is_empty()).then(|| format!("flat regions: {}", parts.join("; ")))
    }

    /// This outcome as the second remeshing's, after the build on the first failed with
    /// `error` in `seconds`.
    pub(crate) fn after_failure(self, error: String, seconds: f64) -> FlatOutcome {
        FlatOutcome {
            second_try: Some((error, seconds)),
            ..self
        }
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
            "second_try": self.second_try.as_ref().map(|(error, seconds)| json!({
                "split_narrow_strips_above_degrees": 0.0,
                "first_error": error,
                "seconds": seconds,
            })),
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
                    second_try: None,
                },
            ))
        }
    }
}

/// Whether a second remeshing ([`split_every_strip`]) may let the surface build after the
/// first build failed with `error`: the hull did not separate or had a degenerate
/// tetrahedron, the errors that the shape of the faces near a thin feature causes.
pub(crate) fn strips_may_help(error: &algesurf_apatch::ApatchError) -> bool {
    use algesurf_hull::HullError;
    matches!(
        error,
        algesurf_apatch::ApatchError::Hull(
            HullError::UnresolvedIntersection { .. } | HullError::DegenerateTetrahedron { .. }
        )
    )
}

/// The second remeshing of `repaired` (the mesh after repair, before the first remeshing),
/// which splits narrow strips between any two flat regions
/// ([`FlatRemeshOptions::split_narrow_strips`] `Some(0.0)`); `None` when it splits no edge
/// (then it is the first's mesh) or fails.
///
/// Why a second try and not the first: a thin plate's side walls (1 × 0.02 strips between
/// 90° creases) and a thin-walled tube's wall quads (0.13 × 2, meeting each other at 7.5°)
/// leave a hull that does not separate with any normals until their long edges are split,
/// but on meshes that build as they are splitting only multiplies the faces: a coin of 32
/// segments (radius 1, 0.01 thick) 124 faces of its caps → 8 892, a box of one quad a side
/// 12 → 14 244, a puck of 1024 segments 14 708 → 113 012. The first try keeps those as they
/// were; the price is the failed first build on the meshes that need the second (0.2–0.9 s
/// on the plates, 3.5 s on the tube).
pub(crate) fn split_every_strip(repaired: &TriMesh) -> Option<(TriMesh, FlatOutcome)> {
    let options = FlatRemeshOptions {
        split_narrow_strips: Some(0.0),
        ..FlatRemeshOptions::default()
    };
    let out = remesh_flat_regions(repaired, &options).ok()?;
    // The first remeshing splits nothing (`apply`, the default options): without a split this
    // one is the same mesh.
    (out.report.split_edges > 0).then_some((
        out.mesh,
        FlatOutcome {
            report: Some(out.report),
            second_try: None,
        },
    ))
}
