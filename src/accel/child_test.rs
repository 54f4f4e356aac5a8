//! How a ray query tests the eight children of a BVH node at once.
//!
//! obvhs's test ([`Portable`]) runs on any x86-64 (SSE2): two passes of four
//! children, each child's quantised box bytes converted to floats one by
//! one. Where the processor has AVX2 ([`Avx2`], x86-64-v3's copy of the
//! queries, `InstructionSet`), all eight children are tested in one pass,
//! each axis's eight bytes widened to eight floats by two instructions.
//! Traversal is most of a hair render's time (hair-eumel-2-256: 40 % of
//! its CPU samples), and the node test most of traversal.
//!
//! Both compute the same floats in the same order (a multiply, then an
//! add; the same minima and maxima), so they find the same children, bit
//! for bit (tested), and the images do not depend on which runs.

use obvhs::cwbvh::node::CwBvhNode;
use obvhs::ray::Ray;

/// The nearest a child's box may be entered (obvhs's `EPSILON`: its
/// traversal ignores boxes behind this distance).
const NEAREST: f32 = 0.0001;

/// Tests a node's children against a ray.
pub trait ChildTest: Copy {
    /// obvhs's hit mask for `node`: the children `ray` enters, inner
    /// children in the high byte (by traversal priority), leaf primitives
    /// in the low 24 bits.
    fn hits(self, node: &CwBvhNode, ray: &Ray, oct_inv4: u32) -> u32;
}

/// obvhs's own test (SSE2).
#[derive(Clone, Copy, Debug)]
pub struct Portable;

impl ChildTest for Portable {
    #[inline(always)]
    fn hits(self, node: &CwBvhNode, ray: &Ray, oct_inv4: u32) -> u32 {
        node.intersect_ray(ray, oct_inv4)
    }
}

/// The eight-wide test with AVX2: made only where the processor has
/// x86-64-v3's features, so holding one is the proof that it may run.
#[cfg(target_arch = "x86_64")]
#[derive(Clone, Copy, Debug)]
pub struct Avx2(());

#[cfg(target_arch = "x86_64")]
impl Avx2 {
    /// The test, where this processor has x86-64-v3's features.
    pub fn detect() -> Option<Self> {
        (super::InstructionSet::detect() == super::InstructionSet::X86_64V3).then_some(Avx2(()))
    }

    /// The test, without checking.
    ///
    /// # Safety
    /// The processor must have x86-64-v3's features
    /// (`InstructionSet::detect`).
    pub unsafe fn new_unchecked() -> Self {
        Avx2(())
    }
}

#[cfg(target_arch = "x86_64")]
impl ChildTest for Avx2 {
    #[inline(always)]
    fn hits(self, node: &CwBvhNode, ray: &Ray, oct_inv4: u32) -> u32 {
        // SAFETY: an `Avx2` exists only where the processor has the
        // features `hits_avx2` is compiled for.
        unsafe { hits_avx2(node, ray, oct_inv4) }
    }
}

/// Eight bytes widened to eight floats.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,avx2,fma,bmi1,bmi2,lzcnt,popcnt,sse3,ssse3,sse4.1,sse4.2")]
#[inline]
unsafe fn widen(bytes: &[u8; 8]) -> std::arch::x86_64::__m256 {
    use std::arch::x86_64::*;
    // SAFETY: an unaligned 8-byte load from an 8-byte array; the rest are
    // register operations this function's features provide.
    unsafe {
        let packed = _mm_loadl_epi64(bytes.as_ptr().cast());
        _mm256_cvtepi32_ps(_mm256_cvtepu8_epi32(packed))
    }
}

/// [`ChildTest::hits`] over all eight children at once: obvhs's
/// `intersect_ray_simd` with eight lanes.
///
/// # Safety
/// The processor must have the features named.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,avx2,fma,bmi1,bmi2,lzcnt,popcnt,sse3,ssse3,sse4.1,sse4.2")]
#[inline]
unsafe fn hits_avx2(node: &CwBvhNode, ray: &Ray, oct_inv4: u32) -> u32 {
    use std::arch::x86_64::*;
    let scale = node.compute_extent() * ray.inv_direction;
    let offset = (glam::Vec3A::from(node.p) - ray.origin) * ray.inv_direction;
    // The near and far planes of each axis: the low bytes, unless the ray
    // runs towards the axis's negative side.
    let planes = |negative: bool, low: &[u8; 8], high: &[u8; 8]| {
        if negative {
            (*high, *low)
        } else {
            (*low, *high)
        }
    };
    let (near_x, far_x) = planes(ray.direction.x < 0.0, &node.child_min_x, &node.child_max_x);
    let (near_y, far_y) = planes(ray.direction.y < 0.0, &node.child_min_y, &node.child_max_y);
    let (near_z, far_z) = planes(ray.direction.z < 0.0, &node.child_min_z, &node.child_max_z);
    let (child_bits, bit_index) = node.get_child_and_index_bits(oct_inv4);
    // SAFETY: register operations this function's features provide.
    unsafe {
        // A multiply, then an add: obvhs's arithmetic (no fused form).
        let distance = |bytes: &[u8; 8], scale: f32, offset: f32| {
            _mm256_add_ps(
                _mm256_mul_ps(widen(bytes), _mm256_set1_ps(scale)),
                _mm256_set1_ps(offset),
            )
        };
        let t_near_x = distance(&near_x, scale.x, offset.x);
        let t_far_x = distance(&far_x, scale.x, offset.x);
        let t_near_y = distance(&near_y, scale.y, offset.y);
        let t_far_y = distance(&far_y, scale.y, offset.y);
        let t_near_z = distance(&near_z, scale.z, offset.z);
        let t_far_z = distance(&far_z, scale.z, offset.z);
        // obvhs's operand order (it decides which operand a NaN yields).
        let t_near = _mm256_max_ps(t_near_x, _mm256_max_ps(t_near_y, t_near_z));
        let t_far = _mm256_min_ps(t_far_x, _mm256_min_ps(t_far_y, t_far_z));
        let t_near = _mm256_max_ps(t_near, _mm256_set1_ps(NEAREST));
        let t_far = _mm256_min_ps(t_far, _mm256_set1_ps(ray.tmax));
        let entered = _mm256_castps_si256(_mm256_cmp_ps::<_CMP_LE_OS>(t_near, t_far));
        // Each entered child's bits (byte k of `child_bits`) moved to its
        // place in the mask (byte k of `bit_index`, below 32), all eight
        // lanes at once and ORed together: obvhs loops over the entered
        // children instead, a loop whose count the processor mispredicts
        // (a quarter of the closest-hit query's mispredicted branches).
        let bytes = |eight: u64| _mm256_cvtepu8_epi32(_mm_cvtsi64_si128(eight as i64));
        let placed = _mm256_and_si256(
            _mm256_sllv_epi32(bytes(child_bits), bytes(bit_index)),
            entered,
        );
        let four = _mm_or_si128(
            _mm256_castsi256_si128(placed),
            _mm256_extracti128_si256::<1>(placed),
        );
        let two = _mm_or_si128(four, _mm_unpackhi_epi64(four, four));
        let one = _mm_or_si128(two, _mm_shuffle_epi32::<0b01>(two));
        _mm_cvtsi128_si32(one) as u32
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes::test_support::TestRng;
    use glam::Vec3A;
    use obvhs::cwbvh::CwBvh;

    /// Random nodes (every byte random, extents from tiny to large) and
    /// rays (some components zero or negative zero, some short): both
    /// tests give the same mask.
    #[test]
    #[cfg(target_arch = "x86_64")]
    fn both_tests_find_the_same_children() {
        let Some(avx2) = Avx2::detect() else {
            eprintln!("skipped: this processor has no x86-64-v3 instructions");
            return;
        };
        let mut rng = TestRng::new(17);
        let mut byte = || (rng.uniform() * 256.0) as u8;
        let mut differing = 0;
        let mut entered = 0;
        for n in 0..200_000 {
            let bytes: [[u8; 8]; 7] = [[0; 8]; 7].map(|b| b.map(|_| byte()));
            // Child boxes mostly the right way round (a few empty).
            let ordered = |a: [u8; 8], b: [u8; 8]| {
                let (mut low, mut high) = (a, b);
                for k in 0..8 {
                    (low[k], high[k]) = (a[k].min(b[k]), a[k].max(b[k]));
                }
                (low, high)
            };
            let (min_x, max_x) = ordered(bytes[1], bytes[2]);
            let (min_y, max_y) = ordered(bytes[3], bytes[4]);
            let (min_z, max_z) = ordered(bytes[5], bytes[6]);
            let node = CwBvhNode {
                p: glam::Vec3::splat(-2.0),
                // Nodes 2 to 32 units wide, around the rays' origins.
                e: [0; 3].map(|_| byte() % 5 + 120),
                imask: byte(),
                child_base_idx: 0,
                primitive_base_idx: 0,
                // Every child present (a leaf or an inner node).
                child_meta: bytes[0].map(|m| m | 0b0010_0000),
                child_min_x: min_x,
                child_max_x: max_x,
                child_min_y: min_y,
                child_max_y: max_y,
                child_min_z: min_z,
                child_max_z: max_z,
            };
            let component = |k: u8| match k % 7 {
                0 => 0.0,
                1 => -0.0,
                _ => (k as f32 - 128.0) / 64.0,
            };
            let direction = Vec3A::new(component(byte()), component(byte()), component(byte()));
            let direction = if direction.length_squared() == 0.0 {
                Vec3A::X
            } else {
                direction + Vec3A::ZERO
            };
            let origin = Vec3A::new(byte() as f32, byte() as f32, byte() as f32) / 64.0 - 2.0;
            let t_max = if n % 3 == 0 { 0.5 } else { f32::INFINITY };
            let ray = Ray::new(origin, direction, 0.0, t_max);
            let oct_inv4 = CwBvh::default().new_traversal(ray.direction).oct_inv4;
            let theirs = Portable.hits(&node, &ray, oct_inv4);
            let ours = avx2.hits(&node, &ray, oct_inv4);
            differing += usize::from(theirs != ours);
            entered += usize::from(theirs != 0);
        }
        assert_eq!(differing, 0);
        assert!(
            entered > 20_000,
            "{entered} nodes entered: the test should enter some"
        );
    }
}
