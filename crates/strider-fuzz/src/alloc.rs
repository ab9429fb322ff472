//! A global allocator that refuses to let the heap grow past a cap, so that an input which
//! makes a parser allocate without bound aborts the fuzz run at once (leaving the input behind)
//! instead of swapping the machine to a halt.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

/// The system allocator with a cap on the bytes live at once. A target installs it with
/// `#[global_allocator] static ALLOC: CappedAlloc = CappedAlloc::new();`; the cap is read once
/// from `FUZZ_MEMORY_MB` by [`crate::fuzz`] (default [`CappedAlloc::DEFAULT_MB`]).
pub struct CappedAlloc {
    live: AtomicUsize,
    cap: AtomicUsize,
}

impl CappedAlloc {
    /// Default heap cap, MiB: above every limit the readers enforce themselves, well below the
    /// machine's memory, so the allocator only trips where a reader forgot to check a size.
    pub const DEFAULT_MB: usize = 6144;

    /// An allocator with no cap until [`CappedAlloc::set_cap_mb`] is called.
    pub const fn new() -> Self {
        Self {
            live: AtomicUsize::new(0),
            cap: AtomicUsize::new(usize::MAX),
        }
    }

    /// Sets the cap, MiB.
    pub fn set_cap_mb(&self, mb: usize) {
        self.cap
            .store(mb.saturating_mul(1 << 20), Ordering::Relaxed);
    }

    /// Bytes live now.
    pub fn live_bytes(&self) -> usize {
        self.live.load(Ordering::Relaxed)
    }

    fn reserve(&self, size: usize) -> bool {
        let before = self.live.fetch_add(size, Ordering::Relaxed);
        if before.saturating_add(size) > self.cap.load(Ordering::Relaxed) {
            self.live.fetch_sub(size, Ordering::Relaxed);
            return false;
        }
        true
    }
}

impl Default for CappedAlloc {
    fn default() -> Self {
        Self::new()
    }
}

// SAFETY: every call is forwarded to `System` unchanged; the counter only decides whether to
// forward an allocation at all, and a refused allocation returns null as the trait allows.
unsafe impl GlobalAlloc for CappedAlloc {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if !self.reserve(layout.size()) {
            return std::ptr::null_mut();
        }
        // SAFETY: forwarded with the caller's layout.
        let p = unsafe { System.alloc(layout) };
        if p.is_null() {
            self.live.fetch_sub(layout.size(), Ordering::Relaxed);
        }
        p
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        if !self.reserve(layout.size()) {
            return std::ptr::null_mut();
        }
        // SAFETY: forwarded with the caller's layout.
        let p = unsafe { System.alloc_zeroed(layout) };
        if p.is_null() {
            self.live.fetch_sub(layout.size(), Ordering::Relaxed);
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: `ptr` came from `System` with this layout.
        unsafe { System.dealloc(ptr, layout) };
        self.live.fetch_sub(layout.size(), Ordering::Relaxed);
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let old = layout.size();
        if new_size > old && !self.reserve(new_size - old) {
            return std::ptr::null_mut();
        }
        // SAFETY: `ptr` came from `System` with `layout`.
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        if p.is_null() {
            if new_size > old {
                self.live.fetch_sub(new_size - old, Ordering::Relaxed);
            }
        } else if new_size < old {
            self.live.fetch_sub(old - new_size, Ordering::Relaxed);
        }
        p
    }
}
