//! Handing freed memory back to the operating system while a scene is
//! built.
//!
//! glibc's allocator keeps what a program frees for later allocations: the
//! many small blocks of a scene description, or the runs' shape storage
//! once appended, stay resident after they are freed, and the next phase's
//! large arrays (mapped afresh) add to them. Trimming after a phase frees
//! makes the process's peak the larger of its phases', not their sum.

/// Returns freed heap memory to the operating system (glibc's
/// `malloc_trim`; nothing elsewhere).
pub fn return_freed_memory() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: malloc_trim only releases free pages of the allocator's own
    // heaps; it has no preconditions.
    unsafe {
        libc::malloc_trim(0);
    }
}
