//! The passes of one frame, run on every thread of the pool with no
//! barrier between the room passes and the character–character passes.
//!
//! A character's own pass (against the room and the objects) comes before
//! any of its pairs; its pairs then run in any order, one at a time (a pass
//! refits and skins its characters on demand, so it holds them alone). That
//! is all the order results need: every sphere and vertex is refit or
//! skinned at most once a frame, whichever pass asks first, so the own
//! pass's counts are the same on any thread, and the pairs' counts of a
//! character add up to its frame total less its own pass's, whatever order
//! they ran in. (A fixed order per character, kept before, serialised the
//! pairs behind the heaviest one: `docs/performance-journal.md`, "All cores".)
//!
//! Which free pass a thread takes is a matter of speed only: the one on the
//! character with the most estimated work not yet started (last frame's
//! times), so the longest chain starts first. Nothing here allocates once
//! the first frame has sized it.

use std::sync::Mutex;
use std::time::Instant;

/// A frame's passes: `characters` passes `0..n` (each character against the
/// room and objects), then one pass per character pair.
#[derive(Default)]
pub struct PassGraph {
    characters: usize,
    /// This frame's pairs, in pass order.
    pairs: Vec<(u32, u32)>,
    /// Who may run what, while running.
    state: Mutex<Schedule>,
}

/// The run's bookkeeping, behind one lock (a frame has a few dozen passes
/// of microseconds each: the lock is not where time goes).
#[derive(Default)]
struct Schedule {
    /// Passes not started yet.
    open: Vec<u32>,
    /// Per character: a pass holding it is running.
    busy: Vec<bool>,
    /// Per character: its own pass is done.
    own_done: Vec<bool>,
    /// Per character: estimated seconds of its passes not started yet.
    remaining: Vec<f32>,
    /// Passes done.
    done: usize,
    /// Last measured seconds of each character's own pass and of each pair
    /// ([`PassGraph::cost_index`]); a pass's entry is updated when it ends,
    /// and not read again in its frame.
    costs: Vec<f32>,
}

impl PassGraph {
    /// A graph for `n` characters, sized for every pair.
    pub fn new(n: usize) -> Self {
        let most = n + n * n.saturating_sub(1) / 2;
        Self {
            characters: n,
            pairs: Vec::with_capacity(most - n),
            state: Mutex::new(Schedule {
                open: Vec::with_capacity(most),
                busy: vec![false; n],
                own_done: vec![false; n],
                remaining: vec![0.0; n],
                done: 0,
                costs: vec![0.0; n + n * n],
            }),
        }
    }

    /// Characters it is sized for.
    pub fn characters(&self) -> usize {
        self.characters
    }

    /// Sets this frame's character pairs, `(i, j)` with `i < j`, each
    /// character at most once with each other.
    pub fn set_pairs(&mut self, pairs: impl IntoIterator<Item = (u32, u32)>) {
        self.pairs.clear();
        self.pairs.extend(pairs);
    }

    /// Passes this frame.
    pub fn len(&self) -> usize {
        self.characters + self.pairs.len()
    }

    /// Character pair of pass `t` (`None` for a character's own pass).
    pub fn pair(&self, t: usize) -> Option<(u32, u32)> {
        t.checked_sub(self.characters).map(|k| self.pairs[k])
    }

    /// Where pass `t`'s last measured cost is kept in `costs` (a pair's
    /// slot belongs to the two characters, whichever frame lists them).
    fn cost_index(&self, t: usize) -> usize {
        match self.pair(t) {
            None => t,
            Some((i, j)) => self.characters * (1 + i as usize) + j as usize,
        }
    }

    /// The characters pass `t` holds (the second is the first again for a
    /// character's own pass).
    fn holds(&self, t: usize) -> (usize, usize) {
        match self.pair(t) {
            None => (t, t),
            Some((i, j)) => (i as usize, j as usize),
        }
    }

    /// Runs every pass with `run(t, pair)` (`pair` as [`PassGraph::pair`]
    /// says), on every thread of the current rayon pool: a character's own
    /// pass before its pairs, no two passes of one character at once.
    /// Returns when all are done.
    pub fn run(&mut self, run: impl Fn(usize, Option<(u32, u32)>) + Sync) {
        let total = self.len();
        let mut st = self.state.lock().expect("no pass panicked");
        st.open.clear();
        st.open.extend(0..total as u32);
        st.busy.iter_mut().for_each(|b| *b = false);
        st.own_done.iter_mut().for_each(|d| *d = false);
        st.remaining.iter_mut().for_each(|r| *r = 0.0);
        for t in 0..total {
            let (i, j) = self.holds(t);
            let c = st.costs[self.cost_index(t)];
            st.remaining[i] += c;
            if j != i {
                st.remaining[j] += c;
            }
        }
        st.done = 0;
        drop(st);
        let worker = || self.work(total, &run);
        // One pass needs no pool (nor asks for rayon's global one when
        // called outside a pool).
        let threads = if total <= 1 {
            1
        } else {
            rayon::current_num_threads().min(total)
        };
        workers(threads, &worker);
    }

    fn work(&self, total: usize, run: &(impl Fn(usize, Option<(u32, u32)>) + Sync)) {
        let mut idle = 0u32;
        loop {
            let Some(t) = self.take(total) else { return };
            let Some(t) = t else {
                // Every pass left waits for a character another thread holds.
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
            let (i, j) = self.holds(t);
            let mut st = self.state.lock().expect("no pass panicked");
            st.costs[self.cost_index(t)] = s;
            st.busy[i] = false;
            st.busy[j] = false;
            if self.pair(t).is_none() {
                st.own_done[i] = true;
            }
            st.done += 1;
        }
    }

    /// `None` when every pass is done; `Some(None)` when none can start now;
    /// else the pass started: among those whose characters are free (and
    /// have had their own pass, for a pair), the one whose character has
    /// the most estimated work left, then the costlier, then the earliest.
    fn take(&self, total: usize) -> Option<Option<usize>> {
        let mut st = self.state.lock().expect("no pass panicked");
        if st.done == total {
            return None;
        }
        let mut best: Option<(usize, f32, f32)> = None;
        for (k, &t) in st.open.iter().enumerate() {
            let t = t as usize;
            let (i, j) = self.holds(t);
            let free = !st.busy[i] && !st.busy[j];
            let ready = self.pair(t).is_none() || (st.own_done[i] && st.own_done[j]);
            if !(free && ready) {
                continue;
            }
            let chain = st.remaining[i].max(st.remaining[j]);
            let cost = st.costs[self.cost_index(t)];
            let better = match best {
                None => true,
                Some((b, bc, bcost)) => {
                    chain > bc
                        || (chain == bc
                            && (cost > bcost || (cost == bcost && t < st.open[b] as usize)))
                }
            };
            if better {
                best = Some((k, chain, cost));
            }
        }
        let Some((k, _, cost)) = best else {
            return Some(None);
        };
        let t = st.open.swap_remove(k) as usize;
        let (i, j) = self.holds(t);
        st.busy[i] = true;
        st.busy[j] = true;
        st.remaining[i] -= cost;
        if j != i {
            st.remaining[j] -= cost;
        }
        Some(Some(t))
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

    fn pool(threads: usize) -> rayon::ThreadPool {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
    }

    /// Milliseconds the second of two frames over `pairs` takes on two
    /// threads, pass `t` sleeping `ms(t)` (the first frame measures the
    /// costs the second one's choices use).
    fn second_frame_ms<const N: usize>(
        characters: usize,
        pairs: [(u32, u32); N],
        ms: impl Fn(usize) -> u64 + Sync,
    ) -> u128 {
        let pool = pool(2);
        let mut g = PassGraph::new(characters);
        let sleep = |t: usize, _| std::thread::sleep(std::time::Duration::from_millis(ms(t)));
        g.set_pairs(pairs);
        pool.install(|| g.run(sleep));
        g.set_pairs(pairs);
        let t0 = Instant::now();
        pool.install(|| g.run(sleep));
        t0.elapsed().as_millis()
    }

    /// Every pass runs once; a character's own pass ends before any of its
    /// pairs starts, and no two passes of one character overlap, on one
    /// thread and on several (checked from the start and end times each
    /// pass logs).
    #[test]
    fn own_pass_first_and_one_pass_per_character_at_a_time() {
        let n = 6;
        let pairs: Vec<(u32, u32)> = vec![(0, 1), (2, 3), (0, 2), (1, 3), (4, 5), (0, 5), (1, 2)];
        for threads in [1, 2, 4] {
            let pool = pool(threads);
            let mut g = PassGraph::new(n);
            for _frame in 0..3 {
                g.set_pairs(pairs.iter().copied());
                let clock = Instant::now();
                let log = StdMutex::new(Vec::new());
                pool.install(|| {
                    g.run(|t, _| {
                        let start = clock.elapsed();
                        // Work of uneven length, so threads interleave.
                        std::thread::sleep(std::time::Duration::from_micros(50 * (t as u64 % 4)));
                        log.lock().unwrap().push((t, start, clock.elapsed()));
                    })
                });
                let log = log.into_inner().unwrap();
                let mut seen: Vec<usize> = log.iter().map(|e| e.0).collect();
                seen.sort();
                assert_eq!(seen, (0..n + pairs.len()).collect::<Vec<_>>());
                let holds = |t: usize, c: usize| match g.pair(t) {
                    None => t == c,
                    Some((i, j)) => i as usize == c || j as usize == c,
                };
                for c in 0..n {
                    let own = log.iter().find(|e| e.0 == c).unwrap();
                    let mine: Vec<_> = log.iter().filter(|e| holds(e.0, c)).collect();
                    for x in &mine {
                        if x.0 != c {
                            assert!(
                                x.1 >= own.2,
                                "character {c}: pair {} before its own pass on {threads} threads",
                                x.0
                            );
                        }
                        for y in &mine {
                            if x.0 < y.0 {
                                let apart = x.2 <= y.1 || y.2 <= x.1;
                                assert!(
                                    apart,
                                    "character {c}: passes {} and {} overlap on {threads} threads",
                                    x.0, y.0
                                );
                            }
                        }
                    }
                }
            }
        }
    }

    /// Two threads run a heavy pair beside the other characters' pairs:
    /// a character's pairs are not held behind one another's order.
    #[test]
    fn pairs_of_free_characters_run_beside_a_heavy_pair() {
        // Listed so that a fixed order per character would put (0, 1) between
        // (0, 2) and (1, 3): pairs (2, 3) and the rest would wait for it.
        let pairs = [(0, 2), (0, 1), (1, 3), (2, 3)];
        // Passes 0–3 are the characters' own; pass 4 + k is `pairs[k]`, so
        // pass 5 is the heavy pair (0, 1).
        let elapsed = second_frame_ms(4, pairs, |t| match t {
            5 => 500,
            4.. => 150,
            _ => 1,
        });
        // Serial: 954 ms. The heavy pair on one thread (500 ms) while the
        // other runs (2, 3) and then waits, then (0, 2) and (1, 3) side by
        // side: about 652 ms; a fixed order (0, 2), (0, 1), (1, 3) takes at
        // least 800. The margin is for a loaded machine's late wake-ups (a
        // run with the test suite beside it once took 38 ms over the ideal
        // when the passes were 200 and 60 ms).
        assert!(elapsed < 740, "took {elapsed} ms");
    }

    /// Two threads overlap a long pair with the other characters' passes
    /// (no barrier after the characters' own passes).
    #[test]
    fn a_long_pair_runs_beside_other_passes() {
        let elapsed = second_frame_ms(4, [(0, 1)], |t| match t {
            4 => 200, // the pair
            2 | 3 => 100,
            _ => 1,
        });
        // Serial: 402 ms; after a barrier behind the characters' own passes:
        // at least 100 + 200; here about 201 (the margin is for a loaded
        // machine's late wake-ups).
        assert!(elapsed < 270, "took {elapsed} ms");
    }
}
