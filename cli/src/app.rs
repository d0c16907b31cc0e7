//! [`Cli`]: the whole `magbench` command line as a library, with a registry a plugin extends.
//!
//! A plugin crate's `main.rs` is a few lines, and its binary has every subcommand of
//! `magbench` with the plugin's planners, trackers and rigs beside the built-ins:
//!
//! ```no_run
//! # use magbench::prelude::*;
//! # #[derive(Default)] struct MyRrt;
//! # impl ParamSet for MyRrt {}
//! # impl Planner for MyRrt {
//! #     fn name(&self) -> &str { "my-rrt" }
//! #     fn solve(&mut self, p: &Problem) -> PlannerResult { unimplemented!() }
//! # }
//! fn main() -> std::process::ExitCode {
//!     magbench::Cli::new().planner::<MyRrt>("my-rrt").run()
//! }
//! ```

use std::ffi::OsString;
use std::process::ExitCode;

use clap::Parser;
use magbench_drivers::rigs::{RigDescription, RigKind};
use magbench_env::InputError;
use magbench_planners::Planner;
use magbench_trackers::Tracker;

use crate::Error;
use crate::cli::{self, Args};
use crate::registry::Registry;

/// The whole `magbench` command line with a registry.
#[derive(Clone, Debug)]
pub struct Cli {
    registry: Registry,
}

impl Default for Cli {
    /// The command line with the built-in registry.
    fn default() -> Self {
        Cli::new()
    }
}

impl Cli {
    /// The command line with the built-in planners, trackers and rigs ([`Registry::builtin`]).
    pub fn new() -> Cli {
        Cli::with_registry(Registry::builtin())
    }

    /// The command line with `registry`.
    pub fn with_registry(registry: Registry) -> Cli {
        Cli { registry }
    }

    /// Adds planner `P` (made by `P::default()`) as `name`.
    ///
    /// # Panics
    ///
    /// When `name` is taken or malformed: a mistake in the program, not in its input.
    pub fn planner<P: Planner + Default + 'static>(mut self, name: &str) -> Cli {
        let summary = format!("{} (plugin)", std::any::type_name::<P>());
        if let Err(e) = self
            .registry
            .add_planner(name, &summary, || Box::new(P::default()))
        {
            panic!(
                "magbench::Cli::planner::<{}>: {e}",
                std::any::type_name::<P>()
            );
        }
        self
    }

    /// Adds tracker `T` (made by `T::default()`) as `name`.
    ///
    /// # Panics
    ///
    /// When `name` is taken or malformed: a mistake in the program, not in its input.
    pub fn tracker<T: Tracker + Default + 'static>(mut self, name: &str) -> Cli {
        let summary = format!("{} (plugin)", std::any::type_name::<T>());
        if let Err(e) = self
            .registry
            .add_tracker(name, &summary, || Box::new(T::default()))
        {
            panic!(
                "magbench::Cli::tracker::<{}>: {e}",
                std::any::type_name::<T>()
            );
        }
        self
    }

    /// Adds rig kind `R` as `name`: `track --rig-type NAME --preset ARG` and
    /// `rig run --rig-type NAME --rig ARG` load it with [`RigKind::load`].
    ///
    /// # Panics
    ///
    /// When `name` is taken or malformed: a mistake in the program, not in its input.
    pub fn rig<R: RigKind>(mut self, name: &str) -> Cli {
        let summary = format!("{} (plugin)", std::any::type_name::<R>());
        if let Err(e) = self.registry.add_rig(name, &summary, |arg, option| {
            Ok(Box::new(R::load(arg, option)?) as Box<dyn RigDescription>)
        }) {
            panic!("magbench::Cli::rig::<{}>: {e}", std::any::type_name::<R>());
        }
        self
    }

    /// The registry, to add entries with a summary or a constructor of their own.
    pub fn registry_mut(&mut self) -> &mut Registry {
        &mut self.registry
    }

    /// The registry.
    pub fn registry(&self) -> &Registry {
        &self.registry
    }

    /// Parses the process's arguments and runs the command, as the `magbench` binary does:
    /// usage errors and `--help` as clap prints them, other errors as `error: ...` on stderr
    /// with exit code 2 for bad input and 1 otherwise.
    pub fn run(self) -> ExitCode {
        let args = match Args::try_parse_from(std::env::args_os()) {
            Ok(a) => a,
            Err(e) => {
                let _ = e.print();
                return ExitCode::from(e.exit_code().clamp(0, 255) as u8);
            }
        };
        match cli::run(args, &self.registry) {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("error: {e}");
                ExitCode::from(e.exit_code())
            }
        }
    }

    /// Runs the command line `args` (`args[0]` is the program name). `--help` and `--version`
    /// print and succeed; a usage error is an input error on the field `arguments`.
    pub fn run_args<I, S>(&self, args: I) -> Result<(), Error>
    where
        I: IntoIterator<Item = S>,
        S: Into<OsString> + Clone,
    {
        let args = match Args::try_parse_from(args) {
            Ok(a) => a,
            Err(e) if e.exit_code() == 0 => {
                let _ = e.print();
                return Ok(());
            }
            Err(e) => {
                let text = e.to_string();
                let reason = text.trim().trim_start_matches("error: ");
                return Err(InputError::new("<command line>", "arguments", reason).into());
            }
        };
        cli::run(args, &self.registry)
    }
}

#[cfg(test)]
mod tests {
    use magbench_planners::planners::GoalZoomRrt;
    use magbench_trackers::Obc;

    use super::*;

    fn plugin_cli() -> Cli {
        Cli::new()
            .planner::<GoalZoomRrt>("my-rrt")
            .tracker::<Obc>("my-obc")
    }

    #[test]
    fn a_plugin_is_named_in_experiment_files_beside_the_built_ins() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("exp.toml");
        std::fs::write(
            &file,
            "scenarios = [\"open-field\"]\nplanners = [\"goal-zoom-rrt\", \"my-rrt{k=3}\"]\n\
             trackers = [\"obc\", \"my-obc{eps=0.3}\"]\nseeds = 1\n[limits]\niterations = 100\n",
        )
        .unwrap();
        let args = |cli: &Cli| cli.run_args(["x", "bench", "--dry-run", file.to_str().unwrap()]);
        if let Err(e) = args(&plugin_cli()) {
            panic!("{e}");
        }
        // the built-in registry does not know them: the file, the field and the names it knows
        let e = args(&Cli::new()).err().unwrap().to_string();
        assert!(
            e.contains("exp.toml") && e.contains("unknown planner \"my-rrt\"") && e.contains("sst"),
            "{e}"
        );
    }

    #[test]
    fn unknown_names_list_the_plugins_and_usage_errors_are_input_errors() {
        let e = plugin_cli()
            .run_args(["x", "plan", "open-field", "--planner", "my-rtt"])
            .err()
            .unwrap();
        assert_eq!(e.exit_code(), 2);
        let text = e.to_string();
        assert!(
            text.contains("my-rrt") && text.contains("goal-zoom-rrt"),
            "{text}"
        );
        let e = plugin_cli()
            .run_args(["x", "track", "open-field", "--tracker", "pid"])
            .err()
            .unwrap();
        assert!(e.to_string().contains("my-obc"), "{e}");
        let e = plugin_cli()
            .run_args(["x", "plan", "--no-such-option"])
            .err()
            .unwrap();
        assert_eq!(e.exit_code(), 2);
        assert!(e.to_string().contains("<command line>: arguments:"), "{e}");
    }

    #[test]
    #[should_panic(expected = "a planner called \"sst\" is already registered")]
    fn a_duplicate_name_is_a_programming_error() {
        let _ = Cli::new().planner::<GoalZoomRrt>("sst");
    }
}
