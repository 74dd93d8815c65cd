//! What the errors of `algesurf smooth` (and of the commands that build a surface as it does)
//! add when the input or the options explain them: a sliver face, normals or apexes other
//! than those made for sharp rims, a mesh made of thin faces.

use crate::smooth::{ApexArg, SmoothNormals};
use algesurf_apatch::ApatchError;
use algesurf_mesh::TriMesh;
use algesurf_mesh::geometry::{THIN_FACE_SHAPE, triangle_shape};

/// Where a tetrahedron on an input face came out degenerate and the face itself is a sliver
/// (twice its area over its longest edge squared below 1e-6: a needle or a cap), says so:
/// the face's tetrahedra inherit its shape, and `Simplex`'s tolerance (1e-10 of the longest
/// edge cubed) rejects them before the face's own area reaches repair's degenerate-face
/// threshold (1e-14 of the bounding box's diagonal squared). Empty otherwise.
pub(crate) fn sliver(tri: &TriMesh, e: &ApatchError) -> String {
    let ApatchError::AtFace {
        input_face, source, ..
    } = e
    else {
        return String::new();
    };
    if !matches!(
        **source,
        ApatchError::Bb(algesurf::bb::BbError::DegenerateSimplex { .. })
    ) {
        return String::new();
    }
    let Some(&[a, b, c]) = tri.triangles().get(*input_face as usize) else {
        return String::new();
    };
    let p = tri.positions();
    let shape = triangle_shape(p[a as usize], p[b as usize], p[c as usize]);
    if shape < 1e-6 {
        format!(
            " (input face {input_face} is a sliver: twice its area over its longest edge squared \
             is {shape:.1e}; collapse its short edge or remesh there)"
        )
    } else {
        String::new()
    }
}

/// What to try when refinement could not separate the hull's tetrahedra and the command ran
/// with normals or apexes other than those made for sharp rims (`docs/ARCHITECTURE.md`, sharp
/// rims): with the defaults every mesh of the test corpus builds, and Suzanne, for one, does
/// not with Loop, area- or angle-weighted normals or with the paper's apexes.
pub(crate) fn sharp_rim(normals: SmoothNormals, apex: ApexArg) -> &'static str {
    match (normals, apex) {
        (SmoothNormals::Auto | SmoothNormals::Butterfly, ApexArg::Nearest) => "",
        (SmoothNormals::Auto | SmoothNormals::Butterfly, ApexArg::Normal) => {
            " (hint: the default --apex nearest keeps the apexes low at sharp rims, where the \
             paper's stand several face widths high)"
        }
        (_, ApexArg::Nearest) => {
            " (hint: the default --normals auto takes the Butterfly limit normal at sharp rims, \
             the normal Butterfly refinement agrees with there)"
        }
        (_, ApexArg::Normal) => {
            " (hint: the defaults --normals auto and --apex nearest are made for sharp rims: \
             Butterfly limit normals there, and low apexes)"
        }
    }
}

/// The share of thin faces from which [`thin_faces`] names them as the likely cause: 1 %. The
/// corpus meshes that build have at most 0.1 % (the cow); the A-patch tessellations of the
/// corpus at `--resolution 2 --across 1`, whose hull refinement diverges, have 10–26 %.
const THIN_SHARE: f64 = 0.01;

/// Where hull refinement failed on a mesh with many thin faces (at least [`THIN_SHARE`] of
/// them thinner than [`THIN_FACE_SHAPE`]), says so: a face's tetrahedra inherit its shape, and the
/// Butterfly point of a thin face's long edge moves off the face by about as much as the face
/// is wide, so bisecting it folds the surface there, and the folds' tetrahedra overlap again,
/// more of them each round. Empty otherwise.
pub(crate) fn thin_faces(tri: &TriMesh) -> String {
    let p = tri.positions();
    let thin = tri
        .triangles()
        .iter()
        // A face of zero size has a NaN shape: repair's business, not a thin one.
        .filter(|&&[a, b, c]| {
            triangle_shape(p[a as usize], p[b as usize], p[c as usize]) < THIN_FACE_SHAPE
        })
        .count();
    let faces = tri.triangles().len();
    if faces == 0 || (thin as f64) < THIN_SHARE * faces as f64 {
        return String::new();
    }
    format!(
        " (hint: {thin} of the mesh's {faces} faces ({:.1} %) are thin, narrower than 1/20 of \
         their longest edge: their tetrahedra are as thin, and refining them folds the surface \
         instead of separating the tetrahedra; remesh to well-shaped triangles first)",
        100.0 * thin as f64 / faces as f64
    )
}
