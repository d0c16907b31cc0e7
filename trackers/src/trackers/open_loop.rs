//! `open-loop`: replays the plan's controls on their schedule and ignores observations (the
//! seed's open-loop tracker, Sec. V-A).

use magbench_env::{Control, declare_params};

use crate::closed_loop::LoopOptions;
use crate::tracker::{Tick, Tracker, TrackerContext, TrackerStatus};

declare_params! {
    /// Replays the reference's controls by time; finished at the reference's end.
    #[derive(Debug, Clone)]
    pub struct OpenLoop {
        progress: usize = 0,
        done: bool = false,
    }
}

impl OpenLoop {
    /// A new open-loop tracker.
    pub fn new() -> Self {
        Self::default()
    }
}

impl Tracker for OpenLoop {
    fn name(&self) -> &str {
        "open-loop"
    }

    /// An open-loop plan is not replanned on error (it ignores the error it would see).
    fn loop_options(&self) -> LoopOptions {
        LoopOptions {
            replan_after: 0.0,
            ..LoopOptions::default()
        }
    }

    fn reset(&mut self, _ctx: &TrackerContext) {
        self.progress = 0;
        self.done = false;
    }

    fn command(&mut self, ctx: &TrackerContext, tick: &Tick) -> Control {
        let r = ctx.reference;
        self.progress = r.index_at(tick.t);
        match r.control(self.progress) {
            Some(u) => *u,
            None => {
                self.done = true;
                r.control(r.last().saturating_sub(1))
                    .copied()
                    .unwrap_or_default()
            }
        }
    }

    fn status(&self) -> TrackerStatus {
        TrackerStatus {
            mode: "open-loop",
            progress: self.progress,
            targets: None,
        }
    }

    fn finished(&self) -> bool {
        self.done
    }
}
