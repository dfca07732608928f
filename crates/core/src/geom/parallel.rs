//! Data parallelism on rayon's thread pool: maps over contiguous runs, an
//! in-place fill, one task per item and a two-way join. Each gives the
//! sequential result in the sequential order, whatever the threads.

use rayon::prelude::*;

pub use rayon::join;

/// Runs per thread of [`parallel_map`] and [`par_for_each_mut`] (when the
/// items allow): enough that a thread slowed by other work leaves its share
/// to the others, few enough that each run still amortizes its start (a
/// warm-started search's first query, a run's allocations).
const RUNS_PER_THREAD: usize = 4;

/// The length of the runs `n` items are cut into (each at least `min_run`
/// long, up to [`RUNS_PER_THREAD`] per thread), or `None` when one run on
/// the calling thread is all there is.
fn run_length(n: usize, min_run: usize) -> Option<usize> {
    let threads = rayon::current_num_threads();
    let most = n / min_run.max(1);
    if threads.min(most) <= 1 {
        return None;
    }
    Some(n.div_ceil(most.min(RUNS_PER_THREAD * threads)))
}

/// `f` over contiguous runs of `items`, concatenated in order: the same
/// result as `f(items)` when `f` maps each item on its own.
pub fn parallel_map<T: Sync, R: Send>(
    items: &[T],
    min_run: usize,
    f: impl Fn(&[T]) -> Vec<R> + Sync,
) -> Vec<R> {
    match run_length(items.len(), min_run) {
        None => f(items),
        Some(size) => items.par_chunks(size).flat_map_iter(&f).collect(),
    }
}

/// `f(i, &mut items[i])` for every item, in runs of at least `min_run`
/// items written in place. Filling a fresh zeroed array this way
/// (`vec![0; n]`: pages the system zeroes on first touch) also spreads the
/// first touches over the threads.
pub fn par_for_each_mut<R: Send>(
    items: &mut [R],
    min_run: usize,
    f: impl Fn(usize, &mut R) + Sync,
) {
    match run_length(items.len(), min_run) {
        None => {
            for (i, x) in items.iter_mut().enumerate() {
                f(i, x);
            }
        }
        Some(size) => items.par_chunks_mut(size).enumerate().for_each(|(k, run)| {
            for (j, x) in run.iter_mut().enumerate() {
                f(k * size + j, x);
            }
        }),
    }
}

/// `f` of every item, in order, one task per item: items of very
/// different cost (a torso and a transition) balance better than in
/// fixed runs.
pub fn each_on_cores<T: Sync, R: Send>(items: &[T], f: impl Fn(&T) -> R + Sync) -> Vec<R> {
    if items.len() < 2 || rayon::current_num_threads() < 2 {
        return items.iter().map(f).collect();
    }
    items.par_iter().with_max_len(1).map(&f).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Work taken as the cores come free still comes back in order.
    #[test]
    fn each_on_cores_keeps_the_order() {
        let items: Vec<u64> = (0..37).map(|i| (i * 7919) % 101).collect();
        let slow = |&x: &u64| (0..x * 1000).fold(x, |a, k| a.wrapping_mul(31).wrapping_add(k));
        let expected: Vec<u64> = items.iter().map(slow).collect();
        assert_eq!(each_on_cores(&items, slow), expected);
        assert!(each_on_cores(&[] as &[u64], slow).is_empty());
    }

    /// Runs taken as the cores come free come back in order, whatever
    /// the run length and the items' costs; `join` returns both results.
    #[test]
    fn parallel_map_keeps_the_order() {
        let items: Vec<u64> = (0..1000).map(|i| (i * 7919) % 101).collect();
        let slow = |x: u64| (0..x * 50).fold(x, |a, k| a.wrapping_mul(31).wrapping_add(k));
        let expected: Vec<u64> = items.iter().map(|&x| slow(x)).collect();
        for min_run in [1, 3, 64, 250, 500, 1000, 5000] {
            let got = parallel_map(&items, min_run, |run| {
                run.iter().map(|&x| slow(x)).collect()
            });
            assert_eq!(got, expected, "min_run {min_run}");
        }
        // A map that is not one-to-one still concatenates its runs in order.
        let pairs = parallel_map(&items, 7, |run| run.iter().flat_map(|&x| [x, x]).collect());
        let doubled: Vec<u64> = items.iter().flat_map(|&x| [x, x]).collect();
        assert_eq!(pairs, doubled);
        assert!(parallel_map(&[] as &[u64], 4, |run| run.to_vec()).is_empty());
        assert_eq!(join(|| slow(7), || slow(9)), (slow(7), slow(9)));
        // In place: every item once, at its own index.
        for min_run in [1, 10, 333, 2000] {
            let mut out = vec![0u64; items.len()];
            par_for_each_mut(&mut out, min_run, |i, x| *x += slow(items[i]) + 1);
            let want: Vec<u64> = expected.iter().map(|x| x + 1).collect();
            assert_eq!(out, want, "min_run {min_run}");
        }
    }
}
