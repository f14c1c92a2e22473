//! A global allocator that counts allocations and reallocations, for the
//! no-allocation tests (each in a test binary of its own, so that no other
//! test's allocations are counted). Declared with `#[path]` by those
//! binaries only.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::atomic::{AtomicU64, Ordering};

pub struct Counting;

pub static ALLOCATIONS: AtomicU64 = AtomicU64::new(0);

thread_local! {
    /// Allocations made on this thread: for code that runs on the calling
    /// thread alone, counted without the test harness's own threads (whose
    /// bookkeeping right after a test starts lands in [`ALLOCATIONS`]).
    static ON_THIS_THREAD: Cell<u64> = const { Cell::new(0) };
}

/// Allocations and reallocations made so far on the calling thread.
#[allow(dead_code)]
pub fn on_this_thread() -> u64 {
    ON_THIS_THREAD.with(Cell::get)
}

fn count() {
    ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
    // A const-initialised cell with no destructor: no allocation, and
    // reachable for the thread's whole life.
    let _ = ON_THIS_THREAD.try_with(|c| c.set(c.get() + 1));
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count();
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count();
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;
