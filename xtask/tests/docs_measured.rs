//! The book's measured figures come from `docs/measured/`, which `cargo xtask measure`
//! regenerates: every file there parses and belongs to a measurement, every include in the book
//! names one, and no chapter types a measured figure by hand.
//!
//! The rule for hand-typed figures, outside fenced code, inline code and include lines:
//! - inside a section about measurements, one whose heading (or a parent's) names one of
//!   [`MEASURED_HEADINGS`] ("Measured", "Speed", "Overheads", …), a line fails if it holds
//!   - a number followed by a unit of time, rate or ratio (`12.6 ms`, `0.5 µs`, `34 s`,
//!     `3 min`, `2 300 it/s`, `205×`), or
//!   - a table row (`| … |`) with a decimal number (`| obc | 0.0258 / 0.0274 |`);
//! - anywhere, a line fails if it states the conditions of a measurement by hand (a load
//!   average with its figure, "development VM", "2-core machine"): those are a generated
//!   file's header.
//!
//! Such figures belong in a measurement's table, quoted by `{{#include measured/NAME.md}}`.
//! Sections not yet generated are listed once, in [`EXCEPTIONS`].
//!
//! A sentence that compares figures of a measured table carries a claim marker, an HTML comment
//! (invisible in the book) that the test reads back from the table; see [`Claim`]:
//! `<!-- claim: measured/NAME.md | COLUMN | STAT | CLAIM -->`, with `STAT` one of `median`,
//! `p90` (the two halves of a `median / p90` cell; `median` also reads the figure of a
//! `median [lo, hi]` cell) or `value`, and `CLAIM` one of
//! - `ROWS < ROWS` (or `>`): the two rows' figures compare so; the paragraph quotes both;
//! - `ROWS / ROWS per KEY spans LO..HI`: the ratios of the first rows' figures to the second
//!   rows' with the same `KEY` column, lowest and highest rounded as `LO` and `HI` are written
//!   (`1.8`, `46k`), are `LO` and `HI`, both quoted in the paragraph;
//! - `ROWS spans LO..HI`: the same for the rows' figures themselves.
//!
//! `ROWS` selects rows by `COLUMN=VALUE`, `COLUMN!=VALUE`, `COLUMN^=PREFIX`, `COLUMN!^=PREFIX`
//! and `nonzero` (the figure), joined by `,` (a comma inside braces, as in a planner's label,
//! belongs to the value). The paragraph is the paragraph or list item that
//! holds the marker: its lines between blank lines, list items and headings.

use std::path::{Path, PathBuf};

use regex::Regex;
use xtask::docs::freshness::file_staleness;
use xtask::docs::{MEASURES, parse};

/// Chapters or sections whose hand-typed figures are not generated yet: (file in `docs/`,
/// heading of the section, or "*" for the whole file; what is missing).
const EXCEPTIONS: &[(&str, &str, &str)] = &[];

fn docs() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs")
}

/// The `.md` files directly in `dir`, sorted.
fn markdown_in(dir: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    v.sort();
    v
}

fn name(p: &Path) -> String {
    p.file_name().unwrap().to_string_lossy().to_string()
}

/// The path of each `{{#include PATH}}` (or `{{#include PATH:anchor}}`) in `text`; mdBook
/// leaves an include escaped as `\{{#include …}}` as text.
fn includes(text: &str) -> Vec<String> {
    let re = Regex::new(r"(?:^|[^\\])\{\{#include\s+([^}:\s]+)[^}]*\}\}").unwrap();
    re.captures_iter(text).map(|c| c[1].to_string()).collect()
}

/// Words that make a heading's section one about measurements (compared in lower case).
const MEASURED_HEADINGS: &[&str] = &[
    "measure",
    "speed",
    "overhead",
    "accuracy",
    "latency",
    "timing",
    "profile",
    "performance",
    "build time",
];

/// `(level, title)` if `line` is an ATX heading.
fn heading(line: &str) -> Option<(usize, &str)> {
    let level = line.chars().take_while(|&c| c == '#').count();
    (1..=6)
        .contains(&level)
        .then(|| line[level..].strip_prefix(' '))
        .flatten()
        .map(|t| (level, t.trim()))
}

/// The lines of `text` that break the rule (1-based line number, line), skipping sections
/// whose nearest heading is in `exempt`.
fn hand_typed(text: &str, exempt: &[&str]) -> Vec<(usize, String)> {
    let unit =
        Regex::new(r"\d(?:[\d.,\u{202f} ]*\d)?\s?(?:ms|µs|us|ns|s|min|it/s|×)(?:[^\w]|$)").unwrap();
    let decimal = Regex::new(r"\d\.\d").unwrap();
    let code = Regex::new(r"`[^`]*`").unwrap();
    let conditions =
        Regex::new(r"(?i)load average[^.;]{0,12}\d|development VM|2-core (?:VM|machine)").unwrap();
    let mut stack: Vec<(usize, String)> = vec![];
    let mut fenced = false;
    let mut found = vec![];
    for (i, line) in text.lines().enumerate() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            continue;
        }
        if fenced {
            continue;
        }
        if let Some((level, title)) = heading(line) {
            stack.retain(|(l, _)| *l < level);
            stack.push((level, title.to_string()));
            continue;
        }
        let measured = stack.iter().any(|(_, t)| {
            let t = t.to_lowercase();
            MEASURED_HEADINGS.iter().any(|w| t.contains(w))
        });
        let nearest = stack.last().map(|(_, t)| t.as_str()).unwrap_or("");
        if exempt.contains(&nearest) || !includes(line).is_empty() {
            continue;
        }
        let prose = code.replace_all(line, "");
        let row = prose.trim_start().starts_with('|');
        let figure = unit.is_match(&prose) || (row && decimal.is_match(&prose));
        if (measured && figure) || conditions.is_match(&prose) {
            found.push((i + 1, line.to_string()));
        }
    }
    found
}

#[test]
fn every_measured_file_parses_and_belongs_to_a_measurement() {
    let files = markdown_in(&docs().join("measured"));
    for f in &files {
        let text = std::fs::read_to_string(f).unwrap();
        let m = parse(&text).unwrap_or_else(|e| panic!("{}: {e}", f.display()));
        let stem = name(f).trim_end_matches(".md").to_string();
        assert!(
            MEASURES.iter().any(|x| x.name == stem),
            "{}: no measurement {stem} regenerates it",
            f.display()
        );
        let command = m.field("command").unwrap();
        assert!(
            command.contains(&format!("--only {stem}")) && !command.contains("--quick"),
            "{}: committed files come from a full run of their own measurement: {command}",
            f.display()
        );
    }
    for m in MEASURES {
        assert!(
            files.iter().any(|f| name(f) == format!("{}.md", m.name)),
            "docs/measured/{}.md is missing: run `cargo xtask measure --only {}`",
            m.name,
            m.name
        );
    }
}

/// Measured files whose source changed after they were measured (or that name a dirty tree),
/// waiting to be regenerated on an idle machine at a clean commit; `cargo xtask stale` says
/// what changed for each. A stale file missing from this list fails, and so does a listed file
/// that is fresh: the list names exactly the files whose figures may not be today's.
const AWAITING_REGENERATION: &[&str] = &["calibration-bench-segments"];

/// Whether the source tree is a git repository with its whole history (not shallow).
fn full_history(root: &Path) -> Result<(), String> {
    let out = std::process::Command::new("git")
        .arg("-C")
        .arg(root)
        .args(["rev-parse", "--is-shallow-repository"])
        .output()
        .map_err(|e| format!("git: {e}"))?;
    match String::from_utf8_lossy(&out.stdout).trim() {
        "false" => Ok(()),
        "true" => Err("a shallow clone (`git fetch --unshallow` gives the history)".into()),
        _ => Err(format!(
            "not a git repository: {}",
            String::from_utf8_lossy(&out.stderr).trim()
        )),
    }
}

#[test]
fn measured_files_are_fresh_or_awaiting_regeneration() {
    let root = docs().join("..");
    if let Err(why) = full_history(&root) {
        eprintln!("SKIPPED measured_files_are_fresh_or_awaiting_regeneration: {why}");
        return;
    }
    let mut unlisted = vec![];
    let mut fresh_but_listed = vec![];
    for m in MEASURES {
        let path = docs().join(format!("measured/{}.md", m.name));
        let text = std::fs::read_to_string(&path).unwrap();
        let stale = file_staleness(&root, m, &text).unwrap_or_else(|e| panic!("{}: {e}", m.name));
        let listed = AWAITING_REGENERATION.contains(&m.name);
        match (stale, listed) {
            (Some(why), false) => unlisted.push(format!("{}: {why}", m.name)),
            (None, true) => fresh_but_listed.push(m.name),
            _ => {}
        }
    }
    assert!(
        unlisted.is_empty(),
        "stale measured files (regenerate with `cargo xtask measure --only NAME`):\n{}",
        unlisted.join("\n")
    );
    assert!(
        fresh_but_listed.is_empty(),
        "fresh, so no longer awaiting regeneration: {fresh_but_listed:?}"
    );
    for name in AWAITING_REGENERATION {
        assert!(
            MEASURES.iter().any(|m| m.name == *name),
            "{name} is no measurement"
        );
    }
}

#[test]
fn every_include_in_the_book_names_a_measured_file() {
    let mut seen = 0;
    for page in markdown_in(&docs()) {
        let text = std::fs::read_to_string(&page).unwrap();
        for inc in includes(&text) {
            assert!(
                inc.starts_with("measured/") && docs().join(&inc).is_file(),
                "{}: {{{{#include {inc}}}}} is not a file in docs/measured/",
                page.display()
            );
            seen += 1;
        }
    }
    assert!(seen > 0, "the book includes no measured file");
}

#[test]
fn measured_sections_quote_only_generated_files() {
    let mut bad = vec![];
    for page in markdown_in(&docs()) {
        let file = name(&page);
        let exempt: Vec<&str> = EXCEPTIONS
            .iter()
            .filter(|(f, _, _)| *f == file)
            .map(|(_, h, _)| *h)
            .collect();
        if exempt.contains(&"*") {
            continue;
        }
        let text = std::fs::read_to_string(&page).unwrap();
        for (line, l) in hand_typed(&text, &exempt) {
            bad.push(format!("docs/{file}:{line}: {l}"));
        }
    }
    assert!(
        bad.is_empty(),
        "hand-typed measured figures (generate them with `cargo xtask measure` and include \
         docs/measured/NAME.md):\n{}",
        bad.join("\n")
    );
}

#[test]
fn every_exception_names_a_chapter_and_a_heading_in_it() {
    for (file, head, why) in EXCEPTIONS {
        assert!(!why.is_empty());
        let text = std::fs::read_to_string(docs().join(file))
            .unwrap_or_else(|e| panic!("docs/{file}: {e}"));
        assert!(
            *head == "*"
                || text
                    .lines()
                    .any(|l| heading(l).is_some_and(|(_, t)| t == *head)),
            "docs/{file} has no heading {head:?}"
        );
    }
}

#[test]
fn the_rule_catches_a_planted_hand_typed_figure() {
    let clean = "# Planners\n\n## Measured\n\nThe success of every planner:\n\n\
                 {{#include measured/planners-success.md}}\n\n\
                 Run `magbench bench --threads 2` for 50 seeds.\n\n## Other\n\nTook 12 ms.\n";
    assert_eq!(hand_typed(clean, &[]), vec![]);
    assert_eq!(includes(clean), vec!["measured/planners-success.md"]);
    assert_eq!(
        includes("see `\\{{#include measured/NAME.md}}`"),
        Vec::<String>::new()
    );
    let planted = [
        "The median is 12.6 ms.",
        "600 runs in 34 s on 2 cores.",
        "It is 205× faster.",
        "About 2 300 it/s.",
        "0.5 µs per call",
        "| obc | realistic | 0.0258 / 0.0274 |",
    ];
    for p in planted {
        let text = clean.replace("The success of every planner:", p);
        assert_eq!(hand_typed(&text, &[]), vec![(5, p.to_string())], "{p}");
        assert_eq!(hand_typed(&text, &["Measured"]), vec![], "{p} exempt");
    }
    let sub = clean.replace(
        "The success",
        "### Speed\n\nOne tick is 8.8 µs. The success",
    );
    assert_eq!(hand_typed(&sub, &[]).len(), 1, "a subsection of Measured");
    assert_eq!(hand_typed(&sub, &["Speed"]), vec![]);
    let overheads = clean.replace("## Measured", "## Overheads");
    assert_eq!(
        hand_typed(
            &overheads.replace("The success", "It takes 0.5 µs. The"),
            &[]
        )
        .len(),
        1,
        "a heading of MEASURED_HEADINGS"
    );
    let other = clean.replace(
        "Took 12 ms.",
        "On the 2-core development VM (load average 8).",
    );
    assert_eq!(
        hand_typed(&other, &[]).len(),
        1,
        "conditions outside a measured section"
    );
}

/// A table of a measured file: its header and rows of cells.
struct Table {
    header: Vec<String>,
    rows: Vec<Vec<String>>,
}

impl Table {
    /// The first `| … |` table in `text`.
    fn parse(text: &str) -> Table {
        let cells = |l: &str| -> Vec<String> {
            l.trim()
                .trim_matches('|')
                .split('|')
                .map(|c| c.trim().to_string())
                .collect()
        };
        let mut lines = text.lines().filter(|l| l.trim_start().starts_with('|'));
        let header = cells(lines.next().expect("a table"));
        let rows = lines.skip(1).map(cells).collect();
        Table { header, rows }
    }

    fn column(&self, name: &str) -> Result<usize, String> {
        self.header
            .iter()
            .position(|h| h == name)
            .ok_or_else(|| format!("no column {name:?} in {:?}", self.header))
    }
}

/// One half of a `median / p90` cell, or the whole cell, as a number and as written; `None`
/// for an empty `–`.
fn figure(cell: &str, stat: &str) -> Result<Option<(f64, String)>, String> {
    let part = match stat {
        "median" => cell
            .split(" / ")
            .next()
            .map(|m| m.split(" [").next().unwrap_or(m)),
        "p90" => cell.split(" / ").nth(1),
        "value" => Some(cell),
        other => return Err(format!("unknown statistic {other:?}")),
    }
    .ok_or_else(|| format!("cell {cell:?} has no {stat}"))?
    .trim();
    if part == "–" {
        return Ok(None);
    }
    part.parse()
        .map(|x| Some((x, part.to_string())))
        .map_err(|_| format!("cell {cell:?}: {part:?} is not a number"))
}

/// A bound as the prose writes it (`1.8`, `46k`): its value, and the step it is rounded to.
fn written(s: &str) -> Result<(f64, f64), String> {
    let (digits, scale) = match s.strip_suffix('k') {
        Some(d) => (d, 1000.0),
        None => (s, 1.0),
    };
    let v: f64 = digits
        .parse()
        .map_err(|_| format!("{s:?} is not a number"))?;
    let decimals = digits.split('.').nth(1).map_or(0, str::len) as i32;
    Ok((v * scale, scale * 10f64.powi(-decimals)))
}

/// Whether `v` rounded to a multiple of `step` is `target` (within rounding noise).
fn rounds_to(v: f64, step: f64, target: f64) -> bool {
    ((v / step).round() * step - target).abs() < step * 1e-6
}

/// A claim marker read from a chapter (see the module documentation).
#[derive(Debug)]
struct Claim {
    /// `docs/FILE:LINE` of the marker.
    at: String,
    /// The measured file, relative to `docs/`.
    file: String,
    /// The column compared.
    column: String,
    /// `median`, `p90` or `value`.
    stat: String,
    /// The relation the sentence states.
    claim: String,
    /// The paragraph or list item holding the marker, markers removed.
    paragraph: String,
}

/// The claim markers of a chapter's `text`, named `docs/{file}`.
fn claims(file: &str, text: &str) -> Vec<Claim> {
    let re = Regex::new(r"<!-- claim: ([^|]+)\|([^|]+)\|([^|]+)\|(.+?) -->").unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let ends = |l: &str| {
        let l = l.trim_start();
        l.is_empty() || l.starts_with("- ") || l.starts_with('#')
    };
    let mut found = vec![];
    for (i, line) in lines.iter().enumerate() {
        for c in re.captures_iter(line) {
            let mut start = i;
            while start > 0 && !lines[start].trim_start().starts_with("- ") && {
                let prev = lines[start - 1].trim_start();
                !(prev.is_empty() || prev.starts_with('#'))
            } {
                start -= 1;
            }
            let end = (i + 1..lines.len())
                .find(|&j| ends(lines[j]))
                .unwrap_or(lines.len());
            let paragraph = lines[start..end].join("\n");
            found.push(Claim {
                at: format!("docs/{file}:{}", i + 1),
                file: c[1].trim().to_string(),
                column: c[2].trim().to_string(),
                stat: c[3].trim().to_string(),
                claim: c[4].trim().to_string(),
                paragraph: re.replace_all(&paragraph, "").to_string(),
            });
        }
    }
    found
}

/// The conditions of a row selection: `sel` split at the commas outside braces (a planner's
/// label, `goal-zoom-rrt{aim=true,guide=true}`, is one value).
fn conditions(sel: &str) -> Vec<&str> {
    let (mut depth, mut start, mut out) = (0i32, 0, vec![]);
    for (i, c) in sel.char_indices() {
        match c {
            '{' => depth += 1,
            '}' => depth -= 1,
            ',' if depth == 0 => {
                out.push(sel[start..i].trim());
                start = i + 1;
            }
            _ => {}
        }
    }
    out.push(sel[start..].trim());
    out
}

impl Claim {
    /// The rows `sel` picks, with their figures (rows whose figure is `–` left out).
    fn select(&self, t: &Table, sel: &str) -> Result<Vec<(usize, f64, String)>, String> {
        let col = t.column(&self.column)?;
        let mut conds = vec![];
        let mut nonzero = false;
        for c in conditions(sel) {
            if c == "nonzero" {
                nonzero = true;
                continue;
            }
            let (key, op, value) = ["!^=", "^=", "!=", "="]
                .iter()
                .find_map(|op| c.split_once(op).map(|(k, v)| (k, *op, v)))
                .ok_or_else(|| format!("condition {c:?} is not COLUMN=VALUE"))?;
            conds.push((t.column(key.trim())?, op, value.trim().to_string()));
        }
        let mut rows = vec![];
        for (i, r) in t.rows.iter().enumerate() {
            let keep = conds.iter().all(|(k, op, v)| match *op {
                "=" => r[*k] == *v,
                "!=" => r[*k] != *v,
                "^=" => r[*k].starts_with(v.as_str()),
                _ => !r[*k].starts_with(v.as_str()),
            });
            if !keep {
                continue;
            }
            if let Some((x, text)) = figure(&r[col], &self.stat)?
                && !(nonzero && x == 0.0)
            {
                rows.push((i, x, text));
            }
        }
        if rows.is_empty() {
            return Err(format!("no row with a figure matches {sel:?}"));
        }
        Ok(rows)
    }

    /// The figure of the one row `sel` picks, as a number and as written.
    fn one(&self, t: &Table, sel: &str) -> Result<(f64, String), String> {
        match self.select(t, sel)?.as_slice() {
            [(_, x, text)] => Ok((*x, text.clone())),
            many => Err(format!("{sel:?} matches {} rows, not one", many.len())),
        }
    }

    /// `Ok` when the claim holds of `t` and the paragraph quotes its figures.
    fn check(&self, t: &Table) -> Result<(), String> {
        let quoted = |s: &str| -> Result<(), String> {
            let alone = format!(r"(?:^|[^\d.]){}(?:[^\d]|$)", regex::escape(s));
            if Regex::new(&alone).unwrap().is_match(&self.paragraph) {
                Ok(())
            } else {
                Err(format!("the sentence does not quote {s}"))
            }
        };
        if let Some((rows, range)) = self.claim.split_once(" spans ") {
            let (lo, hi) = range
                .split_once("..")
                .ok_or_else(|| format!("{range:?} is not LO..HI"))?;
            let values: Vec<f64> = match rows.split_once(" per ") {
                Some((ratio, key)) => {
                    let (a, b) = ratio
                        .split_once(" / ")
                        .ok_or_else(|| format!("{ratio:?} is not ROWS / ROWS"))?;
                    let k = t.column(key.trim())?;
                    let mut v = vec![];
                    for (i, x, _) in self.select(t, a)? {
                        let same = format!("{b},{}={}", key.trim(), t.rows[i][k]);
                        v.push(x / self.one(t, &same)?.0);
                    }
                    v
                }
                None => self
                    .select(t, rows)?
                    .into_iter()
                    .map(|(_, x, _)| x)
                    .collect(),
            };
            let min = values.iter().copied().fold(f64::INFINITY, f64::min);
            let max = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            let ((lo_v, lo_step), (hi_v, hi_step)) = (written(lo)?, written(hi)?);
            if !rounds_to(min, lo_step, lo_v) || !rounds_to(max, hi_step, hi_v) {
                return Err(format!(
                    "the table's figures span {min:.4}..{max:.4}, not {lo}..{hi}"
                ));
            }
            quoted(lo)?;
            return quoted(hi);
        }
        for (op, holds) in [(" < ", f64::lt as fn(&f64, &f64) -> bool), (" > ", f64::gt)] {
            if let Some((a, b)) = self.claim.split_once(op) {
                let ((x, xs), (y, ys)) = (self.one(t, a)?, self.one(t, b)?);
                if !holds(&x, &y) {
                    return Err(format!("the table has {xs}{op}{ys} false"));
                }
                quoted(&xs)?;
                return quoted(&ys);
            }
        }
        Err(format!("{:?} is no claim", self.claim))
    }
}

/// Every claim marker in the book holds of the table it names.
#[test]
fn the_book_s_comparisons_agree_with_their_tables() {
    let mut n = 0;
    let mut bad = vec![];
    for page in markdown_in(&docs()) {
        let text = std::fs::read_to_string(&page).unwrap();
        for c in claims(&name(&page), &text) {
            n += 1;
            let table = std::fs::read_to_string(docs().join(&c.file))
                .map(|t| Table::parse(&t))
                .map_err(|e| format!("{}: {e}", c.file));
            if let Err(e) = table.and_then(|t| c.check(&t)) {
                bad.push(format!(
                    "{}: {} | {} | {} | {}: {e}",
                    c.at, c.file, c.column, c.stat, c.claim
                ));
            }
        }
    }
    assert!(n > 0, "the book has no claim marker");
    assert!(
        bad.is_empty(),
        "claims that disagree with their tables:\n{}",
        bad.join("\n")
    );
}

/// The claim checker fails on a false comparison, a wrong span, an unquoted figure and a
/// selector that matches more than one row; a paragraph is its own list item only.
#[test]
fn the_claim_checker_catches_a_wrong_claim() {
    let table = Table::parse(
        "| scenario | tracker | path |\n| --- | --- | --- |\n\
         | a | obc | 0.0502 / 0.0548 |\n| a | lookahead | 0.0393 / 0.0572 |\n\
         | b | obc | 0.0200 / 0.0300 |\n| b | lookahead | 0.0500 / 0.0600 |\n",
    );
    let check = |claim: &str, prose: &str| {
        let text = format!(
            "first\n\n- before\n- {prose}\n  <!-- claim: t.md | path | {claim} -->\n- next\n\nlast"
        );
        let c = claims("x.md", &text);
        assert_eq!(c.len(), 1);
        for other in ["first", "before", "next", "last"] {
            assert!(
                !c[0].paragraph.contains(other),
                "{other}: {}",
                c[0].paragraph
            );
        }
        c[0].check(&table)
    };
    let ok = "median | scenario=a,tracker=lookahead < scenario=a,tracker=obc";
    assert_eq!(check(ok, "lookahead 0.0393 against 0.0502"), Ok(()));
    assert!(check(ok, "lookahead is lower").is_err(), "unquoted");
    let wrong = "median | scenario=a,tracker=obc < scenario=a,tracker=lookahead";
    assert!(check(wrong, "0.0393 against 0.0502").is_err(), "false");
    let p90 = "p90 | scenario=a,tracker=obc < scenario=a,tracker=lookahead";
    assert_eq!(check(p90, "0.0548 against 0.0572"), Ok(()));
    assert!(
        check("median | tracker=obc < scenario=a,tracker=lookahead", "").is_err(),
        "two rows"
    );
    // obc / lookahead: 1.277 on a, 0.4 on b
    let ratio = "median | tracker=obc / tracker=lookahead per scenario spans";
    assert_eq!(check(&format!("{ratio} 0.4..1.3"), "0.4 to 1.3"), Ok(()));
    assert!(check(&format!("{ratio} 0.4..1.2"), "0.4 to 1.2").is_err());
    assert!(check(&format!("{ratio} 1.0..1.3"), "1.0 to 1.3").is_err());
    let span = "median | nonzero spans 0.02..0.05";
    assert_eq!(check(span, "from 0.02 to 0.05"), Ok(()));
    assert!(
        check(span, "from 0.020 to 0.05").is_err(),
        "0.02 only inside 0.020"
    );
    assert_eq!(written("46k"), Ok((46000.0, 1000.0)));
    assert!(rounds_to(45676.0, 1000.0, 46000.0) && !rounds_to(45676.0, 1000.0, 45000.0));
    assert_eq!(
        conditions("planner=rrt{a=1,b=2},tracker=obc"),
        ["planner=rrt{a=1,b=2}", "tracker=obc"]
    );
}
