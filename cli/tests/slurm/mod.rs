//! A one-node Slurm cluster for the tests (`experiments/slurm-local.sh`), stopped on drop, and
//! the Slurm commands the tests need.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

/// The repository's `experiments/` folder.
pub fn experiments() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../experiments")
}

/// The `run_id` column of the results folder `dir`'s `runs.csv`, in its order.
pub fn run_ids(dir: &Path) -> Vec<String> {
    let mut rd = csv::Reader::from_path(dir.join("runs.csv")).unwrap();
    let col = rd.headers().unwrap().iter().position(|h| h == "run_id");
    rd.records()
        .map(|r| r.unwrap()[col.unwrap()].to_string())
        .collect()
}

/// Writes `experiment` to `root/exp.toml` and runs it unsharded in one process into
/// `root/whole`: the folder an array's merge must equal.
pub fn unsharded(root: &Path, experiment: &str) -> PathBuf {
    crate::common::write(root, "exp.toml", experiment);
    let o = Command::new(env!("CARGO_BIN_EXE_magbench"))
        .args([
            "bench",
            "exp.toml",
            "--threads",
            "2",
            "--quiet",
            "--out",
            "whole",
        ])
        .current_dir(root)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    root.join("whole")
}

/// Says loudly that no local cluster could be started (`why`: the reason and the daemons'
/// logs) and returns, so that the calling test passes; panics instead when
/// `MAGBENCH_REQUIRE_SLURM=1` (set by `.ci/run`).
pub fn skip_or_fail(why: &str) {
    let bar = "!".repeat(78);
    let msg = format!(
        "\n{bar}\nSLURM TEST NOT RUN: no local Slurm cluster could be started, so \
         experiments/slurm-array.sh was NOT tested under Slurm.\nInstall it with \
         `apt-get install slurm-wlm munge` (daemon logs below).\n{why}\n{bar}\n"
    );
    if std::env::var("MAGBENCH_REQUIRE_SLURM").as_deref() == Ok("1") {
        panic!("MAGBENCH_REQUIRE_SLURM=1 and {msg}");
    }
    // Straight to stderr: the test harness captures eprintln! of a passing test.
    let _ = std::io::stderr().write_all(msg.as_bytes());
}

/// A running cluster whose files live in a temporary folder.
pub struct Cluster {
    dir: tempfile::TempDir,
}

/// One job (or array task) as `scontrol show job` reports it.
#[derive(Debug, Clone)]
pub struct Job {
    /// `JobName`.
    pub name: String,
    /// `ArrayJobId` and `ArrayTaskId` of an array task.
    pub array: Option<(String, String)>,
    /// `JobId`.
    pub id: String,
    /// `JobState`, e.g. COMPLETED, CANCELLED.
    pub state: String,
    /// `ExitCode`, e.g. 0:0.
    pub exit_code: String,
}

fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

impl Cluster {
    /// Starts a cluster, or says why it cannot (Slurm or munge not installed, not root, a daemon
    /// that does not come up: the daemons' logs are in the message).
    pub fn start() -> Result<Cluster, String> {
        let dir = tempfile::Builder::new()
            .prefix("magbench-slurm-")
            .tempdir()
            .map_err(|e| format!("temporary folder: {e}"))?;
        let o = Command::new("bash")
            .arg(experiments().join("slurm-local.sh"))
            .arg("start")
            .arg(dir.path())
            .output()
            .map_err(|e| format!("bash: {e}"))?;
        if o.status.success() {
            return Ok(Cluster { dir });
        }
        let mut why = text(&o);
        for log in ["munged.out", "slurmctld.out", "slurmd.out"] {
            if let Ok(t) = std::fs::read_to_string(dir.path().join("log").join(log)) {
                let tail: Vec<&str> = t.lines().rev().take(5).collect();
                why += &format!(
                    "\n{log}: …\n{}",
                    tail.into_iter().rev().collect::<Vec<_>>().join("\n")
                );
            }
        }
        Err(why)
    }

    /// `program` run against this cluster: `SLURM_CONF` set, and no `SLURM_*`/`SBATCH_*`
    /// variables of a job this test may itself run in.
    pub fn command(&self, program: &str) -> Command {
        let mut c = Command::new(program);
        for (k, _) in std::env::vars_os() {
            let k = k.to_string_lossy().to_string();
            if k.starts_with("SLURM_") || k.starts_with("SBATCH_") || k.starts_with("SQUEUE_") {
                c.env_remove(k);
            }
        }
        c.env("SLURM_CONF", self.dir.path().join("slurm.conf"));
        c
    }

    /// Runs `program args` in `cwd` and returns its standard output; panics if it fails.
    pub fn run(&self, cwd: &Path, program: &str, args: &[&str]) -> String {
        let o = self
            .command(program)
            .args(args)
            .current_dir(cwd)
            .output()
            .unwrap_or_else(|e| panic!("{program}: {e}"));
        assert!(o.status.success(), "{program} {args:?}: {}", text(&o));
        String::from_utf8_lossy(&o.stdout).trim().to_string()
    }

    /// `sbatch --parsable ARGS` in `cwd`: the job id.
    pub fn sbatch(&self, cwd: &Path, args: &[&str]) -> String {
        let mut a = vec!["--parsable"];
        a.extend(args);
        self.run(cwd, "sbatch", &a)
    }

    /// Every job the controller still knows (finished ones included).
    pub fn jobs(&self) -> Vec<Job> {
        let out = self.run(self.dir.path(), "scontrol", &["show", "job", "-o"]);
        out.lines()
            .filter(|l| l.starts_with("JobId="))
            .map(|l| {
                let field = |k: &str| {
                    l.split(' ')
                        .find_map(|f| f.strip_prefix(&format!("{k}=")))
                        .unwrap_or_default()
                        .to_string()
                };
                let array = Some((field("ArrayJobId"), field("ArrayTaskId")))
                    .filter(|(j, t)| !j.is_empty() && !t.is_empty());
                Job {
                    name: field("JobName"),
                    array,
                    id: field("JobId"),
                    state: field("JobState"),
                    exit_code: field("ExitCode"),
                }
            })
            .collect()
    }

    /// The jobs that are not finished (pending, running, completing).
    pub fn queue(&self) -> String {
        self.run(self.dir.path(), "squeue", &["-h", "-o", "%i %j %T"])
    }

    /// Polls until `done()` holds, for at most `limit`; panics with `what` and the queue then.
    pub fn wait_until(&self, what: &str, limit: Duration, mut done: impl FnMut() -> bool) {
        let t0 = Instant::now();
        while !done() {
            if t0.elapsed() > limit {
                panic!(
                    "{what}: not within {} s; queue:\n{}\njobs: {:#?}",
                    limit.as_secs(),
                    self.queue(),
                    self.jobs()
                );
            }
            std::thread::sleep(Duration::from_millis(50));
        }
    }

    /// Waits until no job is pending or running.
    pub fn wait_idle(&self, limit: Duration) {
        self.wait_until("the queue emptying", limit, || self.queue().is_empty());
    }
}

impl Drop for Cluster {
    fn drop(&mut self) {
        let o = Command::new("bash")
            .arg(experiments().join("slurm-local.sh"))
            .arg("stop")
            .arg(self.dir.path())
            .output();
        if let Ok(o) = o
            && !o.status.success()
        {
            eprintln!("slurm-local.sh stop: {}", text(&o));
        }
    }
}

/// The tasks of array `job` with their states (`STATE EXIT`), by task number, and the jobs
/// named `merge_job`, among `jobs`.
pub fn split(jobs: &[Job], job: &str, merge_job: &str) -> (Vec<(usize, String)>, Vec<Job>) {
    let mut tasks: Vec<(usize, String)> = jobs
        .iter()
        .filter_map(|j| match &j.array {
            Some((a, t)) if a == job => {
                Some((t.parse().unwrap(), format!("{} {}", j.state, j.exit_code)))
            }
            _ => None,
        })
        .collect();
    tasks.sort();
    let merges = jobs
        .iter()
        .filter(|j| j.name == merge_job)
        .cloned()
        .collect();
    (tasks, merges)
}

/// What the merge job `merge` printed, from its output file in `d`.
pub fn merge_log(d: &Path, merge: &Job) -> String {
    std::fs::read_to_string(d.join(format!("magbench-merge-{}.out", merge.id))).unwrap()
}
