//! The progress line of `plan` and `track` on a terminal: the planner's iterations against its
//! budget, its best cost and the elapsed time; while tracking, the elapsed time and the last
//! replan's progress. Drawn on stderr, and only when stderr is a terminal and the command
//! does not print JSON.

use std::io::IsTerminal;
use std::time::Duration;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use magbench_planners::ProgressPoint;
use magbench_planners::progress::Observer;

/// A progress line, or nothing (not a terminal, or `--json`).
pub struct Progress {
    bar: Option<ProgressBar>,
}

fn style(template: &str) -> ProgressStyle {
    ProgressStyle::with_template(template)
        .unwrap_or_else(|_| ProgressStyle::default_bar())
        .progress_chars("=> ")
}

/// The message of a progress point: its best cost, or that there is none yet.
pub fn cost_message(p: &ProgressPoint) -> String {
    match p.best_cost {
        Some(c) => format!("best cost {c:.3}"),
        None => "no solution yet".to_string(),
    }
}

impl Progress {
    /// A progress line on stderr if `wanted` and stderr is a terminal.
    pub fn new(wanted: bool) -> Self {
        let bar = (wanted && std::io::stderr().is_terminal())
            .then(|| ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr()));
        Progress { bar }
    }

    /// An observer for [`magbench_planners::progress::observe`] that shows the planner's
    /// progress under `prefix` (e.g. `leg 1/3`).
    pub fn planning(&self, prefix: String) -> Observer {
        let Some(bar) = self.bar.clone() else {
            return Box::new(|_, _| {});
        };
        bar.reset();
        bar.set_prefix(prefix);
        let mut known = None;
        Box::new(move |p, budget| {
            if known != Some(budget) {
                known = Some(budget);
                if budget == u64::MAX {
                    bar.set_length(0);
                    bar.set_style(style(
                        "{prefix} {spinner} {pos} iterations, {msg}, {elapsed_precise}",
                    ));
                } else {
                    bar.set_length(budget);
                    bar.set_style(style(
                        "{prefix} [{bar:30}] {pos}/{len} iterations, {msg}, {elapsed_precise}",
                    ));
                }
            }
            bar.set_position(p.iteration);
            bar.set_message(cost_message(p));
        })
    }

    /// An observer for the tracking loop: a spinner with the elapsed time, and the progress of
    /// the replans the loop makes.
    pub fn tracking(&self) -> Observer {
        let Some(bar) = self.bar.clone() else {
            return Box::new(|_, _| {});
        };
        bar.reset();
        bar.set_prefix("tracking");
        bar.set_style(style("{prefix} {spinner} {elapsed_precise} {msg}"));
        bar.set_message(String::new());
        bar.enable_steady_tick(Duration::from_millis(200));
        Box::new(move |p, _| {
            bar.set_message(format!(
                "(replanning: iteration {}, {})",
                p.iteration,
                cost_message(p)
            ));
        })
    }

    /// Removes the line (before the command's summary is printed).
    pub fn clear(&self) {
        if let Some(b) = &self.bar {
            b.finish_and_clear();
        }
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        self.clear();
    }
}
