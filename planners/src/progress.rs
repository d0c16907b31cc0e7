//! Limits and the progress trace: best cost against iteration and time.

use std::cell::RefCell;
use std::time::Instant;

use crate::{Problem, ProgressPoint};

/// What an observer is told: the point just recorded and the run's iteration budget
/// (`u64::MAX` without an iteration limit).
pub type Observer = Box<dyn FnMut(&ProgressPoint, u64)>;

thread_local! {
    static OBSERVER: RefCell<Option<Observer>> = const { RefCell::new(None) };
}

/// Runs `f` with `observer` told of every progress point that planners record on this thread
/// (at every 1% of the budget and every change of the best cost), e.g. to draw a progress bar.
pub fn observe<R>(observer: Observer, f: impl FnOnce() -> R) -> R {
    struct Reset(Option<Observer>);
    impl Drop for Reset {
        fn drop(&mut self) {
            let previous = self.0.take();
            OBSERVER.with(|o| *o.borrow_mut() = previous);
        }
    }
    let previous = OBSERVER.with(|o| o.borrow_mut().replace(observer));
    let _reset = Reset(previous);
    f()
}

fn tell(p: &ProgressPoint, budget: u64) {
    OBSERVER.with(|o| {
        if let Some(f) = o.try_borrow_mut().ok().as_mut().and_then(|o| o.as_mut()) {
            f(p, budget);
        }
    });
}

/// Watches a run's limits and records its progress trace: a point whenever the best cost
/// changes, and at least at every 1% of the iteration budget and of the time budget.
#[derive(Debug)]
pub struct Progress {
    start: Instant,
    max_iterations: u64,
    time_limit: Option<f64>,
    iteration_step: u64,
    next_iteration_mark: u64,
    next_time_mark: f64,
    best: Option<f64>,
    trace: Vec<ProgressPoint>,
}

impl Progress {
    /// Starts the clock for `problem`'s limits and records iteration 0.
    pub fn start(problem: &Problem) -> Self {
        let max_iterations = problem.max_iterations();
        let time_limit = problem.limits.time_limit.map(|t| t.as_secs_f64());
        let iteration_step = if max_iterations == u64::MAX {
            u64::MAX
        } else {
            (max_iterations / 100).max(1)
        };
        let mut p = Progress {
            start: Instant::now(),
            max_iterations,
            time_limit,
            iteration_step,
            next_iteration_mark: iteration_step,
            next_time_mark: time_limit.map(|t| t / 100.0).unwrap_or(f64::INFINITY),
            best: None,
            trace: Vec::new(),
        };
        p.trace.push(ProgressPoint {
            iteration: 0,
            time_s: 0.0,
            best_cost: None,
        });
        p
    }

    /// Seconds since the start.
    pub fn elapsed(&self) -> f64 {
        self.start.elapsed().as_secs_f64()
    }

    /// True when `iterations` done reach a limit.
    #[inline]
    pub fn done(&self, iterations: u64) -> bool {
        iterations >= self.max_iterations || self.time_limit.is_some_and(|t| self.elapsed() >= t)
    }

    /// Records the state after `iteration` iterations with best cost `best`.
    #[inline]
    pub fn record(&mut self, iteration: u64, best: Option<f64>) {
        let changed = best != self.best;
        let mut due = iteration >= self.next_iteration_mark;
        let mut now = None;
        if self.time_limit.is_some() {
            let t = self.elapsed();
            now = Some(t);
            due |= t >= self.next_time_mark;
        }
        if !(changed || due) {
            return;
        }
        let t = now.unwrap_or_else(|| self.elapsed());
        while iteration >= self.next_iteration_mark {
            self.next_iteration_mark = self.next_iteration_mark.saturating_add(self.iteration_step);
        }
        if let Some(limit) = self.time_limit {
            while t >= self.next_time_mark {
                self.next_time_mark += limit / 100.0;
            }
        }
        self.best = best;
        let p = ProgressPoint {
            iteration,
            time_s: t,
            best_cost: best,
        };
        tell(&p, self.max_iterations);
        self.trace.push(p);
    }

    /// Closes the trace at `iteration` and returns it with the elapsed time.
    pub fn finish(mut self, iteration: u64, best: Option<f64>) -> (Vec<ProgressPoint>, f64) {
        let t = self.elapsed();
        if self
            .trace
            .last()
            .is_none_or(|p| p.iteration != iteration || p.best_cost != best)
        {
            self.trace.push(ProgressPoint {
                iteration,
                time_s: t,
                best_cost: best,
            });
        }
        if let Some(p) = self.trace.last() {
            tell(p, self.max_iterations);
        }
        (self.trace, t)
    }
}
