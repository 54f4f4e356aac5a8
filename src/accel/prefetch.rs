//! A hint to the CPU to start loading memory that will be read soon.

/// Starts loading the cache line holding the start of `value` into all
/// cache levels, without waiting for it (a no-op where the target has no
/// prefetch instruction). A hint only: it never faults and changes no
/// result.
#[inline(always)]
pub fn prefetch<T>(value: &T) {
    prefetch_address((value as *const T).cast());
}

/// [`prefetch`] of whatever lies at `address`, which need not be valid:
/// the hint never faults, so a caller can skip bounds checks (an address
/// past an array only loads a line for nothing).
#[inline(always)]
pub fn prefetch_address(address: *const u8) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: a prefetch reads nothing the program sees and cannot fault,
    // whatever the address.
    unsafe {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        _mm_prefetch::<_MM_HINT_T0>(address.cast::<i8>());
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = address;
}
