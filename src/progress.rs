//! Progress of long runs, reported to an embedding program.
//!
//! The binary shows its own bars on stderr (indicatif); a program that
//! embeds flank (the Python package, a notebook, a GUI) has no terminal to
//! draw on and wants the figures instead: which stage of a run is under
//! way and how many of its steps are done. [`observe`] installs one
//! observer for the process; the long loops call [`report`] (or step a
//! [`Counter`] from their parallel iterations), which costs one atomic
//! load when nobody observes.
//!
//! Stages and their steps (the `task` names are stable; scripts may match
//! them):
//!
//! | task | step | where |
//! |---|---|---|
//! | `ltca positions` | one position of a cycle solved | [`crate::ltca::cycle::LtcaCycle::solve_cycle`] and the map over torque (one stage per torque) |
//! | `fe positions` | one FE contact position solved | [`crate::mesh_cycle::run`] (the total grows when a default range is extended) |
//! | `campaign jobs` | one job finished or failed | [`crate::campaign::local`] |
//!
//! There is one observer per process (the last [`observe`] wins until its
//! guard is dropped); runs on several threads at once report to the same
//! observer, which must be `Send + Sync`. The observer is called on the
//! thread that finished the step: it must return quickly (queue the event,
//! do not draw).

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, RwLock};

/// One progress event: `done` of `total` steps of the stage `task`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Progress<'a> {
    /// The stage (see the module's table).
    pub task: &'a str,
    /// Steps done so far (0 at the start of a stage).
    pub done: usize,
    /// Steps in the stage (as known now; may grow).
    pub total: usize,
}

/// What [`observe`] installs.
pub type Observer = Arc<dyn Fn(Progress<'_>) + Send + Sync>;

fn slot() -> &'static RwLock<Option<Observer>> {
    static SLOT: RwLock<Option<Observer>> = RwLock::new(None);
    &SLOT
}

/// Whether an observer is installed (read without the lock).
static OBSERVED: AtomicBool = AtomicBool::new(false);

/// Installs `observer` for the process until the returned guard is
/// dropped (then no observer is installed).
#[must_use = "the observer is removed when the guard is dropped"]
pub fn observe(observer: Observer) -> ObserverGuard {
    if let Ok(mut s) = slot().write() {
        *s = Some(observer);
        OBSERVED.store(true, Ordering::Release);
    }
    ObserverGuard { _private: () }
}

/// Removes the observer when dropped.
pub struct ObserverGuard {
    _private: (),
}

impl Drop for ObserverGuard {
    fn drop(&mut self) {
        if let Ok(mut s) = slot().write() {
            *s = None;
        }
        OBSERVED.store(false, Ordering::Release);
    }
}

/// Whether an observer is installed: the binary's own bars stay hidden
/// then, so that a terminal does not show the same progress twice.
pub fn observed() -> bool {
    OBSERVED.load(Ordering::Acquire)
}

/// Reports `done` of `total` steps of `task` to the observer, if any.
pub fn report(task: &str, done: usize, total: usize) {
    if !observed() {
        return;
    }
    let observer = slot().read().ok().and_then(|s| s.clone());
    if let Some(o) = observer {
        o(Progress { task, done, total });
    }
}

/// A stage's step counter, safe to step from parallel iterations: each
/// [`Counter::step`] reports the count reached (so the observer sees
/// 1, 2, …, total in some order of arrival, each count once).
pub struct Counter {
    task: &'static str,
    total: AtomicUsize,
    done: AtomicUsize,
}

impl Counter {
    /// A stage of `total` steps; reports 0 of `total` at once.
    pub fn start(task: &'static str, total: usize) -> Counter {
        report(task, 0, total);
        Counter {
            task,
            total: AtomicUsize::new(total),
            done: AtomicUsize::new(0),
        }
    }

    /// One step done.
    pub fn step(&self) {
        let done = self.done.fetch_add(1, Ordering::AcqRel) + 1;
        report(self.task, done, self.total.load(Ordering::Acquire));
    }

    /// `n` more steps in the stage (a range extended while it runs).
    pub fn grow(&self, n: usize) {
        self.total.fetch_add(n, Ordering::AcqRel);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Mutex;

    /// One test drives the process-wide observer (tests run in parallel:
    /// a second test of the slot would see this one's events).
    #[test]
    fn an_observer_sees_every_count_once_and_nothing_after_its_guard() {
        use rayon::prelude::*;
        let seen: Arc<Mutex<Vec<(String, usize, usize)>>> = Arc::default();
        let sink = seen.clone();
        let guard = observe(Arc::new(move |p: Progress<'_>| {
            sink.lock()
                .unwrap()
                .push((p.task.to_string(), p.done, p.total))
        }));
        assert!(observed());
        let c = Counter::start("test stage", 40);
        (0..40).into_par_iter().for_each(|_| c.step());
        c.grow(2);
        c.step();
        c.step();
        drop(guard);
        assert!(!observed());
        report("after", 1, 1);
        let seen = seen.lock().unwrap();
        assert_eq!(seen[0], ("test stage".to_string(), 0, 40));
        let mut counts: Vec<usize> = seen[1..].iter().map(|e| e.1).collect();
        counts.sort_unstable();
        assert_eq!(counts, (1..=42).collect::<Vec<_>>());
        assert!(seen.iter().all(|e| e.0 == "test stage"));
        // the two steps after the growth know the new total
        assert_eq!(seen.iter().filter(|e| e.2 == 42).count(), 2);
    }
}
