//! Data parallelism over the available cores: maps over contiguous runs,
//! in-place fills and a two-way join, each giving the sequential result.

/// The cores the parallel helpers use: the available parallelism, at most
/// 8, asked once per process. Each `std::thread::available_parallelism`
/// call reads the cgroup files (about 20 µs here), and a reconstruction
/// asks about a thousand times (most calls on a few points, which stay on
/// one core anyway): 20 ms of the main thread's time.
pub fn cores() -> usize {
    static CORES: std::sync::OnceLock<usize> = std::sync::OnceLock::new();
    *CORES.get_or_init(|| std::thread::available_parallelism().map_or(1, |c| c.get().min(8)))
}

/// `f` over contiguous runs of `items`, concatenated in order: the same
/// result as `f(items)` when `f` maps each item on its own. The runs (each
/// at least `min_run` items long, up to four per core) are
/// taken by the available cores (at most 8; the calling thread is one) as
/// they come free: on a machine shared with other work, a core that is
/// held up takes fewer runs instead of holding up the whole map.
pub fn parallel_map<T: Sync, R: Send>(
    items: &[T],
    min_run: usize,
    f: impl Fn(&[T]) -> Vec<R> + Sync,
) -> Vec<R> {
    use std::sync::atomic::{AtomicUsize, Ordering};
    let cores = cores();
    let most = items.len() / min_run.max(1);
    let threads = cores.min(most);
    if threads <= 1 {
        return f(items);
    }
    let runs: Vec<&[T]> = items
        .chunks(items.len().div_ceil(most.min(RUNS_PER_CORE * cores)))
        .collect();
    let next = AtomicUsize::new(0);
    let work = || {
        let mut done = Vec::new();
        loop {
            let i = next.fetch_add(1, Ordering::Relaxed);
            match runs.get(i) {
                Some(run) => done.push((i, f(run))),
                None => return done,
            }
        }
    };
    let mut all: Vec<(usize, Vec<R>)> = std::thread::scope(|scope| {
        let handles: Vec<_> = (1..threads).map(|_| scope.spawn(work)).collect();
        let mut all = work();
        for h in handles {
            match h.join() {
                Ok(part) => all.extend(part),
                Err(panic) => std::panic::resume_unwind(panic),
            }
        }
        all
    });
    all.sort_unstable_by_key(|(i, _)| *i);
    let mut out = Vec::with_capacity(items.len());
    for (_, part) in all {
        out.extend(part);
    }
    out
}

/// `f(i, &mut items[i])` for every item, over the cores: runs of at least
/// `min_run` items taken as the cores come free (as [`parallel_map`]'s),
/// each core writing its runs in place. Filling a fresh zeroed array this
/// way (`vec![0; n]`: pages the system zeroes on first touch) also
/// spreads the first touches over the cores, where collecting runs and
/// concatenating them would copy everything once more on one core.
pub fn par_for_each_mut<R: Send>(
    items: &mut [R],
    min_run: usize,
    f: impl Fn(usize, &mut R) + Sync,
) {
    let n = items.len();
    let cores = cores();
    let most = n / min_run.max(1);
    let threads = cores.min(most);
    if threads <= 1 {
        for (i, x) in items.iter_mut().enumerate() {
            f(i, x);
        }
        return;
    }
    let size = n.div_ceil(most.min(RUNS_PER_CORE * cores));
    let jobs = std::sync::Mutex::new(items.chunks_mut(size).enumerate());
    let work = || loop {
        // (Nothing panics while the lock is held: a poisoned lock still
        // hands out the runs.)
        let job = match jobs.lock() {
            Ok(mut j) => j.next(),
            Err(poisoned) => poisoned.into_inner().next(),
        };
        let Some((k, run)) = job else {
            return;
        };
        for (j, x) in run.iter_mut().enumerate() {
            f(k * size + j, x);
        }
    };
    std::thread::scope(|scope| {
        let handles: Vec<_> = (1..threads).map(|_| scope.spawn(work)).collect();
        work();
        for h in handles {
            if let Err(panic) = h.join() {
                std::panic::resume_unwind(panic);
            }
        }
    });
}

/// Runs per core of [`parallel_map`] (when the items allow): enough that
/// a core slowed by other work leaves its share to the others, few enough
/// that each run still amortizes its start (a warm-started search's first
/// query, a run's allocations).
const RUNS_PER_CORE: usize = 4;

/// `(a(), b())`, the two run at once on two cores when there are (`b` on
/// a scoped thread): e.g. two gathers into fresh arrays, whose page
/// faults then run side by side.
pub fn join<A: Send, B: Send>(
    a: impl FnOnce() -> A + Send,
    b: impl FnOnce() -> B + Send,
) -> (A, B) {
    if cores() < 2 {
        return (a(), b());
    }
    std::thread::scope(|scope| {
        let hb = scope.spawn(b);
        let ra = a();
        match hb.join() {
            Ok(rb) => (ra, rb),
            Err(panic) => std::panic::resume_unwind(panic),
        }
    })
}

/// `f` of every item, in order, the items taken one at a time by the
/// cores as they come free (an atomic counter): items of very different
/// cost (a torso and a transition) balance better than in fixed runs.
pub(crate) fn each_on_cores<T: Sync, R: Send>(items: &[T], f: impl Fn(&T) -> R + Sync) -> Vec<R> {
    use std::sync::atomic::{AtomicUsize, Ordering};
    let cores = cores();
    let threads = cores.min(items.len());
    if threads <= 1 {
        return items.iter().map(f).collect();
    }
    let next = AtomicUsize::new(0);
    let work = || {
        let mut done = Vec::new();
        loop {
            let i = next.fetch_add(1, Ordering::Relaxed);
            if i >= items.len() {
                return done;
            }
            done.push((i, f(&items[i])));
        }
    };
    let mut all: Vec<(usize, R)> = std::thread::scope(|scope| {
        let handles: Vec<_> = (1..threads).map(|_| scope.spawn(work)).collect();
        let mut all = work();
        for h in handles {
            match h.join() {
                Ok(part) => all.extend(part),
                Err(panic) => std::panic::resume_unwind(panic),
            }
        }
        all
    });
    all.sort_by_key(|(i, _)| *i);
    all.into_iter().map(|(_, r)| r).collect()
}
