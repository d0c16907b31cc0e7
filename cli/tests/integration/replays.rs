//! Replays by policy (`bench --replays`, the experiment file's `replays`): which runs get a
//! page, that a choice does not depend on the threads, a resume or the shards, that the pages
//! share the folder's player, and that every link of the report resolves.
//!
//! The sweeps are small real ones (the fake executor records no replays): iteration limits
//! only, so every run and its outcome are the same on any machine.

use crate::common;

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use common::{magbench, write};
use magbench::replay::policy::{self, ReplayPolicy};
use magbench::results::store::read_runs;

/// 12 runs in 3 configurations, some of which fail: planning runs of two planners with a small
/// budget, and goal-zoom-rrt's plans tracked open loop on the realistic plant.
const EXP: &str = r#"
name = "replays"
scenarios = ["open-field"]
planners = ["goal-zoom-rrt", "rrt-star"]
seeds = 4
[limits]
iterations = 300
[tracking]
plans = ["goal-zoom-rrt"]
trackers = ["open-loop"]
presets = ["realistic"]
"#;

const RUNS: usize = 12;

/// Runs `bench` of the experiment `text` into `dir/name` with `extra` arguments; the folder.
fn bench(dir: &Path, name: &str, text: &str, extra: &[&str]) -> PathBuf {
    let exp = write(dir, &format!("{name}.toml"), text);
    let out = dir.join(name);
    let mut args = vec![
        "bench",
        exp.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ];
    args.extend_from_slice(extra);
    let (code, _, stderr) = magbench(&args);
    assert_eq!(code, 0, "{args:?}: {stderr}");
    out
}

/// The run indices of the replay pages in `dir/replays`.
fn pages(dir: &Path) -> BTreeSet<usize> {
    let Ok(entries) = std::fs::read_dir(dir.join("replays")) else {
        return BTreeSet::new();
    };
    entries
        .flatten()
        .filter_map(|e| {
            let name = e.file_name().to_string_lossy().to_string();
            name.strip_prefix("run-")?
                .strip_suffix(".html")?
                .parse()
                .ok()
        })
        .collect()
}

/// The values of every `attr="…"` in `html`.
fn attrs<'a>(html: &'a str, attr: &str) -> Vec<&'a str> {
    let key = format!("{attr}=\"");
    html.match_indices(&key)
        .map(|(i, _)| {
            let rest = &html[i + key.len()..];
            &rest[..rest.find('"').expect("a closing quote")]
        })
        .collect()
}

/// Asserts that every local `href` and `src` of the HTML file `page` names an existing file
/// (relative to the page's folder); the local links.
fn links_resolve(page: &Path) -> Vec<String> {
    let html = std::fs::read_to_string(page).unwrap();
    let base = page.parent().unwrap();
    let mut local = vec![];
    for link in attrs(&html, "href").into_iter().chain(attrs(&html, "src")) {
        if link.starts_with('#') || link.starts_with("data:") || link.contains("://") {
            continue;
        }
        let file = link.split('#').next().unwrap();
        assert!(
            base.join(file).is_file(),
            "{}: the link {link:?} resolves to no file",
            page.display()
        );
        local.push(link.to_string());
    }
    local
}

/// The report's links to replays, as run indices.
fn report_replays(dir: &Path) -> BTreeSet<usize> {
    links_resolve(&dir.join("report.html"))
        .iter()
        .filter_map(|l| {
            l.strip_prefix("replays/run-")?
                .strip_suffix(".html")?
                .parse()
                .ok()
        })
        .collect()
}

/// The indices of the failed runs of `dir`.
fn failed_runs(dir: &Path) -> BTreeSet<usize> {
    read_runs(dir)
        .unwrap()
        .iter()
        .filter(|r| policy::failed(r))
        .map(|r| r.run)
        .collect()
}

#[test]
fn none_writes_no_page_and_the_report_links_none() {
    let dir = tempfile::tempdir().unwrap();
    let out = bench(dir.path(), "none", EXP, &["--replays", "none"]);
    assert_eq!(read_runs(&out).unwrap().len(), RUNS);
    assert_eq!(pages(&out), BTreeSet::new());
    assert!(!out.join("replays/player.js").exists());
    assert_eq!(report_replays(&out), BTreeSet::new());
    let report = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(report.contains("no replay"), "the report says why");
}

#[test]
fn failed_writes_exactly_the_failed_runs_pages() {
    let dir = tempfile::tempdir().unwrap();
    let out = bench(dir.path(), "failed", EXP, &["--replays", "failed"]);
    let failed = failed_runs(&out);
    assert!(
        !failed.is_empty() && failed.len() < RUNS,
        "the experiment has failed and successful runs: {failed:?}"
    );
    assert_eq!(pages(&out), failed);
    assert_eq!(report_replays(&out), failed);
}

#[test]
fn a_sample_is_the_same_at_one_and_two_threads_and_spans_the_configurations() {
    let dir = tempfile::tempdir().unwrap();
    let one = bench(
        dir.path(),
        "t1",
        EXP,
        &["--replays", "sample:5", "--threads", "1"],
    );
    let two = bench(
        dir.path(),
        "t2",
        EXP,
        &["--replays", "sample:5", "--threads", "2"],
    );
    assert_eq!(pages(&one).len(), 5);
    assert_eq!(pages(&one), pages(&two));
    assert_eq!(report_replays(&one), pages(&one));
    let runs = read_runs(&one).unwrap();
    let configs: BTreeSet<(String, String)> = runs
        .iter()
        .filter(|r| pages(&one).contains(&r.run))
        .map(|r| (r.planner.clone(), r.tracker.clone()))
        .collect();
    assert_eq!(configs.len(), 3, "one run of each configuration first");
}

#[test]
fn the_file_key_applies_and_the_option_overrides_it() {
    let dir = tempfile::tempdir().unwrap();
    let text = EXP.replace("seeds = 4", "seeds = 4\nreplays = \"sample:2\"");
    let out = bench(dir.path(), "file", &text, &[]);
    assert_eq!(pages(&out).len(), 2);
    let out = bench(dir.path(), "over", &text, &["--replays", "all"]);
    assert_eq!(pages(&out).len(), RUNS);
}

#[test]
fn the_default_writes_the_failed_runs_and_a_sample() {
    let dir = tempfile::tempdir().unwrap();
    let out = bench(dir.path(), "default", EXP, &[]);
    let p: ReplayPolicy = policy::DEFAULT.parse().unwrap();
    assert!(p.failed && p.sample > 0, "{p}");
    let e = magbench::experiment::Experiment::load(
        &dir.path().join("default.toml"),
        &magbench::run::real::RealExecutor::default(),
    )
    .unwrap();
    let want: BTreeSet<usize> = failed_runs(&out)
        .union(&policy::sample(e.run_ids(), p.sample))
        .copied()
        .collect();
    assert_eq!(pages(&out), want);
    assert_eq!(report_replays(&out), want);
}

#[test]
fn pages_share_the_folders_player_and_their_links_resolve() {
    let dir = tempfile::tempdir().unwrap();
    let out = bench(dir.path(), "all", EXP, &["--replays", "all"]);
    let player = std::fs::read_to_string(out.join("replays/player.js")).unwrap();
    assert!(player.contains("replay-data"), "the player script");
    assert!(out.join("replays/player.css").is_file());
    assert_eq!(pages(&out).len(), RUNS);
    for run in pages(&out) {
        let page = out.join(format!("replays/run-{run}.html"));
        let links = links_resolve(&page);
        assert!(links.contains(&"player.js".to_string()), "{links:?}");
        assert!(links.contains(&"player.css".to_string()), "{links:?}");
        let html = std::fs::read_to_string(&page).unwrap();
        assert!(
            !html.contains("replay-data\").textContent"),
            "run {run}: the player is not copied into the page"
        );
        // the data is packed (replay/pack.rs): a pair's page stays within 30 kB
        assert!(html.contains("\"packed\":\""), "run {run}: packed data");
        assert!(html.len() <= 30_000, "run {run}: {} bytes", html.len());
    }
    assert_eq!(report_replays(&out), pages(&out));
    // a page on its own (plan --out) keeps its player inside
    let (plan, _) = common::plan_json(dir.path());
    let page = plan.with_file_name("replay.html");
    assert!(
        std::fs::read_to_string(&page)
            .unwrap()
            .contains("replay-data\").textContent")
    );
    assert_eq!(links_resolve(&page), Vec::<String>::new());
}

/// Drops the last `k` rows of `runs.csv` in `dir` (their progress rows become orphans that
/// the resume's repair drops): the folder of a sweep killed before those runs finished.
fn drop_last_runs(dir: &Path, k: usize) -> Vec<usize> {
    let path = dir.join("runs.csv");
    let text = std::fs::read_to_string(&path).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let keep = lines.len() - k;
    std::fs::write(&path, lines[..keep].join("\n") + "\n").unwrap();
    lines[keep..]
        .iter()
        .map(|l| l.split(',').next().unwrap().parse().unwrap())
        .collect()
}

#[test]
fn a_resumed_sweep_writes_the_same_pages_and_no_run_twice() {
    let dir = tempfile::tempdir().unwrap();
    let policy = ["--replays", "failed+sample:3"];
    let whole = bench(dir.path(), "whole", EXP, &policy);
    let want = pages(&whole);
    let cut = dir.path().join("cut");
    common::copy_dir(&whole, &cut, &[]);
    let dropped = drop_last_runs(&cut, 5);
    // the dropped runs' pages: one lost, the others left by the killed sweep, and a page the
    // policy does not choose for a dropped run (written under another policy)
    let stray = dropped.iter().copied().find(|r| !want.contains(r));
    assert!(
        stray.is_some() && dropped.iter().any(|r| want.contains(r)),
        "the dropped runs {dropped:?} include chosen and unchosen ones ({want:?})"
    );
    for r in &dropped {
        if want.contains(r) {
            std::fs::remove_file(cut.join(format!("replays/run-{r}.html"))).unwrap();
            break;
        }
    }
    if let Some(r) = stray {
        std::fs::write(cut.join(format!("replays/run-{r}.html")), "stale").unwrap();
    }
    let exp = dir.path().join("whole.toml");
    let (code, _, stderr) = magbench(&[
        "bench",
        exp.to_str().unwrap(),
        "--out",
        cut.to_str().unwrap(),
        "--resume",
        "--quiet",
        "--threads",
        "1",
        policy[0],
        policy[1],
    ]);
    assert_eq!(code, 0, "{stderr}");
    let runs = read_runs(&cut).unwrap();
    let ids: BTreeSet<&str> = runs.iter().map(|r| r.run_id.as_str()).collect();
    assert_eq!(
        (runs.len(), ids.len()),
        (RUNS, RUNS),
        "no run lost or doubled"
    );
    assert_eq!(pages(&cut), want);
    assert_eq!(report_replays(&cut), want);
    let (code, _, stderr) = magbench(&["results", "verify", cut.to_str().unwrap()]);
    assert_eq!(code, 0, "{stderr}");
}

#[test]
fn merged_shards_have_the_pages_of_one_sweep() {
    let dir = tempfile::tempdir().unwrap();
    let policy = ["--replays", "sample:4"];
    let whole = bench(dir.path(), "whole", EXP, &policy);
    let a = bench(
        dir.path(),
        "a",
        EXP,
        &[policy[0], policy[1], "--shard", "1/2"],
    );
    let b = bench(
        dir.path(),
        "b",
        EXP,
        &[policy[0], policy[1], "--shard", "2/2"],
    );
    let merged = dir.path().join("merged");
    let (code, _, stderr) = magbench(&[
        "merge",
        a.to_str().unwrap(),
        b.to_str().unwrap(),
        "--out",
        merged.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert_eq!(read_runs(&merged).unwrap().len(), RUNS);
    assert_eq!(pages(&merged), pages(&whole));
    assert_eq!(pages(&merged).len(), 4);
    assert!(merged.join("replays/player.js").is_file());
    assert_eq!(report_replays(&merged), pages(&whole));
}
