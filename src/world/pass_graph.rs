//! The passes of one frame as a graph, run on every thread of the pool with
//! no barrier between the room passes and the character–character passes.
//!
//! Each character's passes keep a fixed order (its own pass against the room
//! and the objects first, then its pairs in the order given), because a pass
//! refits and skins its characters on demand and the per-kind counters say
//! which pass did that first. Within that order any pass whose characters
//! are free runs at once: a frame is not held back by rounds, and a heavy
//! character pair runs beside other characters' room passes.
//!
//! Which ready pass a free thread takes is a matter of speed only, never of
//! results: the one with the longest chain of estimated work behind it
//! (last frame's times, the critical path), so the heaviest chain starts
//! first. Nothing here allocates once the first frame has sized it.

use std::sync::Mutex;
use std::sync::atomic::{AtomicU32, AtomicUsize, Ordering};
use std::time::Instant;

const NONE: u32 = u32::MAX;

/// A frame's passes: `characters` passes `0..n` (each character against the
/// room and objects), then one pass per character pair.
#[derive(Default)]
pub struct PassGraph {
    characters: usize,
    /// Per pass: the passes that wait for it (at most two).
    next: Vec<[u32; 2]>,
    /// Per pass: how many passes it waits for (0 to 2).
    waits: Vec<u8>,
    /// Per pass: its estimated cost plus the longest estimated chain after it.
    priority: Vec<f32>,
    /// Per character: its last pass so far while the graph is built.
    last: Vec<u32>,
    /// Last measured seconds of each character's own pass, and of each pair
    /// `(i, j)` at `i * n + j`.
    room_cost: Vec<f32>,
    pair_cost: Vec<f32>,
    /// This frame's pairs, in pass order.
    pairs: Vec<(u32, u32)>,
    // While running.
    pending: Vec<AtomicU32>,
    seconds: Vec<AtomicU32>,
    ready: Mutex<Vec<u32>>,
    done: AtomicUsize,
}

impl PassGraph {
    /// A graph for `n` characters, sized for every pair.
    pub fn new(n: usize) -> Self {
        let most = n + n * n.saturating_sub(1) / 2;
        Self {
            characters: n,
            next: Vec::with_capacity(most),
            waits: Vec::with_capacity(most),
            priority: Vec::with_capacity(most),
            last: Vec::with_capacity(n),
            room_cost: vec![0.0; n],
            pair_cost: vec![0.0; n * n],
            pairs: Vec::with_capacity(most - n),
            pending: (0..most).map(|_| AtomicU32::new(0)).collect(),
            seconds: (0..most).map(|_| AtomicU32::new(0)).collect(),
            ready: Mutex::new(Vec::with_capacity(most)),
            done: AtomicUsize::new(0),
        }
    }

    /// Sets this frame's character pairs, `(i, j)` with `i < j`; each
    /// character meets its pairs in this order, after its own pass.
    pub fn set_pairs(&mut self, pairs: impl IntoIterator<Item = (u32, u32)>) {
        let n = self.characters;
        self.next.clear();
        self.waits.clear();
        self.pairs.clear();
        self.last.clear();
        for c in 0..n {
            self.next.push([NONE; 2]);
            self.waits.push(0);
            self.last.push(c as u32);
        }
        for (i, j) in pairs {
            let t = self.next.len() as u32;
            self.pairs.push((i, j));
            self.next.push([NONE; 2]);
            self.waits.push(2);
            for c in [i, j] {
                let before = self.last[c as usize] as usize;
                let slot = self.next[before].iter().position(|&s| s == NONE);
                // A pass has at most one successor per character it holds.
                self.next[before][slot.expect("at most two successors")] = t;
                self.last[c as usize] = t;
            }
        }
        // Priorities from the end (pass order is topological).
        let total = self.next.len();
        self.priority.clear();
        self.priority.resize(total, 0.0);
        for t in (0..total).rev() {
            let after = self.next[t]
                .iter()
                .filter(|&&s| s != NONE)
                .map(|&s| self.priority[s as usize])
                .fold(0.0, f32::max);
            self.priority[t] = self.cost(t) + after;
        }
    }

    /// Passes this frame.
    pub fn len(&self) -> usize {
        self.next.len()
    }

    pub fn is_empty(&self) -> bool {
        self.next.is_empty()
    }

    /// Character pair of pass `t` (`None` for a character's own pass).
    pub fn pair(&self, t: usize) -> Option<(u32, u32)> {
        t.checked_sub(self.characters).map(|k| self.pairs[k])
    }

    fn cost(&self, t: usize) -> f32 {
        match self.pair(t) {
            None => self.room_cost[t],
            Some((i, j)) => self.pair_cost[i as usize * self.characters + j as usize],
        }
    }

    /// Runs every pass with `run(t, pair)` (`pair` as [`PassGraph::pair`]
    /// says), on every thread of the current rayon pool, each as soon as the
    /// passes it waits for are done. Returns when all are done.
    pub fn run(&mut self, run: impl Fn(usize, Option<(u32, u32)>) + Sync) {
        let total = self.len();
        {
            let ready = self.ready.get_mut().expect("no pass panicked");
            ready.clear();
            for t in 0..total {
                self.pending[t].store(u32::from(self.waits[t]), Ordering::Relaxed);
                if self.waits[t] == 0 {
                    ready.push(t as u32);
                }
            }
        }
        self.done.store(0, Ordering::Relaxed);
        let this = &*self;
        let worker = || this.work(total, &run);
        workers(rayon::current_num_threads().min(total.max(1)), &worker);
        // Costs for the next frame's priorities.
        for t in 0..total {
            let s = f32::from_bits(self.seconds[t].load(Ordering::Relaxed));
            match self.pair(t) {
                None => self.room_cost[t] = s,
                Some((i, j)) => self.pair_cost[i as usize * self.characters + j as usize] = s,
            }
        }
    }

    fn work(&self, total: usize, run: &(impl Fn(usize, Option<(u32, u32)>) + Sync)) {
        let mut idle = 0u32;
        while self.done.load(Ordering::Acquire) < total {
            let Some(t) = self.take() else {
                // Another thread holds the passes this one waits for.
                idle += 1;
                if idle < 64 {
                    std::hint::spin_loop();
                } else {
                    std::thread::yield_now();
                }
                continue;
            };
            idle = 0;
            let t0 = Instant::now();
            run(t, self.pair(t));
            let s = t0.elapsed().as_secs_f32();
            self.seconds[t].store(s.to_bits(), Ordering::Relaxed);
            for &s in &self.next[t] {
                if s != NONE && self.pending[s as usize].fetch_sub(1, Ordering::AcqRel) == 1 {
                    self.ready.lock().expect("no pass panicked").push(s);
                }
            }
            self.done.fetch_add(1, Ordering::AcqRel);
        }
    }

    /// The ready pass with the longest chain behind it (ties: the earliest).
    fn take(&self) -> Option<usize> {
        let mut ready = self.ready.lock().expect("no pass panicked");
        let best = (0..ready.len()).max_by(|&x, &y| {
            let (tx, ty) = (ready[x] as usize, ready[y] as usize);
            self.priority[tx]
                .total_cmp(&self.priority[ty])
                .then(ty.cmp(&tx))
        })?;
        Some(ready.swap_remove(best) as usize)
    }
}

/// Runs `worker` on `n` threads of the current pool (nested joins: no job
/// is boxed, so nothing allocates).
fn workers(n: usize, worker: &(impl Fn() + Sync)) {
    if n <= 1 {
        worker();
    } else {
        let half = n / 2;
        rayon::join(|| workers(half, worker), || workers(n - half, worker));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Mutex as StdMutex;

    /// Every pass runs once, after the passes it waits for, and each
    /// character's passes keep their order, on one thread and on several.
    #[test]
    fn passes_keep_each_characters_order() {
        let n = 6;
        let pairs: Vec<(u32, u32)> = vec![(0, 1), (2, 3), (0, 2), (1, 3), (4, 5), (0, 5), (1, 2)];
        for threads in [1, 2, 4] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let mut g = PassGraph::new(n);
            for _frame in 0..3 {
                g.set_pairs(pairs.iter().copied());
                let log = StdMutex::new(Vec::new());
                pool.install(|| {
                    g.run(|t, _| {
                        // Work of uneven length, so threads interleave.
                        std::thread::sleep(std::time::Duration::from_micros(50 * (t as u64 % 4)));
                        log.lock().unwrap().push(t);
                    })
                });
                let log = log.into_inner().unwrap();
                let mut seen = log.clone();
                seen.sort();
                assert_eq!(seen, (0..n + pairs.len()).collect::<Vec<_>>());
                // Per character: its own pass, then its pairs in order.
                for c in 0..n as u32 {
                    let mine: Vec<usize> = log
                        .iter()
                        .copied()
                        .filter(|&t| match g.pair(t) {
                            None => t == c as usize,
                            Some((i, j)) => i == c || j == c,
                        })
                        .collect();
                    let mut want = vec![c as usize];
                    want.extend(
                        (0..pairs.len())
                            .filter(|&k| pairs[k].0 == c || pairs[k].1 == c)
                            .map(|k| n + k),
                    );
                    assert_eq!(mine, want, "character {c} on {threads} threads");
                }
            }
        }
    }

    /// Two threads overlap a long pair with the other characters' passes
    /// (no barrier after the characters' own passes).
    #[test]
    fn a_long_pair_runs_beside_other_passes() {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        let mut g = PassGraph::new(4);
        g.set_pairs([(0, 1)]);
        let ms = |t: usize| match t {
            4 => 200, // the pair
            2 | 3 => 100,
            _ => 1,
        };
        let sleep = |t: usize, _| std::thread::sleep(std::time::Duration::from_millis(ms(t)));
        // The first frame measures the costs the second one's order uses.
        pool.install(|| g.run(sleep));
        g.set_pairs([(0, 1)]);
        let t0 = Instant::now();
        pool.install(|| g.run(sleep));
        let elapsed = t0.elapsed().as_millis();
        // Serial: 402 ms; after a barrier behind the characters' own passes:
        // at least 100 + 200; here about 201 (the margin is for a loaded
        // machine's late wake-ups).
        assert!(elapsed < 270, "took {elapsed} ms");
    }
}
