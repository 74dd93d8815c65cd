//! A vertex's one-ring as the modified Butterfly rules read it, with what makes the stencil
//! of a vertex of high valence cost O(1) per edge instead of O(valence).
//!
//! Zorin, Schröder and Sweldens' stencil for an edge from an extraordinary vertex `v` of
//! valence `k` to its neighbour `q_s` is `3/4 v + Σ_j s_j q_{(s+j) mod k}` with
//! `s_j = (1/4 + cos(θj) + 1/2 cos(2θj))/k`, `θ = 2π/k` ([`crate::subdivision`]). All `k` edges
//! of `v` read all `k` neighbours, so a Butterfly step around `v` cost O(k²), and the
//! Butterfly normals, which subdivide a cut-out around every vertex near `v` (each one holding
//! all of `v`'s fan), cost O(k³): a capped cylinder of 512 segments (two fans of valence 512)
//! spent 8.7 s in its normals, growing ×7 per doubling of the valence.
//!
//! The sum is a circular correlation with three frequencies, so it splits into sums over the
//! ring that do not depend on the edge: with `C_m = Σ_l cos(mθl) q_l` and
//! `S_m = Σ_l sin(mθl) q_l`, `Σ_j cos(mθj) q_{(s+j) mod k} = cos(mθs) C_m + sin(mθs) S_m`
//! (expand `cos(mθ(l − s))`). [`RingFourier`] keeps `Σ q_l`, `C_1`, `S_1`, `C_2`, `S_2` and
//! each neighbour's place `s`; an edge point is then five vector terms. Below
//! [`FOURIER_MIN_VALENCE`] the direct sum (weights from a table) is kept: it is as fast there
//! and keeps the points of every mesh of ordinary valences bit for bit as they were.

use std::cell::RefCell;
use std::f64::consts::PI;
use std::rc::Rc;

use crate::TriMesh;
use crate::fasthash::FastMap;
use crate::topology::Fan;
use glam::DVec3;

/// The least valence whose stencil goes through [`RingFourier`]: the valences below have
/// their weights tabled (`subdivision::extraordinary_weights`), so the direct sum is `k`
/// multiply-adds there.
pub(crate) const FOURIER_MIN_VALENCE: usize = 33;

/// A vertex's one-ring ([`TriMesh::one_ring`]) and, for a closed ring of valence at least
/// [`FOURIER_MIN_VALENCE`], its [`RingFourier`] sums.
pub(crate) struct ButterflyRing {
    pub(crate) fan: Option<Fan>,
    pub(crate) fourier: Option<RingFourier>,
}

impl ButterflyRing {
    /// Vertex `v`'s ring in `mesh`.
    pub(crate) fn of(mesh: &TriMesh, v: u32) -> ButterflyRing {
        let fan = mesh.one_ring(v);
        let fourier = fan
            .as_ref()
            .filter(|f| f.closed && f.neighbors.len() >= FOURIER_MIN_VALENCE)
            .map(|f| RingFourier::new(mesh.positions(), &f.neighbors));
        ButterflyRing { fan, fourier }
    }

    /// The neighbours in cyclic order (empty without a ring).
    pub(crate) fn neighbors(&self) -> &[u32] {
        self.fan.as_ref().map_or(&[], |f| &f.neighbors)
    }
}

/// The edge-independent sums of the stencil over a ring of valence `k` (see the module docs).
pub(crate) struct RingFourier {
    /// Each neighbour's place in the ring.
    place: FastMap<u32, u32>,
    k: usize,
    sum: DVec3,
    c1: DVec3,
    s1: DVec3,
    c2: DVec3,
    s2: DVec3,
    trig: Rc<[[f64; 4]]>,
}

impl RingFourier {
    fn new(positions: &[DVec3], ring: &[u32]) -> RingFourier {
        let k = ring.len();
        let trig = ring_trig(k);
        let (mut sum, mut c1, mut s1, mut c2, mut s2) = (
            DVec3::ZERO,
            DVec3::ZERO,
            DVec3::ZERO,
            DVec3::ZERO,
            DVec3::ZERO,
        );
        for (&u, &[c, s, cc, ss]) in ring.iter().zip(trig.iter()) {
            let q = positions[u as usize];
            sum += q;
            c1 += c * q;
            s1 += s * q;
            c2 += cc * q;
            s2 += ss * q;
        }
        let place = ring
            .iter()
            .enumerate()
            .map(|(l, &u)| (u, l as u32))
            .collect();
        RingFourier {
            place,
            k,
            sum,
            c1,
            s1,
            c2,
            s2,
            trig,
        }
    }

    /// The stencil `3/4 v + Σ_j s_j q_{(s+j) mod k}` for the edge from `v` (at `pv`) to its
    /// neighbour `to`; `None` if `to` is not in the ring.
    pub(crate) fn edge_point(&self, pv: DVec3, to: u32) -> Option<DVec3> {
        let s = *self.place.get(&to)? as usize;
        let [c, sn, cc, ss] = self.trig[s];
        let ring_part =
            0.25 * self.sum + (c * self.c1 + sn * self.s1) + 0.5 * (cc * self.c2 + ss * self.s2);
        Some(0.75 * pv + ring_part / self.k as f64)
    }
}

thread_local! {
    /// [`ring_trig`]'s rows for the valences met on this thread, each computed once (the
    /// same few valences recur in every cut-out around a fan).
    static RING_TRIG: RefCell<FastMap<usize, Rc<[[f64; 4]]>>> = RefCell::new(FastMap::default());
}

/// `[cos θl, sin θl, cos 2θl, sin 2θl]` for `l = 0..k`, `θ = 2π/k`.
fn ring_trig(k: usize) -> Rc<[[f64; 4]]> {
    RING_TRIG.with(|cache| {
        cache
            .borrow_mut()
            .entry(k)
            .or_insert_with(|| {
                (0..k)
                    .map(|l| {
                        let a = 2.0 * PI * l as f64 / k as f64;
                        let (s, c) = a.sin_cos();
                        let (ss, cc) = (2.0 * a).sin_cos();
                        [c, s, cc, ss]
                    })
                    .collect()
            })
            .clone()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The sums give the direct stencil's point, for every edge of rings of valences 33 to
    /// 300 around a bumpy fan, to rounding of the ring's size.
    #[test]
    fn ring_sums_give_the_direct_stencil() {
        for k in [33usize, 34, 47, 64, 100, 300] {
            let theta = 2.0 * PI / k as f64;
            let mut positions = vec![DVec3::new(0.1, -0.2, 0.3)];
            positions.extend((0..k).map(|l| {
                let a = theta * l as f64;
                DVec3::new(
                    a.cos(),
                    a.sin(),
                    0.2 * (3.0 * a).sin() + 0.05 * (l % 7) as f64,
                )
            }));
            let ring: Vec<u32> = (1..=k as u32).collect();
            let fourier = RingFourier::new(&positions, &ring);
            for s in 0..k {
                let direct = 0.75 * positions[0]
                    + (0..k)
                        .map(|j| {
                            let a = theta * j as f64;
                            let w = (0.25 + a.cos() + 0.5 * (2.0 * a).cos()) / k as f64;
                            w * positions[ring[(s + j) % k] as usize]
                        })
                        .sum::<DVec3>();
                let sums = fourier.edge_point(positions[0], ring[s]).unwrap();
                assert!(
                    (sums - direct).length() < 1e-14,
                    "k {k}, edge {s}: {sums} vs {direct}"
                );
            }
            assert!(fourier.edge_point(positions[0], 0).is_none());
        }
    }
}
