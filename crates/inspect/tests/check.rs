//! The check battery passes on surfaces Theorem 4.1 holds for, and fails — naming the right
//! element — when one coefficient of one tetrahedron's polynomial is perturbed by hand.

use algesurf_apatch::{ApatchSurface, SurfaceOptions};
use algesurf_bb::{BbPoly, Tetrahedron};
use algesurf_hull::Side;
use algesurf_inspect::InspectError;
use algesurf_inspect::check::{
    ApatchView, CheckOptions, CheckReport, Element, InputTopology, Location, PatchSurface,
    Tessellated, check, continuity,
};
use algesurf_mesh::shapes::{icosphere, torus};
use algesurf_mesh::{NormalMethod, TriMesh, vertex_normals};
use glam::DVec3;

fn surface(mesh: &TriMesh) -> ApatchSurface {
    let normals = vertex_normals(mesh, NormalMethod::Loop).unwrap();
    ApatchSurface::new(mesh, &normals, &SurfaceOptions::default()).unwrap()
}

fn report(s: &ApatchSurface) -> CheckReport {
    check(&ApatchView::new(s), &CheckOptions::default()).unwrap()
}

#[test]
fn battery_passes_on_the_icosahedron_sphere_and_icospheres() {
    for level in 0..=2 {
        let s = surface(&icosphere(level));
        let r = report(&s);
        println!("icosphere({level})\n{r}");
        assert!(r.passed(), "icosphere({level}):\n{r}");
        let c1 = r.row("c1_gradient").unwrap();
        assert!(c1.samples > 0, "C1 measured nowhere");
        assert_eq!(r.row("euler_characteristic").unwrap().worst, 0.0);
    }
}

#[test]
fn battery_passes_on_a_torus_with_split_faces() {
    let s = surface(&torus(12, 8, 1.5, 0.6));
    assert!(
        s.faces()
            .iter()
            .any(|f| matches!(f, algesurf_apatch::FaceFunction::Split(_))),
        "the torus's saddle region has nonconvex faces"
    );
    let r = report(&s);
    println!("torus(12, 8)\n{r}");
    assert!(r.passed(), "{r}");
    assert!(
        r.row("closed_manifold").is_some(),
        "a closed input is checked for a closed output"
    );
}

/// Every interior facet gets at least 16 sample points (the "16+ points per facet").
#[test]
fn every_interior_facet_gets_sixteen_points() {
    let s = surface(&torus(12, 8, 1.5, 0.6));
    let c = continuity(&ApatchView::new(&s), CheckOptions::default().facet_level);
    assert!(!c.facets.is_empty());
    assert!(c.min_facet_samples() >= 16, "{}", c.min_facet_samples());
}

/// An open input (a hemisphere-like cap of the torus grid): the output is a manifold with
/// boundary of the input's Euler characteristic, and the battery does not ask it to be closed.
#[test]
fn open_input_is_checked_as_a_manifold_with_boundary() {
    let mesh = algesurf_mesh::shapes::grid(4, 3);
    let normals = vec![DVec3::Z; mesh.vertex_count()];
    let s = ApatchSurface::new(&mesh, &normals, &SurfaceOptions::default()).unwrap();
    let r = report(&s);
    assert!(r.row("manifold").is_some() && r.row("closed_manifold").is_none());
    assert!(r.passed(), "{r}");
}

/// The surface of `inner` with `δ · B_λ(τ(x))` added to piece `piece`: exactly F with the
/// coefficient `b_λ` of that tetrahedron's polynomial raised by δ.
struct Perturbed<'a> {
    inner: ApatchView<'a>,
    piece: usize,
    tet: Tetrahedron,
    bump: BbPoly<f64, 4>,
}

impl<'a> Perturbed<'a> {
    fn new(inner: ApatchView<'a>, piece: usize, lambda: [usize; 4], delta: f64) -> Self {
        let tet = Tetrahedron::new(inner.piece_simplex(piece)).unwrap();
        let mut bump = BbPoly::<f64, 4>::zero(3);
        bump.set(lambda, delta);
        Perturbed {
            inner,
            piece,
            tet,
            bump,
        }
    }
}

impl PatchSurface for Perturbed<'_> {
    fn piece_count(&self) -> usize {
        self.inner.piece_count()
    }
    fn piece_element(&self, piece: usize) -> Element {
        self.inner.piece_element(piece)
    }
    fn piece_simplex(&self, piece: usize) -> [DVec3; 4] {
        self.inner.piece_simplex(piece)
    }
    fn value_gradient(&self, piece: usize, x: DVec3) -> (f64, DVec3) {
        let (f, g) = self.inner.value_gradient(piece, x);
        if piece != self.piece {
            return (f, g);
        }
        (
            f + self.bump.value_at(&self.tet, x),
            g + self.bump.gradient_at(&self.tet, x),
        )
    }
    fn value_gradient_barycentric(&self, piece: usize, tau: [f64; 4]) -> (f64, DVec3) {
        let (f, g) = self.inner.value_gradient_barycentric(piece, tau);
        if piece != self.piece {
            return (f, g);
        }
        // The bump is 1e-6 of F: the rounding of the Cartesian point does not matter for it.
        let x = self.tet.point(tau);
        (
            f + self.bump.eval(tau),
            g + self.bump.gradient_at(&self.tet, x),
        )
    }
    fn interpolation_targets(&self) -> (&[DVec3], &[DVec3]) {
        self.inner.interpolation_targets()
    }
    fn tessellate(&self, resolution: usize) -> Result<Tessellated, InspectError> {
        self.inner.tessellate(resolution)
    }
    fn patch_element(&self, patch: u32) -> Element {
        self.inner.patch_element(patch)
    }
    fn patch_pieces(&self, patch: u32) -> Vec<usize> {
        self.inner.patch_pieces(patch)
    }
    fn parameter_margins(&self) -> Vec<(Element, f64)> {
        self.inner.parameter_margins()
    }
    fn input_topology(&self) -> InputTopology {
        self.inner.input_topology()
    }
}

/// Perturbs `b_{1101}` of `piece` (zero value and gradient at the vertices, so interpolation
/// still holds; nonzero value or gradient on all four facets) and checks that C1 fails on
/// the facets of that piece and nowhere else.
fn assert_c1_failure_at(s: &ApatchSurface, piece: usize) {
    let view = ApatchView::new(s);
    let element = view.piece_element(piece);
    // δ = 1e-6 of the coefficient scale |∇F|·edge (unit normals, unit-size meshes): far above
    // the 1e-8 gradient threshold, far below anything that would change the tessellation.
    let p = Perturbed::new(view, piece, [1, 1, 0, 1], 1e-6);
    let r = check(&p, &CheckOptions::default()).unwrap();
    println!("perturbed {element}:\n{r}");
    assert!(!r.passed(), "the perturbation went unnoticed:\n{r}");
    let row = r.row("c1_gradient").unwrap();
    assert!(!row.pass);
    let Some(Location::Facet(a, b)) = row.at else {
        panic!("C1 failure without a facet: {:?}", row.at);
    };
    assert!(
        a == element || b == element,
        "worst facet between {a} and {b}, not at {element}"
    );
    assert!(
        row.where_text().contains(&element.to_string()),
        "{}",
        row.where_text()
    );
    // Every failing facet is a facet of the perturbed piece, and it has some.
    let c = continuity(&p, CheckOptions::default().facet_level);
    let failing: Vec<_> = c
        .facets
        .iter()
        .filter(|f| f.gradient > 1e-8 || f.value > 1e-10)
        .collect();
    assert!(!failing.is_empty());
    for f in &failing {
        assert!(
            f.pieces.0 == piece || f.pieces.1 == piece,
            "facet of pieces {:?} fails, but only piece {piece} was perturbed",
            f.pieces
        );
    }
    // The vertices are untouched: b_{1101} vanishes to second order there.
    assert!(r.row("interpolation").unwrap().pass);
    assert!(r.row("vertex_normals").unwrap().pass);
}

#[test]
fn c1_failure_is_reported_at_the_perturbed_face_tetrahedron() {
    let s = surface(&icosphere(1));
    let view = ApatchView::new(&s);
    let piece = (0..view.piece_count())
        .rev()
        .find(|&i| matches!(view.piece_element(i), Element::Face(..)))
        .unwrap();
    assert_c1_failure_at(&s, piece);
}

#[test]
fn c1_failure_is_reported_at_the_perturbed_edge_tetrahedron() {
    let s = surface(&icosphere(1));
    let view = ApatchView::new(&s);
    let piece = (0..view.piece_count())
        .find(|&i| {
            matches!(
                view.piece_element(i),
                Element::Edge(_, Some(Side::Positive))
            )
        })
        .unwrap();
    assert_c1_failure_at(&s, piece);
}

#[test]
fn c1_failure_is_reported_at_the_perturbed_split_face_tetrahedron() {
    let s = surface(&torus(12, 8, 1.5, 0.6));
    let split = s
        .faces()
        .iter()
        .position(|f| matches!(f, algesurf_apatch::FaceFunction::Split(_)))
        .unwrap();
    let view = ApatchView::new(&s);
    let piece = (0..view.piece_count())
        .find(|&i| view.piece_element(i) == Element::SplitFace(split, Side::Negative, 1))
        .unwrap();
    assert_c1_failure_at(&s, piece);
}

#[test]
fn elements_are_named_as_in_the_paper() {
    let facet = Location::Facet(
        Element::Face(3, Some(Side::Positive)),
        Element::Edge(7, Some(Side::Negative)),
    );
    assert_eq!(facet.to_string(), "facet between face 3 (+) and edge 7 (−)");
    assert_eq!(Element::Vertex(5).to_string(), "vertex 5");
    assert_eq!(Element::Face(12, None).to_string(), "face 12");
    assert_eq!(
        Element::SplitFace(5, Side::Negative, 2).to_string(),
        "face 5 (−) sub-tetrahedron 2"
    );
}

#[test]
fn report_json_has_one_row_per_property() {
    let s = surface(&icosphere(0));
    let r = report(&s);
    let j = r.to_json();
    assert_eq!(j["passed"], true);
    let rows = j["rows"].as_array().unwrap();
    assert_eq!(rows.len(), r.rows.len());
    for row in rows {
        for field in ["property", "worst", "where", "threshold", "pass"] {
            assert!(row.get(field).is_some(), "{field} missing in {row}");
        }
    }
}

#[test]
fn zero_resolution_is_an_invalid_option() {
    let s = surface(&icosphere(0));
    let options = CheckOptions {
        resolution: 0,
        ..CheckOptions::default()
    };
    assert!(matches!(
        check(&ApatchView::new(&s), &options),
        Err(InspectError::InvalidOption(_))
    ));
}

/// Coincident input vertices (kept apart by repair) are not a crack, nor are coincident
/// vertices of different components; a tessellation vertex repeating a position in its own
/// component is, and so is an edge used by one triangle of a closed input.
#[test]
fn duplicates_and_open_edges_of_the_tessellation_are_counted() {
    use algesurf_inspect::check::topology;
    let p = [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z];
    // A tetrahedron's surface; vertices 0 and 4 coincide in the input.
    let mut t = Tessellated {
        positions: vec![p[0], p[1], p[2], p[3], p[0]],
        triangles: vec![[0, 2, 1], [0, 1, 3], [1, 2, 3], [2, 0, 3]],
        triangle_patch: vec![0; 4],
        interpolated_vertices: 5,
        ..Tessellated::default()
    };
    let closed = InputTopology {
        closed: true,
        euler_characteristic: 2,
    };
    let m = topology(&t, closed);
    assert_eq!((m.bad_edges, m.duplicate_positions), (0, 0));
    assert_eq!(m.euler_characteristic, 2);
    // The same repeated position made by the tessellation is a duplicate.
    t.interpolated_vertices = 4;
    let m = topology(&t, closed);
    assert_eq!((m.duplicate_positions, m.first_duplicate), (1, Some(4)));
    // A tessellation vertex on a second sheet at the same place, another component (the
    // input's detached non-manifold edge with flat patches on both sheets), is no crack; the
    // same vertex joined to the first sheet is.
    let mut sheets = t.clone();
    sheets.positions.extend([p[1], p[2], p[0] + p[1] + p[2]]);
    sheets.triangles.push([5, 6, 7]);
    sheets.triangle_patch.push(1);
    let m = topology(&sheets, closed);
    assert_eq!((m.duplicate_positions, m.first_duplicate), (1, Some(4)));
    sheets.triangles.push([5, 7, 3]);
    sheets.triangle_patch.push(1);
    let m = topology(&sheets, closed);
    assert_eq!((m.duplicate_positions, m.first_duplicate), (3, Some(4)));
    // One triangle fewer: three open edges on a closed input.
    t.triangles.pop();
    let m = topology(&t, closed);
    assert_eq!(m.bad_edges, 3);
    assert_eq!(
        topology(
            &t,
            InputTopology {
                closed: false,
                euler_characteristic: 1
            }
        )
        .bad_edges,
        0,
        "an open input may have boundary edges"
    );
}

/// A view of some faces and edges measures exactly the facets among their pieces: with every
/// owner it is the whole surface's measure, with one face and its edges a nonempty part of it.
#[test]
fn a_view_of_some_owners_measures_the_facets_among_them() {
    use algesurf_apatch::Owner;
    let s = surface(&torus(12, 8, 1.5, 0.6));
    let (nf, ne) = (s.faces().len(), s.edges().len());
    let all = (0..nf).map(Owner::Face).chain((0..ne).map(Owner::Edge));
    let whole = continuity(&ApatchView::new(&s), 3);
    let viewed = continuity(&ApatchView::of_owners(&s, all), 3);
    assert_eq!(whole.facets, viewed.facets);
    // Face 0 and the edges around it.
    let edges = s
        .hull()
        .edges()
        .iter()
        .enumerate()
        .filter(|(_, e)| e.face_k == 0 || e.face_l == Some(0))
        .map(|(e, _)| Owner::Edge(e));
    let view = ApatchView::of_owners(&s, std::iter::once(Owner::Face(0)).chain(edges));
    let part = continuity(&view, 3);
    assert!(!part.facets.is_empty() && part.facets.len() < whole.facets.len());
    assert!(part.value.value <= whole.value.value && part.gradient.value <= whole.gradient.value);
}

/// A hand-made surface of two pieces (the plane `F = z` on two tetrahedra over one triangle,
/// one above and one below), whose interpolation targets and tessellation a test sets, with
/// `patch_pieces` answering `stray` for patch 7.
struct Handmade {
    points: Vec<DVec3>,
    normals: Vec<DVec3>,
    t: Tessellated,
    stray: usize,
}

impl Handmade {
    fn new(t: Tessellated) -> Handmade {
        Handmade {
            points: vec![DVec3::ZERO, DVec3::X, DVec3::Y],
            normals: vec![DVec3::Z; 3],
            t,
            stray: 0,
        }
    }
}

impl PatchSurface for Handmade {
    fn piece_count(&self) -> usize {
        2
    }
    fn piece_element(&self, piece: usize) -> Element {
        Element::Face(0, Some([Side::Positive, Side::Negative][piece]))
    }
    fn piece_simplex(&self, piece: usize) -> [DVec3; 4] {
        let apex = DVec3::new(0.3, 0.3, [1.0, -1.0][piece]);
        [DVec3::ZERO, DVec3::X, DVec3::Y, apex]
    }
    fn value_gradient(&self, _: usize, x: DVec3) -> (f64, DVec3) {
        (x.z, DVec3::Z)
    }
    fn interpolation_targets(&self) -> (&[DVec3], &[DVec3]) {
        (&self.points, &self.normals)
    }
    fn tessellate(&self, _: usize) -> Result<Tessellated, InspectError> {
        Ok(self.t.clone())
    }
    fn patch_element(&self, patch: u32) -> Element {
        Element::Face(patch as usize, None)
    }
    fn patch_pieces(&self, patch: u32) -> Vec<usize> {
        if patch == 7 {
            vec![self.stray]
        } else {
            vec![patch as usize % 2]
        }
    }
    fn parameter_margins(&self) -> Vec<(Element, f64)> {
        Vec::new()
    }
    fn input_topology(&self) -> InputTopology {
        InputTopology {
            closed: false,
            euler_characteristic: 1,
        }
    }
}

/// `PatchSurface` is implemented by users; where an implementation contradicts itself, the
/// battery says what is wrong instead of panicking on an index (each case below panicked).
#[test]
fn a_surface_that_contradicts_itself_is_an_error_not_a_panic() {
    let fan = Tessellated {
        positions: vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::new(0.2, 0.2, 0.0)],
        triangles: vec![[0, 1, 3], [1, 2, 3], [2, 0, 3]],
        triangle_patch: vec![0, 1, 7],
        interpolated_vertices: 3,
        ..Tessellated::default()
    };
    let measure = |s: &Handmade| match check(s, &CheckOptions::default()) {
        Err(InspectError::Measurement(m)) => m,
        other => panic!("expected a measurement error, got {other:?}"),
    };
    let mut s = Handmade::new(fan.clone());
    assert!(check(&s, &CheckOptions::default()).is_ok());
    s.normals.pop();
    assert!(measure(&s).contains("3 points but 2 normals"));
    let mut s = Handmade::new(fan.clone());
    s.stray = 55;
    assert!(measure(&s).contains("patch 7 lists piece 55"));
    let mut t = fan;
    t.triangles[1][2] = 9;
    assert!(measure(&Handmade::new(t)).contains("triangle 1 names vertex 9"));
}

/// The battery on random tessellations of the hand-made surface: triangles naming any
/// vertex, repeated corners, patch ids missing or unknown, NaN positions, any count of
/// interpolated vertices. It may report anything, or refuse, but never panic.
#[test]
fn the_battery_never_panics_on_a_random_tessellation() {
    let mut rng = algesurf_mesh::test_rng::Lcg(29);
    let mut next = |n: usize| (rng.next() * n as f64) as usize;
    let values = [0.0, 1.0, 0.2, 0.5, f64::NAN, -1.0];
    for case in 0..1000 {
        let nv = next(9);
        let positions = (0..nv)
            .map(|_| DVec3::new(values[next(6)], values[next(6)], values[next(3)]))
            .collect();
        let triangles: Vec<[u32; 3]> = (0..next(8))
            .map(|_| [(); 3].map(|_| next(nv + 2) as u32))
            .collect();
        let t = Tessellated {
            positions,
            triangle_patch: (0..next(triangles.len() + 2))
                .map(|_| next(9) as u32)
                .collect(),
            triangles,
            interpolated_vertices: next(nv + 3),
            missed_rays: vec![(next(4) as u32, DVec3::ZERO); next(2)],
            ..Tessellated::default()
        };
        let s = Handmade::new(t);
        let run = std::panic::catch_unwind(|| {
            let _ = check(&s, &CheckOptions::default()).map(|r| r.to_string());
        });
        assert!(run.is_ok(), "case {case}: {:?}", s.t);
    }
}
