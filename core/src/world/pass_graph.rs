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
//! Which free pass a thread takes is a matter of speed only: the one whose
//! characters had the most estimated work at the frame's start (last
//! frame's times), so the longest chain starts first. Taking one is a heap
//! pop (a pair enters the heap when both its characters' own passes are
//! done), so a frame of `p` passes costs `p log p` to schedule, not `p²`:
//! a crowd of thousands has thousands of pairs. Nothing here allocates
//! once a frame as large has sized it.

use std::cmp::Reverse;
use std::collections::BinaryHeap;
use std::sync::Mutex;

use crate::pipeline::counters::{ms_since, ticks};

/// A frame's passes: `characters` passes `0..n` (each character against the
/// room and objects), then one pass per character pair.
#[derive(Default)]
pub struct PassGraph {
    characters: usize,
    /// This frame's pairs, in pass order (ascending).
    pairs: Vec<(u32, u32)>,
    /// Last frame's pairs (ascending) and each one's measured seconds: this
    /// frame's estimates.
    last_pairs: Vec<(u32, u32)>,
    last_pair_costs: Vec<f32>,
    /// Last measured seconds of each character's own pass.
    own_costs: Vec<f32>,
    /// Who may run what, while running.
    state: Mutex<Schedule>,
    /// The last frame's work and span, seconds ([`PassGraph::work_span`]).
    work: f64,
    span: f64,
}

/// Where a free pass ranks: the most estimated work its characters had at
/// the frame's start (the longer chain first), then its own estimated
/// cost, then the earlier pass. Seconds as `f32` bits (never negative, so
/// they order as the numbers do).
type Rank = (u32, u32, Reverse<u32>);

/// The end of a list of parked passes.
const NONE: u32 = u32::MAX;

/// The run's bookkeeping, behind one lock (a pass is tens of microseconds
/// or more; taking one is a heap pop: the lock is not where time goes).
#[derive(Default)]
struct Schedule {
    /// Characters' own passes, best first; those before `own_next` have
    /// started. (An own pass is always free to start: nothing else holds
    /// its character before it ends.)
    own_order: Vec<u32>,
    own_next: usize,
    /// Pairs whose characters have both had their own pass, not started,
    /// and not parked.
    ready: BinaryHeap<(Rank, u32)>,
    /// Ready pairs found with a character held, parked on it until it is
    /// free (then ready again): a list per character through the passes,
    /// `parked[c]` its first pass and `parked_next[t]` the one after `t`
    /// ([`NONE`] ends a list). Taking a pass never walks past a held pair
    /// twice: with many threads, popping held pairs and pushing them back
    /// under the lock made the lock the frame's bottleneck.
    parked: Vec<u32>,
    parked_next: Vec<u32>,
    /// Per character: a pass holding it is running.
    busy: Vec<bool>,
    /// Per character: its own pass is done.
    own_done: Vec<bool>,
    /// Per character: its pairs' passes, `pair_passes[pairs_from[c]..pairs_from[c + 1]]`.
    pairs_from: Vec<u32>,
    pair_passes: Vec<u32>,
    /// Per pass: estimated seconds at the start, measured once it ran.
    costs: Vec<f32>,
    /// Per character: estimated seconds of all its passes at the start.
    chain: Vec<f32>,
    /// Passes done.
    done: usize,
}

impl PassGraph {
    /// A graph for `n` characters.
    pub fn new(n: usize) -> Self {
        Self {
            characters: n,
            own_costs: vec![0.0; n],
            state: Mutex::new(Schedule {
                busy: vec![false; n],
                own_done: vec![false; n],
                parked: vec![NONE; n],
                chain: vec![0.0; n],
                pairs_from: vec![0; n + 1],
                ..Schedule::default()
            }),
            ..Self::default()
        }
    }

    /// Characters it is sized for.
    pub fn characters(&self) -> usize {
        self.characters
    }

    /// Sets this frame's character pairs, `(i, j)` with `i < j`, ascending,
    /// each character at most once with each other.
    pub fn set_pairs(&mut self, pairs: impl IntoIterator<Item = (u32, u32)>) {
        self.pairs.clear();
        self.pairs.extend(pairs);
        debug_assert!(self.pairs.windows(2).all(|w| w[0] < w[1]));
    }

    /// Passes this frame.
    pub fn len(&self) -> usize {
        self.characters + self.pairs.len()
    }

    /// Character pair of pass `t` (`None` for a character's own pass).
    pub fn pair(&self, t: usize) -> Option<(u32, u32)> {
        t.checked_sub(self.characters).map(|k| self.pairs[k])
    }

    /// The last frame's work (the sum of every pass's seconds) and span (the
    /// most seconds one character's passes took: they run one at a time, so
    /// no number of threads finishes the frame's passes sooner).
    pub fn work_span(&self) -> (f64, f64) {
        (self.work, self.span)
    }

    /// The characters pass `t` holds (the second is the first again for a
    /// character's own pass).
    fn holds(&self, t: usize) -> (usize, usize) {
        match self.pair(t) {
            None => (t, t),
            Some((i, j)) => (i as usize, j as usize),
        }
    }

    /// Sets every pass's estimate, the characters' chains, who holds which
    /// pair and the order of the own passes.
    fn plan(&mut self) {
        let n = self.characters;
        let st = self.state.get_mut().expect("no pass panicked");
        st.costs.clear();
        st.costs.extend_from_slice(&self.own_costs);
        // Last frame's measured cost of each pair listed again (both lists
        // ascending: one walk).
        let mut k = 0;
        for p in &self.pairs {
            while k < self.last_pairs.len() && self.last_pairs[k] < *p {
                k += 1;
            }
            let known = k < self.last_pairs.len() && self.last_pairs[k] == *p;
            st.costs
                .push(if known { self.last_pair_costs[k] } else { 0.0 });
        }
        st.chain.copy_from_slice(&self.own_costs);
        st.pairs_from.iter_mut().for_each(|c| *c = 0);
        for (k, &(i, j)) in self.pairs.iter().enumerate() {
            let cost = st.costs[n + k];
            st.chain[i as usize] += cost;
            st.chain[j as usize] += cost;
            st.pairs_from[i as usize + 1] += 1;
            st.pairs_from[j as usize + 1] += 1;
        }
        for c in 0..n {
            st.pairs_from[c + 1] += st.pairs_from[c];
        }
        st.pair_passes.clear();
        st.pair_passes.resize(2 * self.pairs.len(), 0);
        // `pairs_from[c + 1]` is the end of c's run: fill each run from its
        // end backwards, which leaves `pairs_from[c + 1]` at c's start;
        // shifting by one then gives every start, and the end.
        for (k, &(i, j)) in self.pairs.iter().enumerate().rev() {
            for c in [i as usize, j as usize] {
                let end = &mut st.pairs_from[c + 1];
                *end -= 1;
                st.pair_passes[*end as usize] = (n + k) as u32;
            }
        }
        st.pairs_from.rotate_left(1);
        st.pairs_from[n] = (2 * self.pairs.len()) as u32;
        st.own_order.clear();
        st.own_order.extend(0..n as u32);
        let (chain, costs) = (&st.chain, &st.costs);
        st.own_order.sort_unstable_by_key(|&t| {
            Reverse((
                chain[t as usize].to_bits(),
                costs[t as usize].to_bits(),
                Reverse(t),
            ))
        });
        st.own_next = 0;
        // Sized for every pair: how many wait at once depends on the
        // threads' timing, which must not decide whether a frame allocates.
        st.ready.clear();
        st.ready.reserve(self.pairs.len());
        st.parked.iter_mut().for_each(|p| *p = NONE);
        st.parked_next.clear();
        st.parked_next.resize(n + self.pairs.len(), NONE);
        st.busy.iter_mut().for_each(|b| *b = false);
        st.own_done.iter_mut().for_each(|d| *d = false);
        st.done = 0;
    }

    /// Runs every pass with `run(t, pair)` (`pair` as [`PassGraph::pair`]
    /// says), on every thread of the current rayon pool: a character's own
    /// pass before its pairs, no two passes of one character at once.
    /// Returns when all are done.
    pub fn run(&mut self, run: impl Fn(usize, Option<(u32, u32)>) + Sync) {
        let total = self.len();
        self.plan();
        let worker = || self.work(total, &run);
        // One pass needs no pool (nor asks for rayon's global one when
        // called outside a pool).
        let threads = if total <= 1 {
            1
        } else {
            rayon::current_num_threads().min(total)
        };
        workers(threads, &worker);
        self.settle();
    }

    /// Keeps this frame's measured costs as the next one's estimates, and
    /// its work and span.
    fn settle(&mut self) {
        let n = self.characters;
        let st = self.state.get_mut().expect("no pass panicked");
        self.own_costs.copy_from_slice(&st.costs[..n]);
        self.last_pairs.clear();
        self.last_pairs.extend_from_slice(&self.pairs);
        self.last_pair_costs.clear();
        self.last_pair_costs.extend_from_slice(&st.costs[n..]);
        // Each character's passes, one after another: the chain again, now
        // of measured seconds.
        st.chain.copy_from_slice(&st.costs[..n]);
        for (k, &(i, j)) in self.pairs.iter().enumerate() {
            let cost = st.costs[n + k];
            st.chain[i as usize] += cost;
            st.chain[j as usize] += cost;
        }
        self.work = st.costs.iter().map(|&c| f64::from(c)).sum();
        self.span = st.chain.iter().fold(0.0f64, |m, &c| m.max(f64::from(c)));
    }

    /// A thread's loop: take a pass, run it, then, under one lock, mark it
    /// done and take the next (one lock a pass, not two: with many threads
    /// and passes of tens of microseconds the lock is what they share).
    fn work(&self, total: usize, run: &(impl Fn(usize, Option<(u32, u32)>) + Sync)) {
        let mut idle = 0u32;
        let mut next = self.take(&mut self.state.lock().expect("no pass panicked"), total);
        loop {
            let Some(t) = next else { return };
            let Some(t) = t else {
                // Every pass left waits for a character another thread
                // holds: wait a little longer each time before asking the
                // lock again (idle threads asking it at once slow the
                // threads finishing passes).
                idle += 1;
                if idle < 12 {
                    for _ in 0..1u32 << idle {
                        std::hint::spin_loop();
                    }
                } else {
                    std::thread::yield_now();
                }
                next = self.take(&mut self.state.lock().expect("no pass panicked"), total);
                continue;
            };
            idle = 0;
            let t0 = ticks();
            run(t, self.pair(t));
            let s = (ms_since(t0) * 1e-3) as f32;
            let mut st = self.state.lock().expect("no pass panicked");
            self.finish(&mut st, t, s);
            next = self.take(&mut st, total);
        }
    }

    /// Pass `t` done in `s` seconds: its characters free, the pairs parked
    /// on them and (after an own pass) its character's pairs whose other
    /// character has had its own pass ready.
    fn finish(&self, st: &mut Schedule, t: usize, s: f32) {
        let (i, j) = self.holds(t);
        st.costs[t] = s;
        st.busy[i] = false;
        st.busy[j] = false;
        st.done += 1;
        // The pairs parked on them may start again.
        for c in [i, j] {
            let mut p = std::mem::replace(&mut st.parked[c], NONE);
            while p != NONE {
                let next = st.parked_next[p as usize];
                let (a, b) = self.holds(p as usize);
                let rank = rank(&st.chain, &st.costs, a, b, p);
                st.ready.push((rank, p));
                p = next;
            }
        }
        if self.pair(t).is_some() {
            return;
        }
        st.own_done[i] = true;
        let (from, to) = (st.pairs_from[i] as usize, st.pairs_from[i + 1] as usize);
        for &p in &st.pair_passes[from..to] {
            let (a, b) = self.holds(p as usize);
            let other = if a == i { b } else { a };
            if st.own_done[other] {
                let rank = rank(&st.chain, &st.costs, a, b, p);
                st.ready.push((rank, p));
            }
        }
    }

    /// `None` when every pass is done; `Some(None)` when none can start now;
    /// else the pass started: of the next own pass and the best ready pair
    /// whose characters are free, the better ranked ([`Rank`]).
    fn take(&self, st: &mut Schedule, total: usize) -> Option<Option<usize>> {
        if st.done == total {
            return None;
        }
        let mut pair = None;
        while let Some(e) = st.ready.pop() {
            let (i, j) = self.holds(e.1 as usize);
            let on = if st.busy[i] {
                i
            } else if st.busy[j] {
                j
            } else {
                pair = Some(e);
                break;
            };
            st.parked_next[e.1 as usize] = st.parked[on];
            st.parked[on] = e.1;
        }
        let own = st.own_order.get(st.own_next).map(|&t| {
            let t = t as usize;
            (rank(&st.chain, &st.costs, t, t, t as u32), t as u32)
        });
        let t = match (own, pair) {
            (None, None) => return Some(None),
            (Some(o), Some(p)) if p.0 > o.0 => p.1,
            (Some(o), p) => {
                if let Some(p) = p {
                    st.ready.push(p);
                }
                st.own_next += 1;
                o.1
            }
            (None, Some(p)) => p.1,
        } as usize;
        let (i, j) = self.holds(t);
        st.busy[i] = true;
        st.busy[j] = true;
        Some(Some(t))
    }
}

/// Pass `t`'s rank, holding characters `i` and `j` (the same for an own
/// pass).
fn rank(chain: &[f32], costs: &[f32], i: usize, j: usize, t: u32) -> Rank {
    (
        chain[i].max(chain[j]).to_bits(),
        costs[t as usize].to_bits(),
        Reverse(t),
    )
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
    use std::time::Instant;

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
        let pairs: Vec<(u32, u32)> = vec![(0, 1), (0, 2), (0, 5), (1, 2), (1, 3), (2, 3), (4, 5)];
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
        // Character 0 and 1's pairs, if run in a fixed order such as (0, 2),
        // (0, 1), (1, 3), would hold the others behind the heavy one.
        let pairs = [(0, 1), (0, 2), (1, 3), (2, 3)];
        // Passes 0–3 are the characters' own; pass 4 + k is `pairs[k]`, so
        // pass 4 is the heavy pair (0, 1).
        let elapsed = second_frame_ms(4, pairs, |t| match t {
            4 => 500,
            5.. => 150,
            _ => 1,
        });
        // Serial: 954 ms. The heavy pair on one thread (500 ms) while the
        // other runs (2, 3) and then waits, then (0, 2) and (1, 3) side by
        // side: about 652 ms; the fixed order (0, 2), (0, 1), (1, 3) takes at
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
