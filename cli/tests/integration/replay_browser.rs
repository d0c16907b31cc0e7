//! Replays, scenario previews and the report in a real browser: Debian's headless `chromium`
//! loads a run's replay at a time given in its URL (`#t=…`), and the test reads the drawn
//! agent positions back from the DOM and compares them with the run's `ticks.csv`; it also
//! takes screenshots (target/tmp/replay-screenshots/) of the replay at three moments, of a
//! scenario preview and of a bench's report.
//!
//! Without chromium on PATH (or at `MAGBENCH_CHROMIUM`) the browser checks are skipped with a
//! message, unless `MAGBENCH_REQUIRE_CHROMIUM=1`, which makes them fail instead.

use crate::common;

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::mpsc;
use std::time::Duration;

use common::magbench;

/// The chromium binary, or `None` (after saying so) when the browser checks are skipped.
fn chromium() -> Option<PathBuf> {
    let found = std::env::var_os("MAGBENCH_CHROMIUM")
        .map(PathBuf::from)
        .filter(|p| p.is_file())
        .or_else(|| {
            std::env::var_os("PATH").and_then(|paths| {
                std::env::split_paths(&paths)
                    .map(|d| d.join("chromium"))
                    .find(|p| p.is_file())
            })
        });
    if found.is_none() {
        let msg = "chromium not found (apt-get install chromium, or set MAGBENCH_CHROMIUM)";
        assert!(
            std::env::var("MAGBENCH_REQUIRE_CHROMIUM").as_deref() != Ok("1"),
            "MAGBENCH_REQUIRE_CHROMIUM=1 but {msg}"
        );
        eprintln!("SKIPPED the browser checks: {msg}");
    }
    found
}

/// Runs headless chromium with `args` then `url`; returns its stdout. The page gets 5 s of
/// virtual time before its DOM or picture is taken: a replay inflates its packed data
/// asynchronously (`DecompressionStream`) after the load event. A browser that has not
/// finished after two minutes is killed and the test fails.
fn browse(chrome: &Path, args: &[&str], url: &str) -> String {
    let profile = tempfile::tempdir().unwrap();
    let mut child = Command::new(chrome)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--hide-scrollbars",
            "--virtual-time-budget=5000",
        ])
        .arg(format!("--user-data-dir={}", profile.path().display()))
        .args(args)
        .arg(url)
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("start chromium");
    let mut stdout = child.stdout.take().unwrap();
    let child = std::sync::Arc::new(std::sync::Mutex::new(child));
    let (done, watch) = mpsc::channel::<()>();
    let watched = child.clone();
    let watchdog = std::thread::spawn(move || {
        if watch.recv_timeout(Duration::from_secs(120)).is_err() {
            // still running: end this one browser process (its output then ends)
            let _ = watched.lock().unwrap().kill();
            true
        } else {
            false
        }
    });
    let mut out = String::new();
    std::io::Read::read_to_string(&mut stdout, &mut out).unwrap();
    let _ = done.send(());
    let hung = watchdog.join().unwrap();
    child.lock().unwrap().wait().unwrap();
    assert!(!hung, "chromium hung on {url}");
    out
}

fn url(path: &Path, hash: &str) -> String {
    format!("file://{}{hash}", path.canonicalize().unwrap().display())
}

/// The opening tag of the element with `id="ID"` in `dom`.
fn tag<'a>(dom: &'a str, id: &str) -> &'a str {
    let at = dom
        .find(&format!("id=\"{id}\""))
        .unwrap_or_else(|| panic!("no element {id} in the DOM"));
    let start = dom[..at].rfind('<').unwrap();
    let end = at + dom[at..].find('>').unwrap();
    &dom[start..=end]
}

/// The value of attribute `name` in opening tag `tag`.
fn attr<'a>(tag: &'a str, name: &str) -> &'a str {
    let key = format!(" {name}=\"");
    let at = tag
        .find(&key)
        .unwrap_or_else(|| panic!("no {name} in {tag}"))
        + key.len();
    &tag[at..at + tag[at..].find('"').unwrap()]
}

fn num(tag: &str, name: &str) -> f64 {
    attr(tag, name)
        .parse()
        .unwrap_or_else(|_| panic!("{name} of {tag} is not a number"))
}

/// The `<body>` tag of `dom`.
fn body(dom: &str) -> &str {
    let at = dom.find("<body").expect("a body");
    &dom[at..=at + dom[at..].find('>').unwrap()]
}

/// `ticks.csv` of a run: time and every agent's true position per tick.
fn ticks(dir: &Path) -> Vec<(f64, Vec<[f64; 2]>)> {
    let mut rd = csv::Reader::from_path(dir.join("ticks.csv")).unwrap();
    let h: Vec<String> = rd.headers().unwrap().iter().map(String::from).collect();
    let col = |n: &str| h.iter().position(|c| c == n).unwrap();
    let agents = (0..)
        .take_while(|i| h.contains(&format!("x{i}_true")))
        .count();
    assert!(agents > 0, "true positions in ticks.csv");
    rd.records()
        .map(|r| {
            let r = r.unwrap();
            let f = |n: &str| r[col(n)].parse::<f64>().unwrap();
            (
                f("t_s"),
                (0..agents)
                    .map(|i| [f(&format!("x{i}_true")), f(&format!("y{i}_true"))])
                    .collect(),
            )
        })
        .collect()
}

fn shots() -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("replay-screenshots");
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn screenshot(chrome: &Path, page: &str, name: &str, size: &str) -> PathBuf {
    let png = shots().join(name);
    let _ = std::fs::remove_file(&png);
    browse(
        chrome,
        &[
            &format!("--screenshot={}", png.display()),
            &format!("--window-size={size}"),
        ],
        page,
    );
    let len = std::fs::metadata(&png)
        .unwrap_or_else(|_| panic!("no screenshot {}", png.display()))
        .len();
    assert!(len > 10_000, "{} is nearly empty ({len} B)", png.display());
    png
}

#[test]
fn a_replay_shows_the_run_at_the_time_in_its_url() {
    let dir = tempfile::tempdir().unwrap();
    let run = dir.path().join("run");
    let (code, _, stderr) = magbench(&[
        "track",
        "open-field",
        "--tracker",
        "obc",
        "--seed",
        "1",
        "--out",
        run.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    let page = run.join("replay.html");
    let size = std::fs::metadata(&page).unwrap().len();
    println!("replay.html: {size} B");
    assert!(size < 400_000, "a replay of {size} B");
    assert!(!run.join("run.gif").exists(), "a GIF only with --gif");
    let html = std::fs::read_to_string(&page).unwrap();
    assert!(
        !html.contains("src=\"http") && !html.contains("href=\"http"),
        "the page loads nothing from the network"
    );
    let ticks = ticks(&run);
    let end = ticks.last().unwrap().0;
    let Some(chrome) = chromium() else {
        return;
    };
    let mut seen = vec![];
    for (k, t) in [0.0, end / 3.0, 2.0 * end / 3.0].into_iter().enumerate() {
        let t = (t * 100.0).round() / 100.0;
        let dom = browse(&chrome, &["--dump-dom"], &url(&page, &format!("#t={t}")));
        let b = body(&dom);
        assert_eq!(num(b, "data-t"), t, "the page's time is the URL's: {b}");
        assert_eq!(attr(b, "data-playing"), "false");
        let mut team = vec![];
        for i in 0..2 {
            let a = tag(&dom, &format!("agent-{i}"));
            let shown_t = num(a, "data-t");
            assert!(
                shown_t <= t + 1e-9 && shown_t > t - 0.2,
                "the frame shown at {t} s is from {shown_t} s"
            );
            // the tick drawn: the one of ticks.csv at that time
            let (_, truth) = ticks
                .iter()
                .min_by(|a, b| (a.0 - shown_t).abs().total_cmp(&(b.0 - shown_t).abs()))
                .unwrap();
            let (x, y) = (num(a, "data-x"), num(a, "data-y"));
            assert!(
                (x - truth[i][0]).abs() <= 0.011 && (y - truth[i][1]).abs() <= 0.011,
                "agent {i} drawn at ({x}, {y}) at {t} s; ticks.csv: {:?}",
                truth[i]
            );
            assert_eq!(attr(a, "cx").parse::<f64>().unwrap(), x);
            team.push((x, y));
        }
        seen.push(team);
        let png = screenshot(
            &chrome,
            &url(&page, &format!("#t={t}&tree=1")),
            &format!("replay-{}.png", k + 1),
            "1280,820",
        );
        println!("screenshot {}", png.display());
    }
    assert!(
        seen[0] != seen[1] && seen[1] != seen[2],
        "the agents move: {seen:?}"
    );

    // the controls: the tree toggle and the speed come from the URL, play advances time
    let dom = browse(&chrome, &["--dump-dom"], &url(&page, "#t=1&tree=1&speed=2"));
    let b = body(&dom);
    assert_eq!(attr(b, "data-tree"), "true");
    assert_eq!(attr(b, "data-speed"), "2");
    let tree = tag(&dom, "layer-tree");
    assert_eq!(attr(tree, "visibility"), "visible");
    assert!(
        dom.contains("class=\"tree\""),
        "the planner's tree is drawn"
    );
    let dom = browse(&chrome, &["--dump-dom"], &url(&page, "#t=1&tree=0"));
    assert_eq!(attr(tag(&dom, "layer-tree"), "visibility"), "hidden");
    let dom = browse(
        &chrome,
        &["--dump-dom", "--virtual-time-budget=3000"],
        &url(&page, "#t=0&play=1&speed=4"),
    );
    let b = body(&dom);
    assert_eq!(attr(b, "data-playing"), "true", "{b}");
    assert!(num(b, "data-t") > 0.0, "playing moves the time on: {b}");
    // the end
    let dom = browse(&chrome, &["--dump-dom"], &url(&page, "#t=end"));
    assert_eq!(num(body(&dom), "data-t"), (end * 1000.0).round() / 1000.0);
}

#[test]
fn a_scenario_preview_draws_every_leg() {
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("cargo.svg");
    let (code, _, stderr) = magbench(&[
        "scenario",
        "show",
        "cargo-delivery",
        "--out",
        svg.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(
        text.contains("leg 1") && text.contains("leg 2"),
        "both legs"
    );
    assert!(text.contains("pair range"), "the proximity range");
    let (code, _, stderr) = magbench(&[
        "scenario",
        "show",
        "cargo-delivery",
        "--out",
        dir.path().join("x.jpg").to_str().unwrap(),
    ]);
    assert_eq!(code, 2);
    assert!(
        stderr.contains("--out") && stderr.contains(".svg or .png"),
        "{stderr}"
    );
    let Some(chrome) = chromium() else {
        return;
    };
    let png = screenshot(&chrome, &url(&svg, ""), "scenario-preview.png", "1200,560");
    println!("screenshot {}", png.display());
}

#[test]
fn a_bench_writes_a_replay_per_run_linked_from_the_report() {
    let dir = tempfile::tempdir().unwrap();
    let exp = dir.path().join("replays.toml");
    std::fs::write(
        &exp,
        r#"
scenarios = ["open-field"]
planners = ["goal-zoom-rrt"]
seeds = 2
[limits]
iterations = 3000
[tracking]
trackers = ["obc"]
presets = ["realistic"]
"#,
    )
    .unwrap();
    let out = dir.path().join("results");
    let (code, _, stderr) = magbench(&[
        "bench",
        exp.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
        "--threads",
        "1",
    ]);
    assert_eq!(code, 0, "{stderr}");
    let report = std::fs::read_to_string(out.join("report.html")).unwrap();
    let mut total = 0;
    for run in 0..4 {
        let f = format!("replays/run-{run}.html");
        let len = std::fs::metadata(out.join(&f))
            .unwrap_or_else(|_| panic!("{f} missing"))
            .len();
        println!("{f}: {len} B");
        total += len;
        assert!(
            report.contains(&format!("href=\"{f}\"")),
            "the report links {f}"
        );
    }
    println!("4 replays: {total} B");
    assert!(out.join("scenarios/open-field.svg").is_file());
    assert!(
        report.contains("class=\"preview\""),
        "the scenario's preview"
    );
    let (code, _, stderr) = magbench(&["results", "verify", out.to_str().unwrap()]);
    assert_eq!(code, 0, "{stderr}");
    let Some(chrome) = chromium() else {
        return;
    };
    let dom = browse(
        &chrome,
        &["--dump-dom"],
        &url(&out.join("replays/run-0.html"), "#t=0.5"),
    );
    assert_eq!(num(body(&dom), "data-t"), 0.5);
    assert!(dom.contains("id=\"agent-1\""));
    let png = screenshot(
        &chrome,
        &url(&out.join("report.html"), ""),
        "report.png",
        "1280,1400",
    );
    println!("screenshot {}", png.display());
}
