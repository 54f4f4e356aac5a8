//! The process's memory: its peak as the operating system counts it, and
//! handing freed memory back while a scene is built.
//!
//! glibc's allocator keeps what a program frees for later allocations: the
//! many small blocks of a scene description, or the runs' shape storage
//! once appended, stay resident after they are freed, and the next phase's
//! large arrays (mapped afresh) add to them. Trimming after a phase frees
//! makes the process's peak the larger of its phases', not their sum.
//!
//! With the environment variable `RPBRT_MEMORY_PHASES` set, each phase's
//! end prints the peak resident memory during the phase and what stays
//! resident after the trim (the figures of docs/performance-notes.md,
//! "Memory at scale") and the seconds since the previous phase; the peak is then reset for the next phase, so
//! `--stats`'s peak is the last phase's.

use std::alloc::{GlobalAlloc, Layout, System};

/// Blocks of at least this many bytes are mapped on their own and unmapped
/// when freed.
const MAP_ON_THEIR_OWN: i32 = 128 << 10;

/// Makes glibc's allocator hand every large block back to the operating
/// system when it is freed (nothing elsewhere). By default glibc raises
/// its threshold for such blocks up to 32 MB as large blocks are freed,
/// and keeps blocks under it in per-thread arenas for reuse: the build's
/// arrays freed by 16 threads then stay resident beside the next phase's
/// (hair-eumel-2-256 at 16 threads: peak 234 → 178 MB; 161 → 146 MB at 2
/// threads; the 120 MB curve file 918 → 903 MB). Call once, before any
/// thread starts.
pub fn return_large_blocks_when_freed() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: mallopt only sets an allocator parameter; called before any
    // other thread exists.
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, MAP_ON_THEIR_OWN);
    }
}

/// The system's allocator, asking the kernel to back large blocks with
/// huge pages (2 MB) where it gives them on request (Linux's transparent
/// huge pages in their `madvise` mode, the common default; nothing
/// elsewhere). A scene of millions of primitives fills arrays of hundreds
/// of megabytes (curve pieces, primitives, boxes, the BVH and obvhs's
/// working arrays), and with 4 kB pages each page's first write is a
/// fault: 120 MB of random curves took 570,000 of them and over a second
/// of system time. The blocks are written whole once made, so the peak
/// is the same.
pub struct HugePageAllocator;

/// Blocks from this size on (a huge page's, on x86-64 and AArch64 Linux)
/// are advised, as glibc's own `glibc.malloc.hugetlb=1` does: the kernel
/// backs the aligned huge pages inside them.
const ADVISED_FROM: usize = 2 << 20;

/// `block` (of `size` bytes, or null), its pages advised when it is large.
fn advised(block: *mut u8, size: usize) -> *mut u8 {
    if !block.is_null() && size >= ADVISED_FROM {
        advise_huge_pages(block, size);
    }
    block
}

/// Advises the pages of `size` bytes from `block`.
fn advise_huge_pages(block: *mut u8, size: usize) {
    #[cfg(target_os = "linux")]
    {
        const PAGE: usize = 4096;
        let start = block as usize / PAGE * PAGE;
        let end = block as usize + size;
        // SAFETY: the range covers a block the allocator has just handed
        // out (from the start of its first page); the advice changes how
        // pages are backed, not their contents, and a refusal (huge pages
        // off, another page size) is harmless.
        unsafe {
            libc::madvise(start as *mut libc::c_void, end - start, libc::MADV_HUGEPAGE);
        }
    }
    #[cfg(not(target_os = "linux"))]
    let _ = (block, size);
}

// SAFETY: every call goes to the system's allocator with the same
// arguments; the advice only follows a block's allocation.
unsafe impl GlobalAlloc for HugePageAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // SAFETY: the caller's contract, passed on.
        advised(unsafe { System.alloc(layout) }, layout.size())
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        // SAFETY: the caller's contract, passed on.
        advised(unsafe { System.alloc_zeroed(layout) }, layout.size())
    }

    unsafe fn dealloc(&self, block: *mut u8, layout: Layout) {
        // SAFETY: the caller's contract, passed on.
        unsafe { System.dealloc(block, layout) }
    }

    unsafe fn realloc(&self, block: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        if layout.size() < ADVISED_FROM && new_size >= ADVISED_FROM {
            // Grown past the threshold: a new block, advised before the
            // contents are copied in (glibc's realloc would copy them into
            // small pages first). A block already advised keeps the advice
            // when glibc moves its mapping.
            // SAFETY: `new_size` is non-zero and, rounded to the alignment,
            // within isize (the caller's contract).
            let new_layout = unsafe { Layout::from_size_align_unchecked(new_size, layout.align()) };
            // SAFETY: as `alloc`'s.
            let moved = unsafe { self.alloc(new_layout) };
            if !moved.is_null() {
                // SAFETY: both blocks are live and at least `layout.size()`
                // long; they do not overlap.
                unsafe {
                    std::ptr::copy_nonoverlapping(block, moved, layout.size());
                    System.dealloc(block, layout);
                }
            }
            return moved;
        }
        // SAFETY: the caller's contract, passed on.
        unsafe { System.realloc(block, layout, new_size) }
    }
}

/// Whether a thread started beside the pool's `pool_threads` and the main
/// thread still gets an allocator arena of its own: glibc makes at most
/// eight per core and then has threads share them, which changes where
/// the build's blocks land (hair-eumel-2-256 at 16 threads on 2 cores:
/// one thread more made the BVH phase's peak 6 MB higher).
pub fn another_thread_gets_its_own_arena(pool_threads: usize) -> bool {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    pool_threads + 2 <= 8 * cores
}

/// Returns freed heap memory to the operating system (glibc's
/// `malloc_trim`; nothing elsewhere) at the end of the build phase named
/// `phase`.
pub fn return_freed_memory(phase: &str) {
    let trace = std::env::var_os("RPBRT_MEMORY_PHASES").is_some();
    let peak = if trace { peak_memory_bytes() } else { None };
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: malloc_trim only releases free pages of the allocator's own
    // heaps; it has no preconditions.
    unsafe {
        libc::malloc_trim(0);
    }
    if trace {
        let mb = |b: Option<u64>| b.map_or("?".into(), |b| (b >> 20).to_string());
        eprintln!(
            "memory: {phase}: peak {} MB, then {} MB ({:.3} s)",
            mb(peak),
            mb(status_bytes("VmRSS:")),
            seconds_since_last_phase()
        );
        // Linux: writing 5 resets the high-water mark to the current size.
        let _ = std::fs::write("/proc/self/clear_refs", "5");
    }
}

/// Seconds since the previous phase ended (or since the first call).
fn seconds_since_last_phase() -> f64 {
    use std::sync::Mutex;
    use std::time::Instant;
    static LAST: Mutex<Option<Instant>> = Mutex::new(None);
    let now = Instant::now();
    let mut last = LAST.lock().unwrap_or_else(|e| e.into_inner());
    let seconds = last.map_or(0.0, |t| (now - t).as_secs_f64());
    *last = Some(now);
    seconds
}

/// Peak resident set size ("high water mark") of this process in bytes,
/// from `/proc/self/status` (Linux); `None` where that is unavailable.
pub fn peak_memory_bytes() -> Option<u64> {
    status_bytes("VmHWM:")
}

/// A `/proc/self/status` line such as `VmRSS:   1234 kB`, in bytes.
fn status_bytes(key: &str) -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    parse_status_bytes(&status, key)
}

fn parse_status_bytes(status: &str, key: &str) -> Option<u64> {
    let line = status.lines().find(|l| l.starts_with(key))?;
    let mut fields = line[key.len()..].split_whitespace();
    let value: u64 = fields.next()?.parse().ok()?;
    match fields.next() {
        Some("kB") => Some(value * 1024),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn reads_the_high_water_mark_and_the_resident_size() {
        let status = "Name:\trpbrt\nVmPeak:\t  99 kB\nVmHWM:\t   2048 kB\nVmRSS:\t 1 kB\n";
        assert_eq!(
            super::parse_status_bytes(status, "VmHWM:"),
            Some(2048 * 1024)
        );
        assert_eq!(super::parse_status_bytes(status, "VmRSS:"), Some(1024));
        assert_eq!(super::parse_status_bytes("Name: x\n", "VmHWM:"), None);
    }
}
