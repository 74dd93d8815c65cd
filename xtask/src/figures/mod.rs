//! `cargo xtask figures`: regenerates the figures of Xu–Huang–Bajaj 2001 that algesurf's
//! capabilities cover, from our own code, into `docs/figures/*.png` (captions in
//! docs/GALLERY.md). With `ALGESURF_CORPUS` set, the real-mesh figures use the teapot and
//! spot from the corpus; otherwise built-in meshes.
//!
//! Every image is rendered by `algesurf_inspect::render` with fixed options, so the bytes are
//! the same on every run.

mod contour;

use algesurf::apatch::examples::WorkedExample;
use algesurf::apatch::{ApatchSurface, FaceFunction, SurfaceOptions, Tessellation};
use algesurf::bb::roots::shooting_root;
use algesurf::hull::Side;
use algesurf::inspect::render::{
    Background, Camera, Image, LineSet, Mode, Projection, RenderMesh, RenderOptions, View,
    render_scene,
};
use algesurf::mesh::{NormalMethod, RepairOptions, TriMesh, repair, shapes, vertex_normals};
use glam::DVec3;
use std::path::{Path, PathBuf};

type Result<T> = std::result::Result<T, Box<dyn std::error::Error>>;

/// A light blue-grey: the isophote stripes (near white and near black) both stand out from it.
const PAPER: Background = Background::Solid([0.80, 0.84, 0.90]);

fn options(mode: Mode, size: (u32, u32), views: Vec<View>) -> RenderOptions {
    RenderOptions {
        mode,
        views,
        size,
        background: PAPER,
        samples: 3,
        ..RenderOptions::default()
    }
}

fn write(
    dir: &Path,
    name: &str,
    meshes: &[&RenderMesh],
    lines: &[&LineSet],
    o: &RenderOptions,
) -> Result<()> {
    save(dir, name, &render_scene(meshes, lines, o)?)
}

fn surface_mesh(t: &Tessellation) -> RenderMesh {
    let mut m = RenderMesh::from(t);
    m.wire = None;
    m
}

/// A perspective camera looking at the bounding sphere of `points` from direction `from`
/// (z up), far enough that the sphere fills about 80 % of the height.
fn framed(points: &[DVec3], from: DVec3) -> View {
    let (lo, hi) = points.iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    let centre = (lo + hi) * 0.5;
    let radius = (hi - lo).length() * 0.5;
    let fov: f64 = 30.0;
    let distance = radius / (0.95 * (fov.to_radians() / 2.0).sin());
    View::Camera(Camera {
        eye: centre + from.normalize() * distance,
        target: centre,
        up: DVec3::Z,
        projection: Projection::Perspective { fov_y_degrees: fov },
    })
}

/// The direction the §6 figures look from: in front of the edge `p1 p2`, above.
const TWO_TRIANGLE_VIEW: DVec3 = DVec3::new(0.3, -0.6, 1.5);

/// Images side by side (same height).
fn side_by_side(images: &[Image]) -> Image {
    let height = images[0].height;
    let width: u32 = images.iter().map(|i| i.width).sum();
    let mut rgba = Vec::with_capacity((4 * width * height) as usize);
    for y in 0..height as usize {
        for im in images {
            let row = 4 * im.width as usize;
            rgba.extend_from_slice(&im.rgba[y * row..(y + 1) * row]);
        }
    }
    Image {
        width,
        height,
        rgba,
        legend_range: None,
    }
}

fn save(dir: &Path, name: &str, image: &Image) -> Result<()> {
    let path = dir.join(name);
    image.write_png(&path)?;
    let size = std::fs::metadata(&path)?.len();
    println!(
        "{:<40} {}×{} {:>4} KB",
        path.display(),
        image.width,
        image.height,
        size / 1024
    );
    if size > 300 * 1024 {
        return Err(format!(
            "{name} is {} KB, over the gallery's 300 KB limit",
            size / 1024
        )
        .into());
    }
    Ok(())
}

/// Runs the command: writes every figure into `docs/figures`.
pub fn run(root: &Path) -> Result<()> {
    let dir = root.join("docs").join("figures");
    std::fs::create_dir_all(&dir)?;
    fig2_surface_family(&dir)?;
    fig3_multiple_sheets(&dir)?;
    worked_examples(&dir)?;
    icosahedron_and_sphere(&dir)?;
    real_meshes(&dir)?;
    Ok(())
}

/// Fig. 2: the surface over the two triangles of Fig. 6 as both faces' free parameters go from
/// near the single-sheet bound (the surface lifted towards the apex) to far above it (pressed
/// onto the triangles). Surfaces side by side, shifted along x.
fn fig2_surface_family(dir: &Path) -> Result<()> {
    let (mesh, normals) = WorkedExample::Fig6.mesh_and_normals();
    let base = ApatchSurface::new(&mesh, &normals, &SurfaceOptions::default())?;
    // Multipliers of the default's distance from the bound.
    let steps = [0.1, 0.5, 1.0, 3.0, 20.0];
    let wire = LineSet::edges_of(&mesh);
    // Along the common edge p1 p2, a little from above: the profile shows the lift.
    let view = framed(mesh.positions(), DVec3::new(1.0, -0.25, 0.3));
    let mut cells = Vec::new();
    for &m in &steps {
        let mut s = base.clone();
        let values: Vec<(usize, Side, f64)> = base
            .free_parameters()
            .iter()
            .map(|p| (p.face, p.side, p.bound + (p.value - p.bound) * m))
            .collect();
        s.set_free_parameters(&values)?;
        let t = s.tessellate(24, 12)?;
        let o = options(Mode::Shaded, (300, 260), vec![view]);
        cells.push(render_scene(&[&surface_mesh(&t)], &[&wire], &o)?);
    }
    save(dir, "fig02-surface-family.png", &side_by_side(&cells))
}

/// Lattice level of the contours: 40 steps per tetrahedron edge.
const LATTICE: usize = 40;

/// Whether a contour triangle lies on the sheet the A-patch selects (§4.2, (4.6)): the ray
/// from the base point below its centroid towards the apex is one this side shoots
/// (`sign·F(q) ≤ 0`), and its smallest root (§4.4) is within one lattice step of the
/// centroid's apex coordinate (the contour's own error is far smaller than a step).
fn on_selected_sheet(
    tri: [DVec3; 3],
    tet: &algesurf::bb::Tetrahedron,
    poly: &algesurf::bb::BbPoly<f64, 4>,
    sign: f64,
) -> bool {
    let c = (tri[0] + tri[1] + tri[2]) / 3.0;
    let tau = tet.barycentric(c);
    let base = 1.0 - tau[3];
    if base <= 1e-9 {
        return false;
    }
    let q = [tau[0] / base, tau[1] / base, tau[2] / base, 0.0];
    let b = poly.restrict_to_segment(q, [0.0, 0.0, 0.0, 1.0]);
    let b = b.coeffs();
    let coeffs = [b[0], b[1], b[2], b[3]].map(|x| sign * x);
    if coeffs[0] > 0.0 {
        return false;
    }
    matches!(shooting_root(coeffs), Ok(Some(r)) if (r.t - tau[3]).abs() < 1.0 / LATTICE as f64)
}

/// Fig. 3: the data of Fig. 9 with the free parameters just above their bounds: the whole
/// zero set of F in the face tetrahedra: the sheet the shooting rays select (red: the
/// A-patches, face and edge) and the other sheets of F = 0 in the face tetrahedra (grey).
fn fig3_multiple_sheets(dir: &Path) -> Result<()> {
    let (mesh, normals) = WorkedExample::Fig9.mesh_and_normals();
    let mut s = ApatchSurface::new(&mesh, &normals, &SurfaceOptions::default())?;
    let values: Vec<(usize, Side, f64)> = s
        .free_parameters()
        .iter()
        .map(|p| (p.face, p.side, p.bound + (p.value - p.bound) * 0.02))
        .collect();
    s.set_free_parameters(&values)?;
    let mut all = RenderMesh {
        colour: Some([0.78, 0.78, 0.8]),
        ..RenderMesh::default()
    };
    let mut normals_out = Vec::new();
    for ff in s.faces() {
        let FaceFunction::Split(split) = ff else {
            continue;
        };
        for (side, sign) in split.sides.iter().zip([1.0, -1.0]) {
            for a in 0..3 {
                let tet = &side.tets[a];
                let poly = &side.polys[a];
                let corners = [0, 1, 2, 3].map(|i| tet.vertex(i));
                let (p, t) =
                    contour::zero_set_in_tetrahedron(corners, |x| poly.value_at(tet, x), LATTICE);
                let offset = all.positions.len() as u32;
                // The selected sheet is drawn from the tessellation (it includes the edge
                // patches, whose tetrahedra are not contoured here); the contour keeps the
                // other sheets.
                for tri in &t {
                    if !on_selected_sheet(tri.map(|i| p[i as usize]), tet, poly, sign) {
                        all.triangles.push(tri.map(|i| i + offset));
                    }
                }
                normals_out.extend(p.iter().map(|x| poly.gradient_at(tet, *x)));
                all.positions.extend(p);
            }
        }
    }
    all.normals = Some(normals_out);
    let wire = LineSet::edges_of(&mesh);
    let mut sheet = surface_mesh(&s.tessellate(32, 16)?);
    sheet.colour = Some([0.9, 0.3, 0.22]);
    let view = framed(mesh.positions(), TWO_TRIANGLE_VIEW);
    write(
        dir,
        "fig03-multiple-sheets.png",
        &[&sheet, &all],
        &[&wire],
        &options(Mode::Shaded, (720, 540), vec![view]),
    )
}

/// Figs. 6, 7, 9 and 10: the four join configurations of §6, isophotes over the A-patches with
/// the two input triangles drawn as lines.
fn worked_examples(dir: &Path) -> Result<()> {
    for ex in WorkedExample::ALL {
        let (mesh, normals) = ex.mesh_and_normals();
        let s = ApatchSurface::new(&mesh, &normals, &SurfaceOptions::default())?;
        let t = s.tessellate(32, 16)?;
        let rm = surface_mesh(&t);
        let wire = LineSet::edges_of(&mesh);
        let number = ex.name().trim_start_matches("Fig. ");
        let name = format!("fig{number:0>2}-{}.png", slug(ex));
        write(
            dir,
            &name,
            &[&rm],
            &[&wire],
            &options(
                Mode::Patches,
                (640, 480),
                vec![framed(mesh.positions(), TWO_TRIANGLE_VIEW)],
            ),
        )?;
    }
    Ok(())
}

fn slug(ex: WorkedExample) -> &'static str {
    match ex {
        WorkedExample::Fig6 => "convex-convex",
        WorkedExample::Fig7 => "convex-nonconvex",
        WorkedExample::Fig9 => "nonconvex-nonconvex",
        WorkedExample::Fig10 => "nonconvex-planar",
    }
}

/// Figs. 12–13: the icosahedron and the sphere it becomes (its vertices and unit sphere
/// normals; the default free parameters reproduce the quadric), isophotes.
fn icosahedron_and_sphere(dir: &Path) -> Result<()> {
    let ico = shapes::icosphere(0);
    let normals: Vec<DVec3> = ico.positions().iter().map(|p| p.normalize()).collect();
    // Faceted: every triangle with its own corners and its face normal.
    let mut flat = RenderMesh {
        wire: Some(LineSet::edges_of(&ico)),
        ..RenderMesh::default()
    };
    let mut face_normals = Vec::new();
    for (f, t) in ico.triangles().iter().enumerate() {
        let n = ico.face_normal(f);
        for &v in t {
            flat.positions.push(ico.positions()[v as usize]);
            face_normals.push(n);
        }
        let k = 3 * f as u32;
        flat.triangles.push([k, k + 1, k + 2]);
    }
    flat.normals = Some(face_normals);
    let o = options(Mode::Isophotes, (480, 480), vec![View::Iso]);
    let faceted = RenderOptions {
        mode: Mode::Shaded,
        wire: true,
        ..o.clone()
    };
    write(dir, "fig12-icosahedron.png", &[&flat], &[], &faceted)?;
    let s = ApatchSurface::new(&ico, &normals, &SurfaceOptions::default())?;
    let t = s.tessellate(24, 12)?;
    let mut rm = surface_mesh(&t);
    rm.wire = Some(LineSet::edges_of(&ico));
    write(
        dir,
        "fig13-sphere.png",
        &[&rm],
        &[],
        &RenderOptions { wire: true, ..o },
    )
}

/// Figs. 14–17: a real mesh with face patches and edge patches shaded differently (warm face
/// patches, cool edge patches, grey planar ones), and the same surface in isophotes.
fn real_meshes(dir: &Path) -> Result<()> {
    let corpus = std::env::var_os("ALGESURF_CORPUS")
        .filter(|v| !v.is_empty())
        .map(PathBuf::from);
    let inputs: Vec<(String, TriMesh)> = match &corpus {
        Some(c) => ["teapot.obj", "spot.obj"]
            .iter()
            .map(|n| -> Result<(String, TriMesh)> {
                let poly = algesurf::io::read(c.join(n))?;
                let repaired = repair(&poly, &RepairOptions::default())?.mesh;
                Ok((
                    n.trim_end_matches(".obj").to_string(),
                    TriMesh::from_polygon_mesh(&repaired)?,
                ))
            })
            .collect::<Result<_>>()?,
        None => vec![("torus".to_string(), shapes::torus(16, 8, 1.0, 0.4))],
    };
    for (name, mesh) in inputs {
        let normals = vertex_normals(&mesh, NormalMethod::Loop)?;
        let s = ApatchSurface::new(&mesh, &normals, &SurfaceOptions::default())?;
        let t = s.tessellate(6, 3)?;
        let rm = surface_mesh(&t);
        let views = vec![View::Iso];
        write(
            dir,
            &format!("fig14-{name}-patches.png"),
            &[&rm],
            &[],
            &options(Mode::Patches, (640, 480), views.clone()),
        )?;
        write(
            dir,
            &format!("fig15-{name}-isophotes.png"),
            &[&rm],
            &[],
            &options(Mode::Isophotes, (640, 480), views),
        )?;
    }
    Ok(())
}
