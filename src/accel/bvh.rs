//! A bounding volume hierarchy over anything with bounds, built with obvhs
//! (PLOC + reinsertion, then an 8-wide compressed BVH traversed with SIMD).
//!
//! obvhs builds from boxes alone, so any primitive (triangles, spheres,
//! curve segments, instances) fits; traversal calls back with a primitive
//! index and the caller intersects it exactly.

use crate::math::{Bounds3, Ray};
// obvhs's `traverse!` names `UVec2` unqualified.
use glam::UVec2;
use glam::{Vec3, Vec3A};
use obvhs::aabb::Aabb;
use obvhs::cwbvh::node::CwBvhNode;
use obvhs::cwbvh::CwBvh;
use obvhs::ploc::PlocSearchDistance;
use obvhs::BvhBuildParams;
use rayon::prelude::*;

use super::child_test::{ChildTest, Portable};
use super::parallel_build::{self, build_cwbvh_in_parts, Split};

/// Primitive count above which the BVH is built for build speed.
const LARGE_BUILD: usize = 1 << 20;

/// Primitive count from which the BVH is built in parts in parallel
/// (`accel::parallel_build`): there obvhs's single-threaded conversion to
/// the 8-wide tree takes longer than its parallel PLOC.
const PARTS_BUILD: usize = 1 << 16;

/// In a build in parts, a part of this many primitives or more is split
/// again: obvhs holds about 500 bytes per primitive of a tree in progress,
/// so with parts of a few thousand (one in progress per thread) the build
/// adds little to the scene's memory at any thread count
/// (hair-eumel-2-256, 512,000 curve pieces, the BVH phase's peak above
/// what is resident before it: 85 MB with parts of 64,000 at 2 threads,
/// 24 MB at 16 threads with these), and with surface-area splits above
/// them the tree is as good (rays' node and primitive tests within 3 % on
/// hair-eumel-2-256 and hair-blonde-3-bounces-256).
const PART_SIZE: usize = 1 << 12;

/// How the parts of a build in parts are built: obvhs's medium build, but
/// PLOC merges each cluster with the nearer of its two neighbours in
/// Morton order (search distance 1, not 14). Under the surface-area splits
/// above the parts and obvhs's reinsertion after, rays do as little work
/// as in the medium build's trees (instructions per sample −0.6 % on
/// hair-blonde-3-bounces-256, −1.2 % on hair-eumel-2-256, +0.3 % on a
/// mesh of 204,800 triangles; the images byte-identical), and the setup
/// takes a fifth fewer instructions (hair-blonde-3-bounces-256: 4.68 →
/// 3.75 G).
const PARTS_PARAMS: BvhBuildParams = BvhBuildParams {
    ploc_search_distance: PlocSearchDistance::Minimum,
    ..BvhBuildParams::medium_build()
};

/// [`PART_SIZE`] above a million primitives, where build time counts
/// most: one level of splits fewer (120 MB of random curves: build CPU
/// time 0.3–0.6 s less than with parts under 4096).
const LARGE_PART_SIZE: usize = 1 << 14;

/// A BVH whose leaves refer to primitives `0..n` in the order given to
/// [`Bvh::build`] — callers should store their primitives in
/// [`Bvh::order`] so that neighbours in the tree are neighbours in memory.
pub struct Bvh {
    tree: Option<CwBvh>,
    bounds: Bounds3,
    /// Added to a leaf's slot to give the caller's primitive index.
    first: usize,
}

/// A primitive's box in the form the builder takes (obvhs's, SIMD-aligned).
pub type BuildBox = Aabb;

/// `b` as a [`BuildBox`].
pub fn build_box(b: &Bounds3) -> BuildBox {
    Aabb::new(Vec3A::from(b.min), Vec3A::from(b.max))
}

fn bounds_of(b: &Aabb) -> Bounds3 {
    Bounds3 {
        min: Vec3::from(b.min),
        max: Vec3::from(b.max),
    }
}

impl Bvh {
    /// Builds over `bounds` and returns the BVH with the order in which the
    /// caller should lay out its primitives (index `i` of the new layout is
    /// the caller's primitive `order[i]`).
    pub fn build(bounds: &[Bounds3]) -> (Bvh, Vec<u32>) {
        Self::build_from(bounds, 0)
    }

    /// As [`Bvh::build`], for primitives stored from index `first` of the
    /// caller's array: the traversal reports `first + i` (an object's
    /// primitives share one array with the scene's; see `accel::instance`).
    /// `order` is still relative (`0..bounds.len()`).
    pub fn build_from(bounds: &[Bounds3], first: u32) -> (Bvh, Vec<u32>) {
        let boxes: Vec<Aabb> = bounds.par_iter().map(build_box).collect();
        Self::build_from_boxes(&boxes, first)
    }

    /// As [`Bvh::build_from`], from boxes already in the builder's form
    /// ([`build_box`]): a scene of millions of primitives then holds one
    /// array of boxes during the build, not two.
    pub fn build_from_boxes(aabbs: &[BuildBox], first: u32) -> (Bvh, Vec<u32>) {
        let total = aabbs
            .par_iter()
            .fold(|| Bounds3::EMPTY, |a, b| a.union(bounds_of(b)))
            .reduce(|| Bounds3::EMPTY, Bounds3::union);
        if aabbs.is_empty() {
            return (
                Bvh {
                    tree: None,
                    bounds: total,
                    first: first as usize,
                },
                Vec::new(),
            );
        }
        let (params, split, part_size) = if aabbs.len() > LARGE_BUILD {
            // Above a million primitives the build dominates a quick
            // render (120 MB of random curves: 14 s with the medium build,
            // 6.8 s with the very fast one; pbrt-v4 takes 8.9 s), so trade
            // a little traversal speed for it: median splits, cheaper
            // than binning.
            (
                BvhBuildParams::very_fast_build(),
                Split::Median,
                LARGE_PART_SIZE,
            )
        } else if aabbs.len() >= PARTS_BUILD {
            (PARTS_PARAMS, Split::SurfaceArea, PART_SIZE)
        } else {
            (
                BvhBuildParams::medium_build(),
                Split::SurfaceArea,
                usize::MAX,
            )
        };
        let mut tree = build_cwbvh_in_parts(aabbs, params, part_size, split);
        if parallel_build::depth(&tree) > parallel_build::MAX_DEPTH {
            tree = parallel_build::balanced(aabbs, params);
        }
        // Leaves index the caller's reordered array directly: slot i is
        // the caller's primitive `first + i` (no index array to read per
        // primitive).
        let order = std::mem::take(&mut tree.primitive_indices);
        (
            Bvh {
                tree: Some(tree),
                bounds: total,
                first: first as usize,
            },
            order,
        )
    }

    pub fn bounds(&self) -> Bounds3 {
        self.bounds
    }

    fn obvhs_ray(ray: &Ray, t_max: f32) -> obvhs::ray::Ray {
        // `+ 0.0` turns −0 into +0: obvhs 0.4's traversal misses every box
        // for a direction with a −0 component (as a transformed ray or
        // `-v` of an axis-aligned vector has).
        obvhs::ray::Ray::new(
            Vec3A::from(ray.origin),
            Vec3A::from(ray.direction + Vec3::ZERO),
            0.0,
            t_max,
        )
    }

    /// Closest hit: `intersect(i, t_max)` returns the hit distance of
    /// primitive `i` if it is below `t_max` (and above 0). Returns the
    /// primitive and distance of the closest hit.
    #[inline(always)]
    pub fn closest_hit(
        &self,
        ray: &Ray,
        t_max: f32,
        intersect: impl FnMut(usize, f32) -> Option<f32>,
    ) -> Option<(usize, f32)> {
        self.closest_hit_prefetching(ray, t_max, Portable, |_| {}, intersect)
    }

    /// As [`Bvh::closest_hit`], testing nodes with `children`, and calling
    /// `prefetch(i)` for every primitive
    /// of a leaf the ray enters as soon as its node is tested, before any
    /// of them is intersected: the caller can start loading what
    /// `intersect(i, ..)` will read, so that the leaves' cache misses
    /// overlap instead of following one another.
    ///
    /// Always inlined, as are the other queries: the scene compiles its
    /// queries once more for x86-64-v3 (`InstructionSet`), and only what
    /// is inlined there gets the wider instructions.
    #[inline(always)]
    pub fn closest_hit_prefetching(
        &self,
        ray: &Ray,
        t_max: f32,
        children: impl ChildTest,
        prefetch: impl Fn(usize),
        mut intersect: impl FnMut(usize, f32) -> Option<f32>,
    ) -> Option<(usize, f32)> {
        let tree = self.tree.as_ref()?;
        let mut traverse_ray = Self::obvhs_ray(ray, t_max);
        let mut best = None;
        let mut state = tree.new_traversal(traverse_ray.direction);
        let mut node;
        obvhs::traverse!(
            tree,
            node,
            state,
            self.test_node(node, &traverse_ray, state.oct_inv4, children, &prefetch),
            {
                let i = self.first + state.primitive_id as usize;
                if let Some(t) = intersect(i, traverse_ray.tmax) {
                    if t > 0.0 && t < traverse_ray.tmax {
                        best = Some((i, t));
                        traverse_ray.tmax = t;
                    }
                }
            }
        );
        best
    }

    /// Whether any primitive is hit before `t_max`.
    #[inline(always)]
    pub fn any_hit(&self, ray: &Ray, t_max: f32, hits: impl FnMut(usize, f32) -> bool) -> bool {
        self.any_hit_prefetching(ray, t_max, Portable, |_| {}, hits)
    }

    /// As [`Bvh::any_hit`], with `children` and `prefetch` as in
    /// [`Bvh::closest_hit_prefetching`].
    #[inline(always)]
    pub fn any_hit_prefetching(
        &self,
        ray: &Ray,
        t_max: f32,
        children: impl ChildTest,
        prefetch: impl Fn(usize),
        mut hits: impl FnMut(usize, f32) -> bool,
    ) -> bool {
        let Some(tree) = self.tree.as_ref() else {
            return false;
        };
        let traverse_ray = Self::obvhs_ray(ray, t_max);
        let mut state = tree.new_traversal(traverse_ray.direction);
        let mut node;
        obvhs::traverse!(
            tree,
            node,
            state,
            self.test_node(node, &traverse_ray, state.oct_inv4, children, &prefetch),
            {
                if hits(self.first + state.primitive_id as usize, t_max) {
                    return true;
                }
            }
        );
        false
    }

    /// The children of `node` the ray enters (obvhs's hit mask: inner
    /// children in the high byte, leaf primitives in the low 24 bits),
    /// with the leaf primitives handed to `prefetch`.
    #[inline(always)]
    fn test_node(
        &self,
        node: &CwBvhNode,
        ray: &obvhs::ray::Ray,
        oct_inv4: u32,
        children: impl ChildTest,
        prefetch: &impl Fn(usize),
    ) -> u32 {
        let hit_mask = children.hits(node, ray, oct_inv4);
        let leaves = hit_mask & 0x00ff_ffff;
        if leaves != 0 {
            // The first three without a loop (a loop over a varying count
            // of set bits is a branch the processor keeps mispredicting:
            // a sixth of a hair render's mispredictions): where fewer are
            // entered, the last one again (its line is on its way already).
            // Written out: as a fixed-count loop with an `if`, the compiler
            // made branches again (6 % more mispredictions per sample).
            let base = self.first + node.primitive_base_idx as usize;
            let next = |bits: u32, previous: u32| {
                if bits != 0 {
                    bits.trailing_zeros()
                } else {
                    previous
                }
            };
            let first = leaves.trailing_zeros();
            let rest = leaves & (leaves - 1);
            let second = next(rest, first);
            let mut rest = rest & rest.wrapping_sub(1);
            let third = next(rest, second);
            for slot in [first, second, third] {
                prefetch(base + slot as usize);
            }
            rest &= rest.wrapping_sub(1);
            while rest != 0 {
                prefetch(base + rest.trailing_zeros() as usize);
                rest &= rest - 1;
            }
        }
        hit_mask
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    /// Unit spheres on a grid, intersected exactly.
    fn sphere_hit(center: Vec3, ray: &Ray, t_max: f32) -> Option<f32> {
        let oc = ray.origin - center;
        let a = ray.direction.length_squared();
        let b = oc.dot(ray.direction);
        let c = oc.length_squared() - 0.25;
        let disc = b * b - a * c;
        if disc < 0.0 {
            return None;
        }
        let t = (-b - disc.sqrt()) / a;
        (t > 0.0 && t < t_max).then_some(t)
    }

    /// Thousands of primitives in one place make obvhs's tree deeper than
    /// its traversal stack is long (a ray that branches at every level
    /// would skip subtrees): the build balances such a tree, and a ray
    /// still reaches every primitive.
    #[test]
    fn coincident_primitives_are_all_reached() {
        let bounds = vec![
            Bounds3 {
                min: Vec3::ZERO,
                max: Vec3::ONE,
            };
            3000
        ];
        let (bvh, _) = Bvh::build(&bounds);
        let tree = bvh.tree.as_ref().unwrap();
        assert!(parallel_build::depth(tree) <= parallel_build::MAX_DEPTH);
        let ray = Ray::new(Vec3::new(0.5, 0.5, -1.0), Vec3::Z, 0.0);
        let mut reached = vec![false; bounds.len()];
        let got = bvh.closest_hit(&ray, f32::INFINITY, |i, _| {
            reached[i] = true;
            None
        });
        assert!(got.is_none());
        assert_eq!(reached.iter().filter(|&&r| r).count(), bounds.len());
    }

    #[test]
    fn closest_and_any_hit_match_brute_force() {
        let centers: Vec<Vec3> = (0..1000)
            .map(|i| Vec3::new((i % 10) as f32, ((i / 10) % 10) as f32, (i / 100) as f32) * 1.5)
            .collect();
        let bounds: Vec<Bounds3> = centers
            .iter()
            .map(|&c| Bounds3 {
                min: c - Vec3::splat(0.5),
                max: c + Vec3::splat(0.5),
            })
            .collect();
        let (bvh, order) = Bvh::build(&bounds);
        let reordered: Vec<Vec3> = order.iter().map(|&i| centers[i as usize]).collect();
        let mut state = 12345u32;
        let mut rnd = || {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            state as f32 / u32::MAX as f32
        };
        for _ in 0..2000 {
            let origin = Vec3::new(rnd() * 20.0 - 3.0, rnd() * 20.0 - 3.0, -5.0);
            let dir = Vec3::new(rnd() - 0.5, rnd() - 0.5, 1.0).normalize();
            let ray = Ray::new(origin, dir, 0.0);
            let brute = centers
                .iter()
                .filter_map(|&c| sphere_hit(c, &ray, f32::INFINITY))
                .fold(f32::INFINITY, f32::min);
            let got = bvh.closest_hit(&ray, f32::INFINITY, |i, t_max| {
                sphere_hit(reordered[i], &ray, t_max)
            });
            match got {
                Some((i, t)) => {
                    assert!((t - brute).abs() < 1e-4, "{t} vs {brute}");
                    assert!(
                        (sphere_hit(reordered[i], &ray, f32::INFINITY).unwrap() - t).abs() < 1e-4
                    );
                }
                None => assert!(brute.is_infinite()),
            }
            let any = bvh.any_hit(&ray, 1e30, |i, t_max| {
                sphere_hit(reordered[i], &ray, t_max).is_some()
            });
            assert_eq!(any, brute.is_finite());
        }
    }

    #[test]
    fn negative_zero_directions_hit() {
        let (bvh, _) = Bvh::build(&[Bounds3 {
            min: Vec3::new(-1.0, -4.0, -1.0),
            max: Vec3::new(1.0, 4.0, 1.0),
        }]);
        let ray = Ray::new(Vec3::new(1.8, 9.6, 0.0), Vec3::new(-1.2, -6.4, -0.0), 0.0);
        assert!(bvh
            .closest_hit(&ray, f32::INFINITY, |_, _| Some(1.0))
            .is_some());
        assert!(bvh.any_hit(&ray, f32::INFINITY, |_, _| true));
    }

    #[test]
    fn empty_and_single() {
        let (bvh, order) = Bvh::build(&[]);
        assert!(order.is_empty());
        assert!(bvh
            .closest_hit(&Ray::new(Vec3::ZERO, Vec3::Z, 0.0), 1.0, |_, _| Some(0.5))
            .is_none());
        let (bvh, order) = Bvh::build(&[Bounds3 {
            min: Vec3::splat(-1.0),
            max: Vec3::splat(1.0),
        }]);
        assert_eq!(order, vec![0]);
        let hit = bvh.closest_hit(
            &Ray::new(Vec3::new(0.0, 0.0, -5.0), Vec3::Z, 0.0),
            100.0,
            |_, _| Some(4.0),
        );
        assert_eq!(hit, Some((0, 4.0)));
    }
}
