//! A binary BVH made into obvhs's compressed 8-wide one (CWBVH): the same
//! tree as obvhs's `bvh2_to_cwbvh` makes, node for node (tested), in less
//! time.
//!
//! The conversion follows Ylitie, Karras and Laine 2017 ("Efficient
//! incoherent ray traversal on GPUs through compressed wide BVHs"): a cost
//! table over the binary tree says, for each node and each number of
//! subtrees it may be split into, whether it is a leaf, an inner node or
//! split among its children's slots; the wide nodes are then read off the
//! table from the root, each node's children placed in the slots their
//! direction from its centre suits (so that a ray visits them near to
//! far by its octant alone), and child boxes quantised to 8 bits.
//!
//! On a large scene it was a fifth of the build's CPU time (120 MB of
//! random curves, 4.8 million pieces). What differs from obvhs's code is
//! how, not what: the cost table is kept from one part of a parallel
//! build to the next (made afresh, it was faulted in page by page each
//! time), and each node's children are given their slots by vector
//! minima over all 64 child-and-slot costs instead of a branching scan of
//! them (the same greedy choice, ties broken alike).

use glam::{BVec4A, UVec3, Vec3A, Vec4};
use obvhs::bvh2::Bvh2;
use obvhs::cwbvh::node::CwBvhNode;
use obvhs::cwbvh::CwBvh;

/// A wide node's children.
const BRANCHING: usize = 8;

/// obvhs's quantisation: child boxes in 8-bit steps of the node's box.
const DENOM: f32 = 1.0 / 255.0;

/// A leaf's cost per primitive, relative to an inner node's (obvhs's).
const PRIMITIVE_COST: f32 = 0.3;

/// No slot or child.
const NONE: u32 = u32::MAX;

#[derive(Clone, Copy, Default, PartialEq, Eq)]
enum Kind {
    Leaf,
    Inner,
    /// Split among the parent's slots.
    #[default]
    Distribute,
}

/// One entry of the cost table: node `n`, at most `i + 1` subtrees.
#[derive(Clone, Copy, Default)]
struct Decision {
    cost: f32,
    kind: Kind,
    /// Subtrees (less one) given to the left and right child when split.
    left: u8,
    right: u8,
}

/// The conversion, its cost table kept for the next tree.
#[derive(Default)]
pub struct WideConversion {
    /// Seven entries per binary node (at most 1 … 7 subtrees).
    decisions: Vec<Decision>,
}

/// One tree's conversion in progress.
struct Output<'a> {
    binary: &'a Bvh2,
    decisions: &'a [Decision],
    nodes: Vec<CwBvhNode>,
    primitive_indices: Vec<u32>,
}

impl WideConversion {
    /// `binary` (one primitive per leaf, as obvhs's PLOC makes it) as a
    /// CWBVH of at most `max_per_leaf` (1 to 3) primitives per leaf, with
    /// children ordered by ray octant: `bvh2_to_cwbvh(binary,
    /// max_per_leaf, true, false)`.
    pub fn convert(&mut self, binary: &Bvh2, max_per_leaf: u32) -> CwBvh {
        if binary.nodes.is_empty() {
            return CwBvh::default();
        }
        // Every entry read is written first (`cost_of`): no clearing.
        self.decisions
            .resize(binary.nodes.len() * 7, Decision::default());
        cost_of(binary, &mut self.decisions, 0, max_per_leaf.clamp(1, 3));
        let capacity = binary.primitive_indices.len();
        let mut out = Output {
            binary,
            decisions: &self.decisions,
            nodes: Vec::with_capacity(capacity),
            primitive_indices: Vec::with_capacity(capacity),
        };
        out.nodes.push(CwBvhNode::default());
        out.wide_node(0, 0);
        CwBvh {
            nodes: out.nodes,
            primitive_indices: out.primitive_indices,
            total_aabb: *binary.nodes[0].aabb(),
            exact_node_aabbs: None,
            uses_spatial_splits: binary.uses_spatial_splits,
        }
    }
}

/// Fills the cost table of the subtree at `node`; returns its primitive
/// count. The arithmetic is obvhs's, in its order: the same costs to the
/// bit, hence the same tree.
fn cost_of(binary: &Bvh2, decisions: &mut [Decision], node: usize, max_per_leaf: u32) -> u32 {
    let binary_node = &binary.nodes[node];
    let half_area = binary_node.aabb().half_area();
    let first = binary_node.first_index as usize;
    let here = node * 7;
    if binary_node.prim_count != 0 {
        let count = binary_node.prim_count;
        let cost = half_area * (count as f32) * PRIMITIVE_COST;
        for decision in &mut decisions[here..here + 7] {
            decision.kind = Kind::Leaf;
            decision.cost = cost;
        }
        return count;
    }
    let count = cost_of(binary, decisions, first, max_per_leaf)
        + cost_of(binary, decisions, first + 1, max_per_leaf);
    let (left, right) = (first * 7, (first + 1) * 7);
    let left_costs: [f32; 7] = std::array::from_fn(|k| decisions[left + k].cost);
    let right_costs: [f32; 7] = std::array::from_fn(|k| decisions[right + k].cost);
    // At most one subtree: this node a leaf or an inner node.
    let cost_leaf = if count <= max_per_leaf {
        (count as f32) * half_area * PRIMITIVE_COST
    } else {
        f32::INFINITY
    };
    let (cost_distribute, split_left) = cheapest_split(&left_costs, &right_costs, 7, f32::INFINITY);
    let split_right = if split_left == u8::MAX {
        u8::MAX
    } else {
        6 - split_left
    };
    let cost_internal = cost_distribute + half_area;
    let (kind, cost) = if cost_leaf < cost_internal {
        (Kind::Leaf, cost_leaf)
    } else {
        (Kind::Inner, cost_internal)
    };
    let mut previous = Decision {
        cost,
        kind,
        left: split_left,
        right: split_right,
    };
    decisions[here] = previous;
    // At most i + 1 subtrees: as with i, or split between the children.
    for i in 1..7 {
        let (cost_distribute, split_left) =
            cheapest_split(&left_costs, &right_costs, i, previous.cost);
        let split = Decision {
            cost: cost_distribute,
            kind: Kind::Distribute,
            left: split_left,
            right: (i as u8).wrapping_sub(1).wrapping_sub(split_left),
        };
        previous = if split_left != u8::MAX {
            split
        } else {
            previous
        };
        decisions[here + i] = previous;
    }
    count
}

/// The cheapest split of `subtrees + 1` subtrees between a node's two
/// children: the left child's cost-table index `k` (at most `k + 1`
/// subtrees) and the right's `subtrees - 1 - k`, the first of equal ones;
/// `(cost, u8::MAX)` when none is cheaper than `cost`. Chosen by selects
/// rather than branches: which split is cheapest is a coin toss to the
/// branch predictor.
#[inline]
fn cheapest_split(left: &[f32; 7], right: &[f32; 7], subtrees: usize, mut cost: f32) -> (f32, u8) {
    let mut split_left = u8::MAX;
    for k in 0..subtrees {
        let c = left[k] + right[subtrees - 1 - k];
        let better = c < cost;
        cost = if better { c } else { cost };
        split_left = if better { k as u8 } else { split_left };
    }
    (cost, split_left)
}

impl Output<'_> {
    /// Writes wide node `wide` for binary node `node`, then its inner
    /// children's, depth first (obvhs's layout: a node's inner children
    /// contiguous, in slot order).
    fn wide_node(&mut self, wide: usize, node: usize) {
        let aabb = *self.binary.nodes[node].aabb();
        let mut out = self.nodes[wide];
        out.p = aabb.min.into();
        let e = ((aabb.max - aabb.min).max(Vec3A::splat(1e-20)) * DENOM)
            .log2()
            .ceil()
            .exp2();
        let rcp_e = 1.0 / e;
        // A power of two: its exponent's bits alone.
        let exponent: UVec3 = UVec3::new(e.x.to_bits(), e.y.to_bits(), e.z.to_bits()) >> 23u32;
        out.e = [exponent.x as u8, exponent.y as u8, exponent.z as u8];

        let mut children = [NONE; BRANCHING];
        let mut count = 0;
        self.subtrees(node, 0, &mut children, &mut count);
        order_by_direction(&self.binary.nodes, aabb.center(), &mut children, count);

        out.imask = 0;
        out.primitive_base_idx = self.primitive_indices.len() as u32;
        out.child_base_idx = self.nodes.len() as u32;
        let mut inner_children = 0;
        let mut primitives = 0u32;
        for (slot, &child) in children.iter().enumerate() {
            if child == NONE {
                continue;
            }
            let child_aabb = self.binary.nodes[child as usize].aabb();
            let lo = ((child_aabb.min - aabb.min) * rcp_e)
                .floor()
                .clamp(Vec3A::ZERO, Vec3A::splat(255.0));
            let hi = ((child_aabb.max - aabb.min) * rcp_e)
                .ceil()
                .clamp(Vec3A::ZERO, Vec3A::splat(255.0));
            out.child_min_x[slot] = lo.x as u8;
            out.child_min_y[slot] = lo.y as u8;
            out.child_min_z[slot] = lo.z as u8;
            out.child_max_x[slot] = hi.x as u8;
            out.child_max_y[slot] = hi.y as u8;
            out.child_max_z[slot] = hi.z as u8;
            if self.decisions[child as usize * 7].kind == Kind::Inner {
                out.imask |= 1 << slot;
                out.child_meta[slot] = 0b0010_0000 | (24 + slot as u8);
                inner_children += 1;
            } else {
                // A leaf: its primitives' count in unary in the high bits.
                let count = self.gather_primitives(child as usize);
                let unary = match count {
                    1 => 0b0010_0000,
                    2 => 0b0110_0000,
                    _ => 0b1110_0000,
                };
                out.child_meta[slot] = primitives as u8 | unary;
                primitives += count;
            }
        }
        self.nodes
            .resize(self.nodes.len() + inner_children, CwBvhNode::default());
        self.nodes[wide] = out;
        let mut rank = 0;
        for (slot, &child) in children.iter().enumerate() {
            if child != NONE && out.imask & (1 << slot) != 0 {
                self.wide_node(out.child_base_idx as usize + rank, child as usize);
                rank += 1;
            }
        }
    }

    /// The subtrees binary node `node` is split into when it may have at
    /// most `i + 1` (the cost table's choice), appended to `children`.
    fn subtrees(&self, node: usize, i: usize, children: &mut [u32; 8], count: &mut usize) {
        let binary_node = &self.binary.nodes[node];
        if binary_node.is_leaf() {
            children[*count] = node as u32;
            *count += 1;
            return;
        }
        let decision = self.decisions[node * 7 + i];
        let first = binary_node.first_index as usize;
        for (child, share) in [(first, decision.left), (first + 1, decision.right)] {
            if self.decisions[child * 7 + share as usize].kind == Kind::Distribute {
                self.subtrees(child, share as usize, children, count);
            } else {
                children[*count] = child as u32;
                *count += 1;
            }
        }
    }

    /// Appends the primitives under binary node `node` (one per leaf);
    /// returns how many.
    fn gather_primitives(&mut self, node: usize) -> u32 {
        let binary_node = &self.binary.nodes[node];
        if binary_node.is_leaf() {
            let first = binary_node.first_index as usize;
            self.primitive_indices
                .push(self.binary.primitive_indices[first]);
            return binary_node.prim_count;
        }
        let first = binary_node.first_index as usize;
        self.gather_primitives(first) + self.gather_primitives(first + 1)
    }
}

/// Slot s's octant diagonal: x, y, z negative where bits 2, 1, 0 of s are
/// set (obvhs's table).
const OCTANT_DIAGONALS: [Vec3A; 8] = [
    Vec3A::new(1.0, 1.0, 1.0),
    Vec3A::new(1.0, 1.0, -1.0),
    Vec3A::new(1.0, -1.0, 1.0),
    Vec3A::new(1.0, -1.0, -1.0),
    Vec3A::new(-1.0, 1.0, 1.0),
    Vec3A::new(-1.0, 1.0, -1.0),
    Vec3A::new(-1.0, -1.0, 1.0),
    Vec3A::new(-1.0, -1.0, -1.0),
];

/// Puts the first `count` of `children` into the slots whose ray octant
/// their direction from `center` suits, as obvhs does: greedily, the
/// child and slot whose cost (the direction's dot product with the
/// octant's diagonal) is least first, ties to the lower child then the
/// lower slot. Each child's eight costs are two four-lane vectors (slots
/// 0–3, 4–7), so each choice is a vector minimum, then the first child
/// and slot that hold it (the tie rule); a taken slot is ruled out in
/// every child with one blend.
fn order_by_direction(
    nodes: &[obvhs::bvh2::node::Bvh2Node],
    center: Vec3A,
    children: &mut [u32; 8],
    count: usize,
) {
    // A pair already ruled out (its child or slot taken), or a cost
    // obvhs never takes (at or above f32::MAX, its starting minimum: not
    // infinities or NaN).
    let taken = Vec4::splat(f32::INFINITY);
    let mut low = [taken; BRANCHING];
    let mut high = [taken; BRANCHING];
    for (c, &child) in children[..count].iter().enumerate() {
        let v = nodes[child as usize].aabb().center() - center;
        let cost = OCTANT_DIAGONALS.map(|diagonal| diagonal.dot(v));
        let usable = |costs: Vec4| Vec4::select(costs.cmplt(Vec4::splat(f32::MAX)), costs, taken);
        low[c] = usable(Vec4::from_slice(&cost[..4]));
        high[c] = usable(Vec4::from_slice(&cost[4..]));
    }
    let mut slot_of = [usize::MAX; BRANCHING];
    for _ in 0..count {
        let least = low
            .iter()
            .chain(&high)
            .fold(taken, |a, &b| a.min(b))
            .min_element();
        if least == f32::INFINITY {
            break;
        }
        let least = Vec4::splat(least);
        let Some((c, s)) = (0..count).find_map(|c| {
            let lanes = low[c].cmpeq(least).bitmask() | high[c].cmpeq(least).bitmask() << 4;
            (lanes != 0).then(|| (c, lanes.trailing_zeros() as usize))
        }) else {
            break;
        };
        slot_of[c] = s;
        (low[c], high[c]) = (taken, taken);
        let half = if s < 4 { &mut low } else { &mut high };
        let lane = BVec4A::new(s % 4 == 0, s % 4 == 1, s % 4 == 2, s % 4 == 3);
        for costs in half.iter_mut() {
            *costs = Vec4::select(lane, taken, *costs);
        }
    }
    let original = std::mem::replace(children, [NONE; BRANCHING]);
    let mut free_slots = (0..BRANCHING).filter(|s| !slot_of.contains(s));
    for (c, &child) in original[..count].iter().enumerate() {
        // A child left without a slot (only with costs beyond f32::MAX,
        // where obvhs would stop) takes the first free one.
        let slot = match slot_of[c] {
            usize::MAX => free_slots.next().unwrap_or(c),
            s => s,
        };
        children[slot] = child;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use obvhs::aabb::Aabb;
    use obvhs::bvh2::reinsertion::ReinsertionOptimizer;
    use obvhs::cwbvh::bvh2_to_cwbvh::bvh2_to_cwbvh;
    use obvhs::ploc::{PlocBuilder, PlocSearchDistance, SortPrecision};

    /// Random boxes: clustered, spread, and many coincident ones.
    fn boxes(n: usize, seed: u64) -> Vec<Aabb> {
        let mut state = seed | 1;
        let mut rnd = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 40) as f32 / (1u64 << 24) as f32
        };
        (0..n)
            .map(|i| {
                let c = match i % 5 {
                    0 => Vec3A::splat(0.25),
                    1 => Vec3A::new(rnd(), rnd(), rnd()) * 0.01,
                    _ => Vec3A::new(rnd(), rnd(), rnd()) * 10.0,
                };
                let half = Vec3A::new(rnd(), rnd(), rnd()) * 0.05;
                Aabb::new(c - half, c + half)
            })
            .collect()
    }

    /// The tree obvhs's own conversion makes, node for node, for trees
    /// built as the BVH builds them (PLOC, reinsertion), at every leaf
    /// size; the cost table reused from one tree to the next.
    #[test]
    fn the_same_tree_as_obvhs_makes() {
        let mut conversion = WideConversion::default();
        for (n, seed) in [
            (1, 1),
            (2, 2),
            (9, 3),
            (100, 4),
            (3000, 5),
            (20_000, 6),
            (700, 7),
        ] {
            let aabbs = boxes(n, seed);
            let mut binary = PlocBuilder::with_capacity(n).build(
                PlocSearchDistance::Minimum,
                &aabbs,
                (0..n as u32).collect(),
                SortPrecision::U64,
                0,
            );
            ReinsertionOptimizer::default().run(&mut binary, 0.05, None);
            for max_per_leaf in 1..=3 {
                let theirs = bvh2_to_cwbvh(&binary, max_per_leaf, true, false);
                let ours = conversion.convert(&binary, max_per_leaf);
                assert!(ours == theirs, "{n} boxes, {max_per_leaf} per leaf");
            }
        }
    }
}
