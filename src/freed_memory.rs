//! Giving the system back the memory a large phase freed.
//!
//! glibc's allocator keeps the small blocks a program frees, in the middle
//! of its heaps, for the program's own later use: resident memory does not
//! fall when they are freed. Loading a million quads' OBJ (its text, faces
//! and the coplanar merge) frees about 684 MiB that would otherwise stay
//! resident through the whole solve, beside what meshing's per-surface
//! lists free. `malloc_trim`
//! returns every free page of every heap; it takes 10–60 ms on a building,
//! so it is asked for only between phases, where a large one ends: after
//! loading, after the rooms are found, after meshing, and before an
//! image's ambient term (what the shots freed).
//!
//! Elsewhere (other C libraries, other systems) this does nothing.

/// Returns the allocator's free pages to the system (glibc's
/// `malloc_trim(0)`).
pub(crate) fn give_back_freed_memory() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: malloc_trim only releases pages the allocator holds free;
    // it takes no pointer and leaves every live allocation in place.
    unsafe {
        libc::malloc_trim(0);
    }
}
