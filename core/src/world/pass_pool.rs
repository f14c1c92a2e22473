//! What a pass needs only while it runs, lent to the thread running it.
//!
//! A character's own passes mark which pairs they have tested
//! (`pipeline::pass::PassMarksOf`, started afresh by each pass), and the
//! passes against objects and between characters need a traversal stack,
//! their leaf pairs and two tables of prepared triangles
//! (`pipeline::pass::PassScratch`), none of it read after the pass. The
//! world keeps one set per thread of the pool stepping it (and one for a
//! caller outside it) instead of one per character and per character pair:
//! memory grows with the threads, not with the bodies (a 10k-vertex
//! humanoid's marks are about 400 KB, a pass's scratch 21 KB and up).
//!
//! Each set has marks for the largest character and, after every step,
//! room for twice the most leaf pairs any pass has needed and the largest
//! stack, so a step allocates nothing once the first has sized the sets,
//! unless it runs on more threads than before, a larger character was
//! added or one of its passes needs more than any pass before. (A room pass
//! keeps its own scratch: its leaf pairs are read after the step,
//! `CharacterView::room_leaf_pairs`.)

use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

use crate::pipeline::pass::{PassMarksOf, PassScratch};

/// What one pass borrows.
#[derive(Default)]
pub(crate) struct Lent {
    pub(crate) marks: PassMarksOf,
    pub(crate) scratch: PassScratch,
}

/// One [`Lent`] set per thread.
#[derive(Default)]
pub(crate) struct PassPool {
    sets: Vec<Mutex<Lent>>,
    triangles: usize,
    nodes: usize,
    /// The most leaf pairs and the deepest traversal stack a pass has
    /// needed so far.
    most_leaf_pairs: AtomicUsize,
    most_stack: AtomicUsize,
}

impl PassPool {
    /// Room for a character of `triangles` triangles and `nodes` tree nodes
    /// (sized at the next [`PassPool::prepare`]).
    pub(crate) fn fit(&mut self, triangles: usize, nodes: usize) {
        self.triangles = self.triangles.max(triangles);
        self.nodes = self.nodes.max(nodes);
    }

    /// A set for each of `threads` threads and one more, each with marks
    /// for the largest character (at a step's start).
    pub(crate) fn prepare(&mut self, threads: usize) {
        while self.sets.len() < threads + 1 {
            self.sets.push(Mutex::default());
        }
        for s in &mut self.sets {
            s.get_mut()
                .expect("no pass panicked")
                .marks
                .grow_to(self.triangles, self.nodes);
        }
        self.settle();
    }

    /// Gives every set room for twice the most leaf pairs and the largest
    /// stack any pass has needed (at a step's end, so that the sets a
    /// larger pass did not use catch up in the step that grew one).
    pub(crate) fn settle(&mut self) {
        let leaf_pairs = 2 * *self.most_leaf_pairs.get_mut();
        // A capacity, headroom included (`Workspace::reserve_headroom`):
        // matched, not doubled.
        let stack = *self.most_stack.get_mut();
        for s in &mut self.sets {
            let s = s.get_mut().expect("no pass panicked");
            s.scratch.reserve(leaf_pairs, stack);
        }
    }

    /// Runs `f` with a set no other pass holds: the calling pool thread's
    /// own, or the first free one.
    pub(crate) fn with<R>(&self, f: impl FnOnce(&mut Lent) -> R) -> R {
        let n = self.sets.len();
        let start = rayon::current_thread_index().map_or(n.saturating_sub(1), |i| i % n.max(1));
        for k in 0..n {
            if let Ok(mut lent) = self.sets[(start + k) % n].try_lock() {
                let r = f(&mut lent);
                self.note(&lent.scratch);
                return r;
            }
        }
        // More passes at once than threads (not seen: a pass runs no other
        // pass inside it): a set of its own, sized now.
        let mut own = Lent::default();
        own.marks.grow_to(self.triangles, self.nodes);
        let r = f(&mut own);
        self.note(&own.scratch);
        r
    }

    /// Remembers what a pass needed, for the next [`PassPool::prepare`].
    fn note(&self, scratch: &PassScratch) {
        let (leaf_pairs, stack) = scratch.needed();
        self.most_leaf_pairs
            .fetch_max(leaf_pairs, Ordering::Relaxed);
        self.most_stack.fetch_max(stack, Ordering::Relaxed);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sets_are_sized_for_the_largest_character_and_lent_apart() {
        let mut pool = PassPool::default();
        pool.fit(10, 20);
        pool.fit(5, 40);
        pool.prepare(2);
        assert_eq!(pool.sets.len(), 3);
        pool.with(|a| {
            assert!(a.marks.repeats.len() >= 10 && a.marks.groups.len() >= 40);
            // A second pass at the same time gets another set.
            let a_ptr: *const Lent = a;
            pool.with(|b| assert!(!std::ptr::eq(a_ptr, b)));
        });
    }
}
