//! Clumps: `--clumps K` guide strands grown like the others (their own
//! random streams); each strand belongs to the guide whose root is nearest
//! its own and is pulled towards it by `--clumping` (see `strand::clump`).
//! The guides are not written.
//!
//! | option       | default | meaning                                        |
//! |--------------|---------|------------------------------------------------|
//! | `--clumps`   | 0       | number of clumps (0: none)                     |
//! | `--clumping` | 0.5     | c in [0, 1]: how far tips move to the guide's |
//!
//! The nearest root is found in a uniform grid over the guide roots (cells
//! about one guide apart), searched in growing shells of cells until no
//! nearer root can remain.

use glam::DVec3;
use std::collections::HashMap;

/// Guide roots in a grid.
pub struct NearestRoot {
    roots: Vec<DVec3>,
    origin: DVec3,
    cell: f64,
    cells: HashMap<[i64; 3], Vec<u32>>,
    /// The largest cell index in any axis from the origin (stops the search).
    reach: i64,
}

impl NearestRoot {
    /// `roots` must not be empty.
    pub fn new(roots: Vec<DVec3>) -> Self {
        let (lo, hi) = roots.iter().fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        );
        let extent = (hi - lo).max_element().max(1e-12);
        // Roots lie on a surface: about sqrt(K) cells across it.
        let cell = extent / (roots.len() as f64).sqrt().max(1.0);
        let mut cells: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
        let mut grid = NearestRoot {
            roots: Vec::new(),
            origin: lo,
            cell,
            cells: HashMap::new(),
            reach: ((extent / cell).ceil() as i64).max(1) + 1,
        };
        for (i, p) in roots.iter().enumerate() {
            cells.entry(grid.key(*p)).or_default().push(i as u32);
        }
        grid.roots = roots;
        grid.cells = cells;
        grid
    }

    fn key(&self, p: DVec3) -> [i64; 3] {
        let c = ((p - self.origin) / self.cell).floor();
        [c.x as i64, c.y as i64, c.z as i64]
    }

    /// The index of the root nearest `p` (the lowest index among equals).
    pub fn nearest(&self, p: DVec3) -> usize {
        let margin = DVec3::splat(self.cell);
        let inside = p.cmpge(self.origin - margin).all()
            && p.cmple(self.origin + margin * (self.reach + 1) as f64)
                .all();
        if self.roots.len() <= 64 || !inside {
            return self.nearest_by_search(p);
        }
        let center = self.key(p);
        let mut best: Option<(f64, usize)> = None;
        let visit = |key: [i64; 3], best: &mut Option<(f64, usize)>| {
            if let Some(list) = self.cells.get(&key) {
                for &i in list {
                    let d = self.roots[i as usize].distance_squared(p);
                    let i = i as usize;
                    if best.is_none_or(|(bd, bi)| d < bd || (d == bd && i < bi)) {
                        *best = Some((d, i));
                    }
                }
            }
        };
        let far = self.reach + 2;
        for shell in 0..=far {
            for dx in -shell..=shell {
                for dy in -shell..=shell {
                    for dz in -shell..=shell {
                        if dx.abs().max(dy.abs()).max(dz.abs()) != shell {
                            continue;
                        }
                        visit([center[0] + dx, center[1] + dy, center[2] + dz], &mut best);
                    }
                }
            }
            // Anything in shell + 1 or beyond is at least shell·cell away.
            if let Some((d, _)) = best {
                let reach = shell as f64 * self.cell;
                if d <= reach * reach {
                    break;
                }
            }
        }
        best.map_or(0, |(_, i)| i)
    }

    fn nearest_by_search(&self, p: DVec3) -> usize {
        let mut best = (f64::INFINITY, 0);
        for (i, r) in self.roots.iter().enumerate() {
            let d = r.distance_squared(p);
            if d < best.0 {
                best = (d, i);
            }
        }
        best.1
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tools::hairgen::roots::Random;

    #[test]
    fn the_grid_finds_the_same_root_as_a_full_search() {
        let mut r = Random::new(9, 0, 0);
        let point = |r: &mut Random| {
            DVec3::new(r.uniform(), r.uniform(), r.uniform()).normalize_or_zero() * 2.0
        };
        let roots: Vec<DVec3> = (0..300).map(|_| point(&mut r)).collect();
        let grid = NearestRoot::new(roots.clone());
        for _ in 0..2000 {
            let p = point(&mut r) * (0.5 + r.uniform());
            let brute = (0..roots.len())
                .min_by(|&a, &b| {
                    roots[a]
                        .distance_squared(p)
                        .total_cmp(&roots[b].distance_squared(p))
                })
                .unwrap();
            assert_eq!(grid.nearest(p), brute);
        }
        let one = NearestRoot::new(vec![DVec3::ONE]);
        assert_eq!(one.nearest(DVec3::new(-40.0, 3.0, 9.0)), 0);
    }
}
