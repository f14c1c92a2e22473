//! Each thread of a world's pool kept on a processor of its own.
//!
//! Why: a frame of several characters starts on one pool thread while the
//! others are woken for it (the workers of `pass_graph`). Linux often
//! queues a woken thread on the processor of the thread that woke it,
//! and there it waited behind the frame: in 28–38 of a crowd's 60 two-thread
//! frames the second thread ran no pass, although the other processor was
//! idle. With each pool thread pinned to its own processor it happened in
//! none of two runs' 120 frames (docs/performance-journal.md, "Pinned pool threads").
//!
//! Pinning applies to pools of at least two threads and at most as many
//! threads as the process may use processors; otherwise the threads are
//! left to the operating system. Elsewhere than on Linux it does nothing.

/// A pool of `threads` threads (0: one per core), each pinned to a
/// processor of its own where [`pin_pool_thread`] can.
pub fn pinned_pool(threads: usize) -> Result<rayon::ThreadPool, rayon::ThreadPoolBuildError> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        // The handler runs on the new thread, already in its pool.
        .start_handler(|i| {
            pin_pool_thread(i, rayon::current_num_threads());
        })
        .build()
}

/// Pins the calling thread, the `index`-th of a pool of `threads`, to the
/// `index`-th processor this process may run on, when the pool has between
/// two threads and as many as those processors. Returns whether it pinned.
/// A thread pool's start handler calls it.
pub fn pin_pool_thread(index: usize, threads: usize) -> bool {
    #[cfg(target_os = "linux")]
    {
        linux::pin(index, threads)
    }
    #[cfg(not(target_os = "linux"))]
    {
        let _ = (index, threads);
        false
    }
}

/// The processor the calling thread runs on now, where the platform says.
pub fn current_processor() -> Option<usize> {
    #[cfg(target_os = "linux")]
    {
        // SAFETY: no arguments; returns -1 on failure.
        let c = unsafe { libc::sched_getcpu() };
        usize::try_from(c).ok()
    }
    #[cfg(not(target_os = "linux"))]
    {
        None
    }
}

/// The processors the calling thread may run on (empty where the platform
/// does not say).
pub fn allowed_processors() -> Vec<usize> {
    #[cfg(target_os = "linux")]
    {
        linux::allowed()
    }
    #[cfg(not(target_os = "linux"))]
    {
        Vec::new()
    }
}

#[cfg(target_os = "linux")]
mod linux {
    use std::mem::{size_of, zeroed};

    /// The processors in the calling thread's affinity mask, in order.
    pub(super) fn allowed() -> Vec<usize> {
        // SAFETY: `cpu_set_t` is plain bits (all-zero is the empty set), and
        // the call writes at most `size_of::<cpu_set_t>()` bytes into it.
        unsafe {
            let mut set: libc::cpu_set_t = zeroed();
            if libc::sched_getaffinity(0, size_of::<libc::cpu_set_t>(), &mut set) != 0 {
                return Vec::new();
            }
            (0..libc::CPU_SETSIZE as usize)
                .filter(|&c| libc::CPU_ISSET(c, &set))
                .collect()
        }
    }

    pub(super) fn pin(index: usize, threads: usize) -> bool {
        let cpus = allowed();
        if threads < 2 || threads > cpus.len() || index >= threads {
            return false;
        }
        // SAFETY: as in `allowed`; the set names one allowed processor.
        unsafe {
            let mut set: libc::cpu_set_t = zeroed();
            libc::CPU_SET(cpus[index], &mut set);
            libc::sched_setaffinity(0, size_of::<libc::cpu_set_t>(), &set) == 0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pool_of_two_threads_is_pinned_to_two_processors() {
        let pool = pinned_pool(2).unwrap();
        // What each thread may run on (its affinity mask).
        let masks: Vec<Vec<usize>> = pool.broadcast(|_| allowed_processors());
        let can = allowed_processors().len() >= 2;
        if cfg!(target_os = "linux") && can {
            assert_eq!(masks[0].len(), 1, "thread 0 may run on {:?}", masks[0]);
            assert_eq!(masks[1].len(), 1, "thread 1 may run on {:?}", masks[1]);
            assert_ne!(masks[0], masks[1], "both pool threads on one processor");
            // And they run there.
            let at: Vec<Option<usize>> = pool.broadcast(|_| current_processor());
            assert_eq!(at[0], Some(masks[0][0]));
            assert_eq!(at[1], Some(masks[1][0]));
        }
        // The thread that built the pool is left as it was.
        assert_eq!(allowed_processors().len() >= 2, can);
    }

    #[test]
    fn pools_of_one_and_oversubscribed_pools_are_not_pinned() {
        let all = allowed_processors();
        let one = pinned_pool(1).unwrap();
        assert_eq!(one.install(allowed_processors), all);
        let many = pinned_pool(all.len() + 1).unwrap();
        let masks: Vec<Vec<usize>> = many.broadcast(|_| allowed_processors());
        assert!(masks.iter().all(|m| *m == all), "{masks:?} against {all:?}");
        assert!(!pin_pool_thread(0, 1));
    }
}
