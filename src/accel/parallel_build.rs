//! Building a large CWBVH on every core: the primitives are split into
//! eight spatial groups, each group's tree is built with obvhs on its own
//! (in parallel), and the eight trees hang from one root node; a group
//! still large is split again in the same way.
//!
//! obvhs's PLOC is parallel, but its conversion of the binary tree into the
//! 8-wide compressed one is a single-threaded recursion, and it was the
//! largest part of the build of a hair scene (hair-blonde-3-bounces-256:
//! 0.36 s of a 0.6 s BVH build; 640,000 curve pieces). obvhs also holds
//! about 500 bytes per primitive of a tree in progress, so groups of at
//! most a few thousand primitives keep the build's peak memory small: one
//! group per core is in progress at a time. The top levels of the tree
//! come from binned surface-area splits instead of PLOC's clustering; the
//! groups are then as good as obvhs makes them.

use super::wide_conversion::WideConversion;
use glam::Vec3A;
use obvhs::aabb::Aabb;
use obvhs::bvh2::reinsertion::ReinsertionOptimizer;
use obvhs::bvh2::Bvh2;
use obvhs::cwbvh::builder::build_cwbvh;
use obvhs::cwbvh::bvh2_to_cwbvh::bvh2_to_cwbvh;
use obvhs::cwbvh::node::CwBvhNode;
use obvhs::cwbvh::CwBvh;
use obvhs::ploc::PlocBuilder;
use obvhs::BvhBuildParams;
use rayon::prelude::*;
use std::ops::Range;
use std::sync::Mutex;

/// Number of groups: one CWBVH node's children.
const GROUPS: usize = 8;

/// A child slot's meta byte for an inner child (the CWBVH encoding, as in
/// `CwBvhNode::child_meta`'s doc): high bits 001, low bits 24 + slot.
fn inner_child_meta(slot: usize) -> u8 {
    0b0010_0000 | (24 + slot as u8)
}

/// How the primitives of a group are halved.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Split {
    /// At the median centroid along the longest axis of the centroids:
    /// halves of equal size, so the tree's depth is bounded whatever the
    /// boxes.
    Median,
    /// Along the same axis, where the surface area heuristic of [`BINS`]
    /// bins of centroids is least (Wald 2007, "On fast construction of
    /// SAH-based bounding volume hierarchies"): the better tree where
    /// primitives are not spread evenly (hair: strands of different
    /// lengths, bare scalp).
    SurfaceArea,
}

/// Builds over `aabbs` as obvhs's `build_cwbvh` does, in eight parts when
/// there are at least `part_size` primitives (else in one), each part in
/// parts again while it has that many. The result's `primitive_indices`
/// refer to `aabbs` as obvhs's do.
pub fn build_cwbvh_in_parts(
    aabbs: &[Aabb],
    params: BvhBuildParams,
    part_size: usize,
    split: Split,
) -> CwBvh {
    if aabbs.len() < part_size.max(GROUPS) {
        // obvhs reports its core build time; unused here.
        return build_cwbvh(aabbs, params, &mut std::time::Duration::default());
    }
    // All the splits first, then the parts: the members (16 bytes each,
    // with their centroids) are freed before any part's tree is built, and
    // the builds need only the box indices (4 bytes each).
    let mut members = Member::all(aabbs);
    let plan = plan_groups(aabbs, &mut members, 0, part_size, split);
    let indices: Vec<u32> = members.par_iter().map(|m| m.index).collect();
    drop(members);
    build_planned(aabbs, &indices, &plan, params, &Workspaces::default())
}

/// obvhs's working arrays for one part's tree, kept for the next part:
/// made afresh for each part, they were mapped, faulted in page by page
/// and unmapped again, hundreds of times over on a large scene (120 MB of
/// random curves: 300 parts of up to 16,384 pieces, about 3 MB each; page
/// faults 810,000 → 680,000 over the whole run, its build 0.09 s shorter).
#[derive(Default)]
struct PartWorkspace {
    boxes: Vec<Aabb>,
    clustering: PlocBuilder,
    binary_tree: Bvh2,
    reinsertion: ReinsertionOptimizer,
    conversion: WideConversion,
}

impl PartWorkspace {
    /// What obvhs's `build_cwbvh` makes of `group`'s boxes (the same tree:
    /// PLOC, reinsertion, conversion), with its indices into `aabbs`.
    fn build(&mut self, aabbs: &[Aabb], group: &[u32], params: BvhBuildParams) -> CwBvh {
        self.boxes.clear();
        self.boxes.extend(group.iter().map(|&i| aabbs[i as usize]));
        self.clustering.build_with_bvh(
            &mut self.binary_tree,
            params.ploc_search_distance,
            &self.boxes,
            (0..group.len() as u32).collect(),
            params.sort_precision,
            params.search_depth_threshold,
        );
        self.reinsertion
            .run(&mut self.binary_tree, params.reinsertion_batch_ratio, None);
        let max_per_leaf = params.max_prims_per_leaf.clamp(1, 3);
        let mut tree = self.conversion.convert(&self.binary_tree, max_per_leaf);
        for index in &mut tree.primitive_indices {
            *index = group[*index as usize];
        }
        tree
    }
}

/// Parts of at least this many primitives leave their workspace for the
/// next part: from here on its arrays of 32 bytes per primitive reach
/// glibc's threshold for mapping blocks on their own (128 kB, `memory.rs`).
/// Smaller parts' arrays come from its heap at no such cost; kept, they
/// would only add to the peak (hair scenes, whose parts are smaller, at 16
/// threads: +5 to +9 MB, build time the same).
const REUSED_FROM: usize = 1 << 12;

/// The workspaces of one build: at most one per part in progress (one per
/// thread), freed before the top of the tree is joined.
#[derive(Default)]
struct Workspaces(Mutex<Vec<PartWorkspace>>);

impl Workspaces {
    fn build(&self, aabbs: &[Aabb], group: &[u32], params: BvhBuildParams) -> CwBvh {
        let taken = self.idle().pop();
        let mut workspace = taken.unwrap_or_default();
        let tree = workspace.build(aabbs, group, params);
        if group.len() >= REUSED_FROM {
            self.idle().push(workspace);
        }
        tree
    }

    fn free(&self) {
        self.idle().clear();
    }

    /// The workspaces no part is using.
    fn idle(&self) -> std::sync::MutexGuard<'_, Vec<PartWorkspace>> {
        self.0.lock().unwrap_or_else(|e| e.into_inner())
    }
}

/// A primitive of a group being split: its box's centroid and its index in
/// the array of boxes. The centroid travels with the index, so halving a
/// group reads its members in order and no box at all: selecting among
/// indices by their boxes' centroids read boxes at random, twice per
/// halving (the centroids' bounds, then the keys to select by), and was
/// the build's largest cost above a million primitives (120 MB of random
/// curves: 13 % of the run's CPU time).
#[derive(Clone, Copy, Debug)]
struct Member {
    centroid: [f32; 3],
    index: u32,
}

impl Member {
    /// The members of every box of `aabbs`, in order.
    fn all(aabbs: &[Aabb]) -> Vec<Member> {
        aabbs
            .par_iter()
            .enumerate()
            .map(|(index, b)| Member {
                centroid: b.center().into(),
                index: index as u32,
            })
            .collect()
    }

    /// The order of a halving along `axis`: by centroid as
    /// `f32::total_cmp` orders them, ties by index.
    fn key(self, axis: usize) -> u64 {
        u64::from(ordered_bits(self.centroid[axis])) << 32 | u64::from(self.index)
    }
}

/// `x`'s bits as an unsigned integer in the order of `f32::total_cmp`.
fn ordered_bits(x: f32) -> u32 {
    let bits = x.to_bits();
    if bits >> 31 == 1 {
        !bits
    } else {
        bits | 1 << 31
    }
}

/// How a group of members is built: whole, or as eight groups whose trees
/// hang from one root. Each holds its range of the members.
enum Plan {
    Whole(Range<usize>),
    Parts(Range<usize>, Vec<Plan>),
}

/// Splits `group` (the members from `first` on) into groups, and those
/// again, until each has fewer than `part_size`; returns how they are to
/// be built.
fn plan_groups(
    aabbs: &[Aabb],
    group: &mut [Member],
    first: usize,
    part_size: usize,
    split: Split,
) -> Plan {
    let range = first..first + group.len();
    if group.len() < part_size.max(GROUPS) {
        return Plan::Whole(range);
    }
    // The groups are consecutive stretches of `group`, in order.
    let mut start = first;
    let parts: Vec<(usize, &mut [Member])> = split_into_groups(group, aabbs, split, GROUPS)
        .into_iter()
        .map(|part| {
            start += part.len();
            (start - part.len(), part)
        })
        .collect();
    let plans = parts
        .into_par_iter()
        .map(|(first, part)| plan_groups(aabbs, part, first, part_size, split))
        .collect();
    Plan::Parts(range, plans)
}

/// The tree `plan` says over the boxes `indices` of `aabbs` (its
/// `primitive_indices` are indices of `aabbs`). Only a part built whole
/// copies its boxes, so the parts in progress, one per core, are all the
/// build adds.
fn build_planned(
    aabbs: &[Aabb],
    indices: &[u32],
    plan: &Plan,
    params: BvhBuildParams,
    workspaces: &Workspaces,
) -> CwBvh {
    let (range, plans) = match plan {
        Plan::Whole(range) => return workspaces.build(aabbs, &indices[range.clone()], params),
        Plan::Parts(range, plans) => (range, plans),
    };
    let parts: Vec<CwBvh> = plans
        .par_iter()
        .map(|part| build_planned(aabbs, indices, part, params, workspaces))
        .collect();
    if range.len() == indices.len() {
        // Every part is built: the workspaces (a few MB each, one per
        // thread) go before the joined tree comes.
        workspaces.free();
    }
    join_under_root(parts)
        .unwrap_or_else(|| workspaces.build(aabbs, &indices[range.clone()], params))
}

/// Splits `members` into `count` (a power of two) groups by halving each
/// along the longest axis of its centroids as `split` says (the halves in
/// parallel). Every group holds at least one primitive when there are at
/// least `count`.
fn split_into_groups<'a>(
    members: &'a mut [Member],
    aabbs: &[Aabb],
    split: Split,
    count: usize,
) -> Vec<&'a mut [Member]> {
    if count <= 1 {
        return vec![members];
    }
    let (lo, hi) = members
        .par_iter()
        .fold(
            || (Vec3A::splat(f32::INFINITY), Vec3A::splat(f32::NEG_INFINITY)),
            |(lo, hi), m| {
                let c = Vec3A::from(m.centroid);
                (lo.min(c), hi.max(c))
            },
        )
        .reduce(
            || (Vec3A::splat(f32::INFINITY), Vec3A::splat(f32::NEG_INFINITY)),
            |a, b| (a.0.min(b.0), a.1.max(b.1)),
        );
    let extent = hi - lo;
    let axis = if extent.x >= extent.y && extent.x >= extent.z {
        0
    } else if extent.y >= extent.z {
        1
    } else {
        2
    };
    let median = members.len() / 2;
    let middle = match split {
        Split::Median => select(members, median, axis),
        Split::SurfaceArea => {
            let plane = surface_area_split(members, aabbs, axis, lo, hi);
            let wanted = plane.as_ref().map_or(median, |p| p.left_count);
            // Each half must keep enough primitives for its groups.
            let middle = wanted.clamp(count / 2, members.len() - count / 2);
            match plane {
                // The bins' own halves: one pass, where selecting them by
                // centroid took several.
                Some(plane) if middle == wanted => partition(members, |m| plane.goes_left(m)),
                _ => select(members, middle, axis),
            }
        }
    };
    let (left, right) = members.split_at_mut(middle);
    let (mut groups, right_groups) = rayon::join(
        || split_into_groups(left, aabbs, split, count / 2),
        || split_into_groups(right, aabbs, split, count / 2),
    );
    groups.extend(right_groups);
    groups
}

/// Bins of centroids along the split axis for [`Split::SurfaceArea`].
const BINS: usize = 32;

/// Moves the `middle` smallest centroids along `axis` (ties in index
/// order) before the others; returns `middle`.
fn select(members: &mut [Member], middle: usize, axis: usize) -> usize {
    members.select_nth_unstable_by_key(middle, |m| m.key(axis));
    middle
}

/// Moves the members for which `goes_left` holds before the others, in
/// one pass without branches on it (the halves' order within is
/// arbitrary); returns how many there are.
fn partition(members: &mut [Member], goes_left: impl Fn(&Member) -> bool) -> usize {
    // members[..left] go left, members[left..i] go right.
    let mut left = 0;
    for i in 0..members.len() {
        let goes = goes_left(&members[i]);
        members.swap(left, i);
        left += usize::from(goes);
    }
    left
}

/// The halving [`surface_area_split`] chooses: the members whose
/// centroids fall in the bins before `first_right_bin`.
struct BinPlane {
    axis: usize,
    lo: f32,
    scale: f32,
    first_right_bin: usize,
    /// How many members go left.
    left_count: usize,
}

impl BinPlane {
    /// The bin of `m`'s centroid, of [`BINS`] equal bins from `lo` on
    /// (converted through `u32`, which saturates in fewer instructions
    /// than `usize`: the same bin for every value, NaN's 0 included).
    fn bin(&self, m: &Member) -> usize {
        (((m.centroid[self.axis] - self.lo) * self.scale) as u32).min(BINS as u32 - 1) as usize
    }

    fn goes_left(&self, m: &Member) -> bool {
        self.bin(m) < self.first_right_bin
    }
}

/// The boundary between two of [`BINS`] equal bins of the centroids along
/// `axis` (from `lo` to `hi`) where the halves' surface area heuristic,
/// area × count summed over the two halves, is least; `None` when all
/// centroids share one bin.
fn surface_area_split(
    members: &[Member],
    aabbs: &[Aabb],
    axis: usize,
    lo: Vec3A,
    hi: Vec3A,
) -> Option<BinPlane> {
    let n = members.len();
    let (lo, hi) = (lo[axis], hi[axis]);
    if hi <= lo {
        return None;
    }
    let mut plane = BinPlane {
        axis,
        lo,
        scale: BINS as f32 / (hi - lo),
        first_right_bin: 0,
        left_count: 0,
    };
    // Each chunk's bins filled in place (a fold moving the 1.3 kB of bins
    // per primitive costs more than the binning).
    let (boxes, counts) = members
        .par_chunks(1 << 12)
        .map(|chunk| {
            let mut boxes = [Aabb::empty(); BINS];
            let mut counts = [0usize; BINS];
            for m in chunk {
                let k = plane.bin(m);
                boxes[k] = boxes[k].union(&aabbs[m.index as usize]);
                counts[k] += 1;
            }
            (boxes, counts)
        })
        .reduce(
            || ([Aabb::empty(); BINS], [0usize; BINS]),
            |(mut boxes, mut counts), (other_boxes, other_counts)| {
                for k in 0..BINS {
                    boxes[k] = boxes[k].union(&other_boxes[k]);
                    counts[k] += other_counts[k];
                }
                (boxes, counts)
            },
        );
    // right_cost[k]: the heuristic of bins k.. as one half.
    let mut right_cost = [0.0f32; BINS];
    let (mut right, mut right_count) = (Aabb::empty(), 0);
    for k in (1..BINS).rev() {
        right = right.union(&boxes[k]);
        right_count += counts[k];
        right_cost[k] = right.half_area() * right_count as f32;
    }
    let mut best_cost = f32::INFINITY;
    let (mut left, mut left_count) = (Aabb::empty(), 0);
    for k in 1..BINS {
        left = left.union(&boxes[k - 1]);
        left_count += counts[k - 1];
        if left_count == 0 || left_count == n {
            continue;
        }
        let cost = left.half_area() * left_count as f32 + right_cost[k];
        if cost < best_cost {
            best_cost = cost;
            (plane.first_right_bin, plane.left_count) = (k, left_count);
        }
    }
    (plane.first_right_bin > 0).then_some(plane)
}

/// One tree of the eight `parts`: a root node whose children are the
/// parts' roots. The root is made by obvhs from a tree over the parts'
/// boxes (so its quantised child boxes and its child order for each ray
/// octant are obvhs's own); its eight leaves then become inner children.
/// None if obvhs does not put all eight boxes in one node.
fn join_under_root(parts: Vec<CwBvh>) -> Option<CwBvh> {
    // Each part is freed once copied: the joined tree does not sit beside
    // all of them.
    let mut parts: Vec<Option<CwBvh>> = parts.into_iter().map(Some).collect();
    let part_boxes: Vec<Aabb> = parts.iter().flatten().map(|p| p.total_aabb).collect();
    let top = PlocBuilder::with_capacity(part_boxes.len()).build(
        obvhs::ploc::PlocSearchDistance::Minimum,
        &part_boxes,
        (0..part_boxes.len() as u32).collect::<Vec<_>>(),
        obvhs::ploc::SortPrecision::U64,
        1,
    );
    let top = bvh2_to_cwbvh(&top, 1, true, false);
    let mut root = *top.nodes.first()?;
    if top.nodes.len() != 1 || root.child_meta.iter().filter(|&&m| m != 0).count() != parts.len() {
        return None;
    }
    // Slot s holds part `part_in_slot[s]` (a leaf's low 5 bits index the
    // root's primitives, which are the part numbers).
    let mut part_in_slot = [usize::MAX; GROUPS];
    for (slot, &meta) in root.child_meta.iter().enumerate() {
        if meta != 0 {
            let k = root.primitive_base_idx as usize + (meta & 0b1_1111) as usize;
            part_in_slot[slot] = *top.primitive_indices.get(k)? as usize;
        }
    }
    let node_count: usize = parts.iter().flatten().map(|p| p.nodes.len()).sum::<usize>() + 1;
    let prim_count: usize = parts
        .iter()
        .flatten()
        .map(|p| p.primitive_indices.len())
        .sum();
    let mut nodes = Vec::with_capacity(node_count);
    let mut primitive_indices = Vec::with_capacity(prim_count);
    // Layout: the root, the parts' roots in slot order (a node's inner
    // children are contiguous, in slot order), then each part's other
    // nodes.
    nodes.push(root);
    nodes.resize(1 + parts.len(), root);
    let mut rest_base = 1 + parts.len();
    let mut total = Aabb::empty();
    for (rank, &p) in part_in_slot
        .iter()
        .filter(|&&p| p != usize::MAX)
        .enumerate()
    {
        let part = parts[p].take()?;
        total = total.union(&part.total_aabb);
        // Part node k ≥ 1 moves to rest_base + k − 1; its root to 1 + rank.
        let node_shift = rest_base as u32 - 1;
        let prim_shift = primitive_indices.len() as u32;
        nodes[1 + rank] = shifted(&part.nodes[0], node_shift, prim_shift);
        nodes.extend(
            part.nodes[1..]
                .iter()
                .map(|node| shifted(node, node_shift, prim_shift)),
        );
        primitive_indices.extend_from_slice(&part.primitive_indices);
        rest_base += part.nodes.len() - 1;
    }
    root.imask = 0;
    for (slot, &p) in part_in_slot.iter().enumerate() {
        if p != usize::MAX {
            root.imask |= 1 << slot;
            root.child_meta[slot] = inner_child_meta(slot);
        }
    }
    root.child_base_idx = 1;
    root.primitive_base_idx = 0;
    nodes[0] = root;
    Some(CwBvh {
        nodes,
        primitive_indices,
        total_aabb: total,
        exact_node_aabbs: None,
        uses_spatial_splits: false,
    })
}

/// The deepest a ray's traversal goes: obvhs's traversal stack holds 32
/// entries and, when full, overwrites its last one (a subtree would be
/// skipped), so a tree must be shallower than that.
pub const MAX_DEPTH: u32 = 31;

/// Primitives per part of [`balanced`]: obvhs's tree over this many
/// primitives stays shallow whatever their boxes.
const BALANCED_PART: usize = 24;

/// A tree whose depth is bounded whatever the boxes: median splits down to
/// parts of at most [`BALANCED_PART`] primitives. For boxes that obvhs's
/// clustering cannot separate (thousands in one place), where its own tree
/// grows deeper than [`MAX_DEPTH`].
pub fn balanced(aabbs: &[Aabb], params: BvhBuildParams) -> CwBvh {
    build_cwbvh_in_parts(aabbs, params, BALANCED_PART * GROUPS, Split::Median)
}

/// The depth of `tree` (1 for a root alone; 0 when empty).
pub fn depth(tree: &CwBvh) -> u32 {
    if tree.nodes.is_empty() {
        return 0;
    }
    let mut deepest = 0;
    let mut stack = vec![(0usize, 1u32)];
    while let Some((index, depth)) = stack.pop() {
        deepest = deepest.max(depth);
        let Some(node) = tree.nodes.get(index) else {
            continue;
        };
        for k in 0..node.imask.count_ones() as usize {
            stack.push((node.child_base_idx as usize + k, depth + 1));
        }
    }
    deepest
}

/// `node` with its children and primitives moved by the given offsets.
fn shifted(node: &CwBvhNode, node_shift: u32, prim_shift: u32) -> CwBvhNode {
    CwBvhNode {
        child_base_idx: node.child_base_idx + node_shift,
        primitive_base_idx: node.primitive_base_idx + prim_shift,
        ..*node
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes::test_support::TestRng;

    fn random_boxes(n: usize, seed: u64) -> Vec<Aabb> {
        let mut rng = TestRng::new(seed);
        let mut point = || Vec3A::new(rng.uniform(), rng.uniform(), rng.uniform());
        (0..n)
            .map(|_| {
                let c = point() * 10.0;
                let h = point() * 0.05;
                Aabb::new(c - h, c + h)
            })
            .collect()
    }

    #[test]
    fn eight_parts_make_a_valid_tree_over_every_primitive() {
        let boxes = random_boxes(5000, 3);
        let tree =
            build_cwbvh_in_parts(&boxes, BvhBuildParams::medium_build(), 1000, Split::Median);
        // Joined, not the one-piece fallback: the root's children are the
        // parts' roots.
        assert_eq!(tree.nodes[0].imask, 0xff);
        let mut seen = tree.primitive_indices.clone();
        seen.sort_unstable();
        assert_eq!(seen, (0..boxes.len() as u32).collect::<Vec<_>>());
        let result = tree.validate(&boxes, false);
        assert_eq!(result.discovered_primitives.len(), boxes.len());
    }

    /// The keys order as `f32::total_cmp` does, across signs, zeros,
    /// subnormals and infinities.
    #[test]
    fn ordered_bits_keep_the_order_of_floats() {
        let values = [
            f32::NEG_INFINITY,
            -3.5e30,
            -2.0,
            -1.0e-40,
            -0.0,
            0.0,
            1.0e-40,
            0.5,
            1.0,
            7.0e12,
            f32::INFINITY,
        ];
        for a in values {
            for b in values {
                assert_eq!(
                    ordered_bits(a).cmp(&ordered_bits(b)),
                    a.total_cmp(&b),
                    "{a} against {b}"
                );
            }
        }
    }

    /// Two clusters, 300 boxes around x = 0 and 30 around x = 10: the
    /// surface-area split falls in the gap between them, the median inside
    /// the larger one.
    #[test]
    fn the_surface_area_split_separates_clusters() {
        let mut boxes = random_boxes(330, 7);
        for b in &mut boxes[300..] {
            *b = Aabb::new(b.min * 0.1 + Vec3A::X * 10.0, b.max * 0.1 + Vec3A::X * 10.0);
        }
        for b in &mut boxes[..300] {
            *b = Aabb::new(b.min * 0.1, b.max * 0.1);
        }
        let members = Member::all(&boxes);
        let lo = boxes.iter().fold(Vec3A::INFINITY, |a, b| a.min(b.center()));
        let hi = boxes
            .iter()
            .fold(Vec3A::NEG_INFINITY, |a, b| a.max(b.center()));
        let plane = surface_area_split(&members, &boxes, 0, lo, hi);
        assert_eq!(plane.map(|p| p.left_count), Some(300));
    }

    /// The bins' halves, taken in one pass, are the halves that selecting
    /// the same number of smallest centroids gives: the bins are in the
    /// centroids' order.
    #[test]
    fn the_bins_halves_are_the_smallest_centroids() {
        let boxes = random_boxes(5000, 3);
        let members = Member::all(&boxes);
        let lo = boxes.iter().fold(Vec3A::INFINITY, |a, b| a.min(b.center()));
        let hi = boxes
            .iter()
            .fold(Vec3A::NEG_INFINITY, |a, b| a.max(b.center()));
        for axis in 0..3 {
            let plane = surface_area_split(&members, &boxes, axis, lo, hi).unwrap();
            let (mut by_bins, mut selected) = (members.clone(), members.clone());
            let left = partition(&mut by_bins, |m| plane.goes_left(m));
            assert_eq!(left, plane.left_count);
            assert!(left > 0 && left < members.len());
            select(&mut selected, left, axis);
            let sorted = |half: &[Member]| {
                let mut indices: Vec<u32> = half.iter().map(|m| m.index).collect();
                indices.sort_unstable();
                indices
            };
            assert_eq!(sorted(&by_bins[..left]), sorted(&selected[..left]));
        }
    }

    /// Parts in parts (three levels here) with surface-area splits: a valid
    /// tree over every primitive.
    #[test]
    fn parts_of_parts_make_a_valid_tree_over_every_primitive() {
        let boxes = random_boxes(20_000, 11);
        let tree = build_cwbvh_in_parts(
            &boxes,
            BvhBuildParams::medium_build(),
            100,
            Split::SurfaceArea,
        );
        let mut seen = tree.primitive_indices.clone();
        seen.sort_unstable();
        assert_eq!(seen, (0..boxes.len() as u32).collect::<Vec<_>>());
        let result = tree.validate(&boxes, false);
        assert_eq!(result.discovered_primitives.len(), boxes.len());
        assert!(depth(&tree) <= MAX_DEPTH);
    }

    /// Boxes all in one place: obvhs's own tree is deeper than its
    /// traversal stack; the balanced one is not, and holds every primitive.
    #[test]
    fn coincident_boxes_get_a_balanced_tree() {
        let boxes = vec![Aabb::new(Vec3A::ZERO, Vec3A::ONE); 3000];
        let params = BvhBuildParams::medium_build();
        let whole = build_cwbvh_in_parts(&boxes, params, usize::MAX, Split::Median);
        assert!(depth(&whole) > MAX_DEPTH, "{}", depth(&whole));
        let tree = balanced(&boxes, params);
        // Two levels of parts (375, then 47 boxes) over obvhs trees of 47.
        assert!(depth(&tree) <= 12, "{}", depth(&tree));
        let result = tree.validate(&boxes, false);
        assert_eq!(result.discovered_primitives.len(), boxes.len());
        assert_eq!(result.max_depth + 1, depth(&tree));
    }
}
