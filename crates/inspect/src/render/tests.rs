//! Claims about the renderer, checked on shapes whose images are known in closed form.

use super::*;
use algesurf_apatch::{ApatchSurface, PatchKind, SurfaceOptions};
use algesurf_mesh::{NormalMethod, TriMesh, shapes, vertex_normals};
use std::collections::{BTreeMap, BTreeSet};

/// Pixels per unit of the orthographic head-on camera below: `SIZE / 2 / HALF`.
const SIZE: u32 = 200;
const HALF: f64 = 1.25;
const SCALE: f64 = SIZE as f64 / 2.0 / HALF;

/// The unit sphere (level-5 icosphere) with its exact normals.
fn sphere() -> (TriMesh, RenderMesh) {
    let s = shapes::icosphere(5);
    let mut m = RenderMesh::from(&s);
    m.normals = Some(s.positions().iter().map(|p| p.normalize()).collect());
    (s, m)
}

fn head_on(mode: Mode) -> RenderOptions {
    RenderOptions {
        mode,
        size: (SIZE, SIZE),
        views: vec![View::Camera(Camera {
            eye: DVec3::new(0.0, 0.0, 5.0),
            target: DVec3::ZERO,
            up: DVec3::Y,
            projection: Projection::Orthographic { half_height: HALF },
        })],
        light: DVec3::Z,
        ..RenderOptions::default()
    }
}

/// Distance of pixel (x, y)'s centre from the image centre, in units of the sphere radius.
fn rho(x: u32, y: u32) -> f64 {
    let c = SIZE as f64 / 2.0;
    ((x as f64 + 0.5 - c).hypot(y as f64 + 0.5 - c)) / SCALE
}

#[test]
fn sphere_silhouette_is_where_the_projection_says() {
    let (s, m) = sphere();
    let img = render(&m, &head_on(Mode::Shaded)).unwrap();
    // The polyhedron lies between its faces' least distance from the centre (1 − chord
    // error) and 1, so its silhouette lies between those circles. A pixel is fully covered
    // when its whole footprint (half a diagonal, 0.71 px) is inside the inner circle, and
    // empty when outside the outer circle.
    let inner = s
        .triangles()
        .iter()
        .map(|t| {
            let p = t.map(|v| s.positions()[v as usize]);
            (p[1] - p[0]).cross(p[2] - p[0]).normalize().dot(p[0]).abs()
        })
        .fold(1.0, f64::min);
    assert!(inner > 0.99 && inner < 1.0, "chord error {}", 1.0 - inner);
    let foot = 0.71 / SCALE;
    let (mut inside, mut outside) = (0, 0);
    for y in 0..SIZE {
        for x in 0..SIZE {
            let r = rho(x, y);
            let a = img.pixel(x, y)[3];
            if r < inner - foot {
                assert_eq!(a, 255, "pixel ({x}, {y}) at ρ = {r} should be covered");
                inside += 1;
            } else if r > 1.0 + foot {
                assert_eq!(a, 0, "pixel ({x}, {y}) at ρ = {r} should be background");
                outside += 1;
            }
        }
    }
    assert!(inside > 19_000 && outside > 9_000, "{inside} {outside}");
}

#[test]
fn isophote_stripes_fall_on_the_predicted_circles() {
    let (_, m) = sphere();
    let o = head_on(Mode::Isophotes);
    let k = f64::from(o.stripes);
    let img = render(&m, &o).unwrap();
    // Orthographic view along −z with L = +z: at image radius ρ the unit sphere has
    // n·L = √(1 − ρ²), so the band is ⌊k √(1 − ρ²)⌋ and its parity picks light or dark.
    // Pixels more than 1.5 px (the footprint plus the interpolated normals' error, far below
    // a pixel on a level-5 sphere) away from every boundary circle ρ_j = √(1 − (j/k)²) must be
    // exactly light or dark as predicted.
    let bounds: Vec<f64> = (0..=k as usize)
        .map(|j| (1.0 - (j as f64 / k).powi(2)).sqrt())
        .collect();
    let margin = 1.5 / SCALE;
    let mut checked = 0;
    for y in 0..SIZE {
        for x in 0..SIZE {
            let r = rho(x, y);
            if r > 0.98 || bounds.iter().any(|b| (r - b).abs() < margin) {
                continue;
            }
            let band = (k * (1.0 - r * r).sqrt()).floor() as i64;
            let want = if band % 2 == 0 {
                to_byte(0.95)
            } else {
                to_byte(0.12)
            };
            assert_eq!(
                img.pixel(x, y),
                [want, want, want, 255],
                "({x}, {y}) ρ = {r}"
            );
            checked += 1;
        }
    }
    assert!(checked > 10_000, "{checked}");
}

fn to_byte(v: f32) -> u8 {
    (v * 255.0 + 0.5) as u8
}

/// The smoothed icosahedron (the unit sphere: 20 face patches, 30 edge patches).
fn smoothed_icosahedron() -> algesurf_apatch::Tessellation {
    let ico = shapes::icosphere(0);
    let normals = vertex_normals(&ico, NormalMethod::Loop).unwrap();
    let surface = ApatchSurface::new(&ico, &normals, &SurfaceOptions::default()).unwrap();
    surface.tessellate(8, 8).unwrap()
}

#[test]
fn patches_mode_shows_one_hue_family_per_patch_kind() {
    let t = smoothed_icosahedron();
    let kinds: BTreeSet<u8> = t.triangle_kind.iter().map(|&k| kind_index(k)).collect();
    let mut palette = BTreeMap::new();
    for (&id, &k) in t.triangle_patch.iter().zip(&t.triangle_kind) {
        palette.insert(rgb_bytes(patch_colour(k, id)), kind_index(k));
    }
    let o = RenderOptions {
        mode: Mode::Patches,
        flat: true,
        size: (160, 160),
        views: vec![View::Front, View::Iso],
        ..RenderOptions::default()
    };
    let img = render(&RenderMesh::from(&t), &o).unwrap();
    // A pixel whose 3×3 neighbourhood is one opaque colour lies inside one patch: with flat
    // colours that colour must be exactly a palette entry of a patch present.
    let mut seen_colours = BTreeSet::new();
    let mut seen_kinds = BTreeSet::new();
    for y in 1..img.height - 1 {
        for x in 1..img.width - 1 {
            let c = img.pixel(x, y);
            let uniform = (0..9).all(|i| img.pixel(x + i % 3 - 1, y + i / 3 - 1) == c);
            if !uniform || c[3] != 255 {
                continue;
            }
            let rgb = [c[0], c[1], c[2]];
            let kind = palette
                .get(&rgb)
                .unwrap_or_else(|| panic!("({x}, {y}) colour {rgb:?} is no patch's colour"));
            seen_colours.insert(rgb);
            seen_kinds.insert(*kind);
        }
    }
    assert_eq!(
        seen_kinds, kinds,
        "hue families seen vs patch kinds present"
    );
    assert_eq!(
        kinds.len(),
        2,
        "the smoothed icosahedron has face and edge patches"
    );
    // Neighbouring patches are told apart by lightness: many distinct colours.
    assert!(seen_colours.len() > 10, "{} colours", seen_colours.len());
    // And the families really are hue families.
    for (rgb, &k) in &palette {
        let fam = hue_family(*rgb);
        assert_eq!(fam, k, "{rgb:?}");
    }
}

fn kind_index(k: PatchKind) -> u8 {
    match k {
        PatchKind::Face => 0,
        PatchKind::Edge => 1,
        PatchKind::Planar => 2,
    }
}

fn rgb_bytes(c: Rgb) -> [u8; 3] {
    c.map(|v| (v.clamp(0.0, 1.0) * 255.0 + 0.5) as u8)
}

/// Warm (red > blue) = 0, cool (blue > red) = 1, grey = 2.
fn hue_family(c: [u8; 3]) -> u8 {
    let (r, b) = (i32::from(c[0]), i32::from(c[2]));
    if (r - b).abs() <= 2 && (i32::from(c[1]) - r).abs() <= 2 {
        2
    } else if r > b {
        0
    } else {
        1
    }
}

fn every_mode_options() -> Vec<RenderOptions> {
    [
        Mode::Shaded,
        Mode::Isophotes,
        Mode::Zebra,
        Mode::Patches,
        Mode::Curvature,
    ]
    .into_iter()
    .map(|mode| RenderOptions {
        mode,
        size: (96, 80),
        views: vec![View::Front, View::Side, View::Top, View::Iso],
        wire: mode == Mode::Shaded,
        ..RenderOptions::default()
    })
    .collect()
}

#[test]
fn same_input_gives_the_same_bytes_whatever_the_thread_count() {
    let torus = RenderMesh::from(&shapes::torus(48, 24, 1.5, 0.6));
    for o in every_mode_options() {
        let a = render(&torus, &o).unwrap().encode_png().unwrap();
        let b = render(&torus, &o).unwrap().encode_png().unwrap();
        assert_eq!(a, b, "{:?}: twice", o.mode);
        for threads in [1, 2, 3] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let c = pool.install(|| render(&torus, &o).unwrap().encode_png().unwrap());
            assert_eq!(a, c, "{:?}: {threads} threads", o.mode);
        }
    }
}

#[test]
fn a_grid_of_views_places_each_view_in_its_cell() {
    let (_, m) = sphere();
    let mut o = head_on(Mode::Shaded);
    let single = render(&m, &o).unwrap();
    o.views = vec![o.views[0]; 3];
    let grid = render(&m, &o).unwrap();
    assert_eq!((grid.width, grid.height), (2 * SIZE, 2 * SIZE));
    for (cx, cy) in [(0, 0), (1, 0), (0, 1)] {
        for (x, y) in [(100, 100), (3, 3), (150, 60)] {
            assert_eq!(grid.pixel(cx * SIZE + x, cy * SIZE + y), single.pixel(x, y));
        }
    }
    assert_eq!(
        grid.pixel(SIZE + 100, SIZE + 100),
        [0; 4],
        "the fourth cell is empty"
    );
}

#[test]
fn curvature_legend_labels_the_range_of_a_sphere() {
    let (_, m) = sphere();
    let img = render(&m, &head_on(Mode::Curvature)).unwrap();
    let [lo, hi] = img.legend_range.unwrap();
    // H = 1 everywhere on the unit sphere (to the cotangent formula's accuracy); a constant
    // field is shown over ±5 % around it.
    assert!(lo < 1.0 && hi > 1.0 && lo > 0.9 && hi < 1.1, "[{lo}, {hi}]");
    assert!(img.width > SIZE, "the legend strip is added");
}

#[test]
fn wire_is_hidden_behind_the_surface_and_drawn_in_front() {
    // A unit square at z = 0 and a wire segment crossing it at z = +0.5 (in front) and
    // another at z = −0.5 (behind), seen head-on.
    let square = RenderMesh {
        positions: vec![
            DVec3::new(-1.0, -1.0, 0.0),
            DVec3::new(1.0, -1.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(-1.0, 1.0, 0.0),
        ],
        triangles: vec![[0, 1, 2], [0, 2, 3]],
        ..RenderMesh::default()
    };
    let lines = LineSet {
        positions: vec![
            DVec3::new(-0.5, 0.5, 0.5),
            DVec3::new(0.5, 0.5, 0.5),
            DVec3::new(-0.5, -0.5, -0.5),
            DVec3::new(0.5, -0.5, -0.5),
        ],
        edges: vec![[0, 1], [2, 3]],
    };
    let mut o = head_on(Mode::Shaded);
    o.flat = true;
    o.wire_width = 3.0;
    let img = render_scene(&[&square], &[&lines], &o).unwrap();
    let wire = rgb_bytes(o.wire_colour);
    let at = |x: f64, y: f64| {
        let p = img.pixel((100.0 + x * SCALE) as u32, (100.0 - y * SCALE) as u32);
        [p[0], p[1], p[2]]
    };
    assert_eq!(at(0.0, 0.5), wire, "the front segment is drawn");
    assert_ne!(at(0.0, -0.5), wire, "the back segment is hidden");
}

#[test]
fn bad_options_are_errors_not_panics() {
    let (_, m) = sphere();
    let base = RenderOptions {
        size: (8, 8),
        ..RenderOptions::default()
    };
    let cases = [
        RenderOptions {
            size: (0, 8),
            ..base.clone()
        },
        RenderOptions {
            samples: 9,
            ..base.clone()
        },
        RenderOptions {
            views: vec![],
            ..base.clone()
        },
        RenderOptions {
            light: DVec3::ZERO,
            ..base.clone()
        },
        RenderOptions {
            views: vec![View::Camera(Camera {
                eye: DVec3::ZERO,
                target: DVec3::ZERO,
                up: DVec3::Y,
                projection: Projection::Perspective {
                    fov_y_degrees: 30.0,
                },
            })],
            ..base.clone()
        },
    ];
    for o in cases {
        assert!(
            matches!(render(&m, &o), Err(InspectError::InvalidOption(_))),
            "{o:?}"
        );
    }
    // An eye so far that its distance overflows is named as such (it was reported as an up
    // parallel to the view).
    let far = RenderOptions {
        views: vec![View::Camera(Camera {
            eye: DVec3::new(1e308, 0.0, 0.0),
            target: DVec3::ZERO,
            up: DVec3::Y,
            projection: Projection::Perspective {
                fov_y_degrees: 30.0,
            },
        })],
        ..base.clone()
    };
    let e = render(&m, &far).unwrap_err().to_string();
    assert!(e.contains("too far apart"), "{e}");
    // A bad field of view is named as such (a NaN one was reported as a bad eye: the preset
    // views place the eye by it).
    for fov in [f64::NAN, 0.0, -5.0, 180.0, f64::INFINITY] {
        let o = RenderOptions {
            fov_y_degrees: fov,
            ..base.clone()
        };
        let e = render(&m, &o).unwrap_err().to_string();
        assert!(e.contains("field of view"), "{fov}: {e}");
    }
    let mut broken = m.clone();
    broken.triangles.push([0, 1, 1_000_000]);
    assert!(render(&broken, &base).is_err());
    let mut no_ids = m.clone();
    no_ids.patch_ids = None;
    let patches = RenderOptions {
        mode: Mode::Patches,
        ..base
    };
    assert!(render(&no_ids, &patches).is_err());
    assert!(parse_size("12x").is_err() && parse_size("0x5").is_err());
    assert_eq!(parse_size("640x480").unwrap(), (640, 480));
    assert!(Mode::parse("glossy").is_err() && View::parse("back").is_err());
}

#[test]
fn highlighted_triangles_and_several_meshes_compose_in_one_frame() {
    // Two unit squares side by side (x ∈ [−2, 0] and [0, 2]); the right one's first
    // triangle (lower right half) highlighted; flat colours, head-on.
    let square = |dx: f64, colour: Rgb, highlighted: Vec<u32>| RenderMesh {
        positions: [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
            .map(|(x, y)| DVec3::new(x + dx, y, 0.0))
            .to_vec(),
        triangles: vec![[0, 1, 2], [0, 2, 3]],
        colour: Some(colour),
        highlighted,
        ..RenderMesh::default()
    };
    let left = square(-1.0, [0.2, 0.6, 0.2], vec![]);
    let right = square(1.0, [0.2, 0.2, 0.6], vec![0]);
    let mut o = head_on(Mode::Shaded);
    o.flat = true;
    if let View::Camera(c) = &mut o.views[0] {
        c.projection = Projection::Orthographic { half_height: 2.5 };
    }
    let img = render_scene(&[&left, &right], &[], &o).unwrap();
    let scale = f64::from(SIZE) / 2.0 / 2.5;
    let at = |x: f64, y: f64| {
        let p = img.pixel((100.0 + x * scale) as u32, (100.0 - y * scale) as u32);
        [p[0], p[1], p[2]]
    };
    assert_eq!(at(-1.0, 0.0), rgb_bytes(left.colour.unwrap()));
    assert_eq!(
        at(0.5, 0.5),
        rgb_bytes(right.colour.unwrap()),
        "upper-left half of the right square"
    );
    assert_eq!(
        at(1.5, -0.5),
        rgb_bytes(o.highlight_colour),
        "its highlighted lower-right half"
    );
}
