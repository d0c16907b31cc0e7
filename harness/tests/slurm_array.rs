//! `experiments/slurm-array.sh` run as two array tasks (with a stand-in `sbatch` that records
//! the merge job), then the recorded merge: the result equals an unsharded sweep.

mod common;

use std::path::Path;
use std::process::Command;

use common::{deterministic_runs, write};

#[test]
fn job_array_then_merge_equals_an_unsharded_sweep() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../experiments/slurm-array.sh");
    let bin = env!("CARGO_BIN_EXE_magbench");
    write(
        d,
        "exp.toml",
        "name = \"slurm-test\"\nscenarios = [\"open-field\", \"micro-factory\"]\nplanners = [\"fake\", \"fake{p=0.2}\"]\nseeds = 5\n[limits]\niterations = 300\n",
    );
    let fake_bin = d.join("bin");
    std::fs::create_dir_all(&fake_bin).unwrap();
    let sbatch = write(
        &fake_bin,
        "sbatch",
        "#!/bin/sh\nfor a in \"$@\"; do case \"$a\" in --wrap=*) echo \"${a#--wrap=}\" >> \"$SBATCH_LOG\";; esac; done\n",
    );
    Command::new("chmod")
        .arg("+x")
        .arg(&sbatch)
        .status()
        .unwrap();
    let path = format!(
        "{}:{}",
        fake_bin.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    for task in 1..=2 {
        let o = Command::new("bash")
            .arg(&script)
            .arg("exp.toml")
            .current_dir(d)
            .env("PATH", &path)
            .env("SBATCH_LOG", d.join("sbatch.log"))
            .env("MAGBENCH", bin)
            .env("MAGBENCH_ARGS", "--executor fake")
            .env("SLURM_SUBMIT_DIR", d)
            .env("SLURM_ARRAY_TASK_ID", task.to_string())
            .env("SLURM_ARRAY_TASK_COUNT", "2")
            .env("SLURM_ARRAY_TASK_MIN", "1")
            .env("SLURM_ARRAY_JOB_ID", "42")
            .env("SLURM_CPUS_PER_TASK", "1")
            .output()
            .unwrap();
        assert!(
            o.status.success(),
            "task {task}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
    }
    let merge = std::fs::read_to_string(d.join("sbatch.log")).unwrap();
    assert_eq!(merge.lines().count(), 1, "one merge job: {merge}");
    let o = Command::new("sh")
        .arg("-c")
        .arg(merge.trim())
        .current_dir(d)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let o = Command::new(bin)
        .args([
            "bench",
            "exp.toml",
            "--executor",
            "fake",
            "--quiet",
            "--out",
            "whole",
        ])
        .current_dir(d)
        .output()
        .unwrap();
    assert!(o.status.success());
    let merged = deterministic_runs(&d.join("results/slurm-test"));
    assert_eq!(merged.len(), 20);
    assert_eq!(merged, deterministic_runs(&d.join("whole")));
}
