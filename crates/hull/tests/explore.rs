mod common;
use algesurf_hull::*;
use glam::DVec3;

fn grid(n: usize, f: &dyn Fn(f64, f64) -> (f64, DVec3)) -> (Vec<DVec3>, Vec<[u32; 3]>, Vec<DVec3>) {
    let mut p = Vec::new();
    let mut nn = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let x = -1.0 + 2.0 * i as f64 / n as f64;
            let y = -1.0 + 2.0 * j as f64 / n as f64;
            let (z, g) = f(x, y);
            p.push(DVec3::new(x, y, z));
            nn.push(g.normalize());
        }
    }
    let mut t = Vec::new();
    let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    for j in 0..n {
        for i in 0..n {
            t.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            t.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    (p, t, nn)
}

#[test]
fn explore() {
    for (name, a, w) in [("wave", 0.3, 3.0)] {
        let f = move |x: f64, y: f64| {
            let z = a * (w * x).sin() * (w * y).sin();
            let gx = a * w * (w * x).cos() * (w * y).sin();
            let gy = a * w * (w * x).sin() * (w * y).cos();
            (z, DVec3::new(-gx, -gy, 1.0))
        };
        for n in [3] {
            let (p, t, nn) = grid(n, &f);
            let o0 = HullOptions { max_refinement_rounds: 0, check_intersections: false, ..Default::default() };
            let h0 = match SimplicialHull::new(&p, &t, &nn, &o0) { Ok(h) => h, Err(e) => { eprintln!("{name} n={n}: {e}"); continue } };
            let k = h0.intersections().len();
            let r = SimplicialHull::new(&p, &t, &nn, &HullOptions::default());
            match r {
                Ok(h) => eprintln!("{name} n={n}: {k} hits, resolved with {} splits, faces {}", h.refinements().len(), h.faces().len()),
                Err(e) => eprintln!("{name} n={n}: {k} hits, error {e}"),
            }
        }
    }
}
