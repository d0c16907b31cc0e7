//! The book's measured figures come from `docs/measured/`, which `magbench docs measure`
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

use std::path::{Path, PathBuf};

use magbench::docs::{MEASURES, parse};
use regex::Regex;

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
            "docs/measured/{}.md is missing: run `magbench docs measure --only {}`",
            m.name,
            m.name
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
        "hand-typed measured figures (generate them with `magbench docs measure` and include \
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
