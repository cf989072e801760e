//! The threads the workers run on. Every task is a pure function of its index and its own
//! random stream, so what a thread computes never depends on which thread computes it or when:
//! results come back in task order, and the layout is the same on any machine.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

/// Runs `task(i)` for `i in 0..tasks` on `threads` threads, each thread taking the next task
/// as soon as it is free (so a thread that drew cheap tasks does not sit idle while another
/// finishes expensive ones); results in task order.
pub(super) fn shared_out<T: Send>(
    threads: usize,
    tasks: usize,
    task: impl Fn(usize) -> T + Sync,
) -> Vec<T> {
    let threads = threads.min(tasks);
    if threads <= 1 {
        return (0..tasks).map(task).collect();
    }
    let next = AtomicUsize::new(0);
    let done: Mutex<Vec<(usize, T)>> = Mutex::new(Vec::with_capacity(tasks));
    let run = || loop {
        let i = next.fetch_add(1, Ordering::Relaxed);
        if i >= tasks {
            break;
        }
        let result = task(i);
        done.lock()
            .expect("no thread panics holding it")
            .push((i, result));
    };
    std::thread::scope(|scope| {
        for _ in 1..threads {
            scope.spawn(run);
        }
        run();
    });
    let mut done = done.into_inner().expect("no thread panicked");
    done.sort_by_key(|(i, _)| *i);
    done.into_iter().map(|(_, result)| result).collect()
}

/// Runs `job(w)` for `w in 0..workers` on that many threads; results in worker order.
pub(super) fn parallel<T: Send>(workers: usize, job: impl Fn(usize) -> T + Sync) -> Vec<T> {
    shared_out(workers, workers, job)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn results_come_back_in_task_order_whatever_the_threads() {
        // Tasks of very different cost, so threads finish out of order.
        let work = |i: usize| {
            let mut x = i as u64;
            for _ in 0..(i % 3) * 20_000 {
                x = x.wrapping_mul(6364136223846793005).wrapping_add(1);
            }
            (i, x)
        };
        let one = shared_out(1, 17, work);
        for threads in [2, 3, 8] {
            assert_eq!(shared_out(threads, 17, work), one);
        }
        assert_eq!(
            one.iter().map(|r| r.0).collect::<Vec<_>>(),
            (0..17).collect::<Vec<_>>()
        );
    }
}
