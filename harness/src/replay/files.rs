//! Where a results folder keeps replays and scenario previews: `replays/run-<index>.html`
//! per run that has one, the player they share (`replays/player.js`, `replays/player.css`)
//! and `scenarios/<scenario>.svg` per scenario.

use std::path::Path;

use magbench_env::Scenario;

use super::data::ReplayData;
use crate::Error;
use crate::results::summary::GroupSummary;
use crate::run::RunRecord;

/// The folder of the replays in a results folder.
pub const REPLAYS: &str = "replays";
/// The folder of the scenario previews in a results folder.
pub const SCENARIOS: &str = "scenarios";

/// The replay of run `index`, relative to the results folder.
pub fn replay_file(index: usize) -> String {
    format!("{REPLAYS}/run-{index}.html")
}

/// The files every replay of a results folder loads, relative to the folder.
pub fn player_files() -> [String; 2] {
    [super::page::PLAYER_FILE, super::page::STYLE_FILE].map(|f| format!("{REPLAYS}/{f}"))
}

/// `label` with every character outside `A-Za-z0-9._-` replaced by `_`.
pub fn slug(label: &str) -> String {
    label
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || "._-".contains(c) {
                c
            } else {
                '_'
            }
        })
        .collect()
}

/// The preview of scenario `label` (as in `runs.csv`), relative to the results folder.
pub fn preview_file(label: &str) -> String {
    format!("{SCENARIOS}/{}.svg", slug(label))
}

/// The report's cell of configuration `g`: a link to the replay of each of its runs that has
/// one in results folder `dir`, labelled by seed; "–" when none has.
pub fn links_cell(dir: &Path, runs: &[RunRecord], g: &GroupSummary) -> String {
    let mut mine: Vec<&RunRecord> = runs
        .iter()
        .filter(|r| {
            r.scenario == g.scenario
                && r.planner == g.planner
                && r.tracker == g.tracker
                && r.preset == g.preset
        })
        .collect();
    mine.sort_by_key(|r| r.run);
    let links = mine
        .iter()
        .filter(|r| dir.join(replay_file(r.run)).is_file())
        .map(|r| {
            format!(
                "<a href=\"{}\" title=\"run {}, seed {}\">{}</a>",
                replay_file(r.run),
                r.run,
                r.seed,
                r.seed
            )
        })
        .collect::<Vec<_>>();
    if links.is_empty() {
        "–".into()
    } else {
        links.join(" ")
    }
}

/// The runs of `runs` that have a replay in results folder `dir`.
pub fn with_replay(dir: &Path, runs: &[RunRecord]) -> usize {
    runs.iter()
        .filter(|r| dir.join(replay_file(r.run)).is_file())
        .count()
}

/// Writes the player the replays of results folder `dir` share.
pub fn write_player(dir: &Path) -> Result<(), Error> {
    super::page::write_player(&dir.join(REPLAYS))
}

/// Writes run `index`'s replay into results folder `dir`; it loads the folder's player
/// ([`write_player`]).
pub fn write_replay(dir: &Path, index: usize, data: &ReplayData) -> Result<(), Error> {
    super::page::write_with(
        &dir.join(replay_file(index)),
        data,
        super::page::Player::Shared,
    )
}

/// Removes run `index`'s replay from results folder `dir`, if it has one.
pub fn remove_replay(dir: &Path, index: usize) -> Result<(), Error> {
    let path = dir.join(replay_file(index));
    match std::fs::remove_file(&path) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
            Err(Error::Failed(format!("{}: {e}", path.display())))
        }
        _ => Ok(()),
    }
}

/// Copies run `index`'s replay (if it has one) with the player it loads from results folder
/// `from` into `to` (merging shards); a file `to` has is kept.
pub fn copy_run(from: &Path, to: &Path, index: usize) -> Result<(), Error> {
    if !from.join(replay_file(index)).is_file() {
        return Ok(());
    }
    copy_new(
        from,
        to,
        std::iter::once(replay_file(index)).chain(player_files()),
    )
}

/// Copies the scenario previews of results folder `from` into `to` (merging shards); a file
/// `to` has is kept.
pub fn copy_previews(from: &Path, to: &Path) -> Result<(), Error> {
    let Ok(dir) = std::fs::read_dir(from.join(SCENARIOS)) else {
        return Ok(());
    };
    copy_new(
        from,
        to,
        dir.flatten()
            .map(|e| format!("{SCENARIOS}/{}", e.file_name().to_string_lossy())),
    )
}

/// Copies each of `files` (paths in a results folder) that `from` has and `to` lacks.
fn copy_new(from: &Path, to: &Path, files: impl Iterator<Item = String>) -> Result<(), Error> {
    for f in files {
        let (src, dst) = (from.join(&f), to.join(&f));
        if !src.is_file() || dst.exists() {
            continue;
        }
        let fail = |e: std::io::Error| Error::Failed(format!("{}: {e}", dst.display()));
        std::fs::create_dir_all(dst.parent().expect("a folder")).map_err(fail)?;
        std::fs::copy(&src, &dst).map_err(fail)?;
    }
    Ok(())
}

/// Writes the preview of each `(label, scenario)` into results folder `dir` (once per label).
pub fn write_previews<'a>(
    dir: &Path,
    scenarios: impl Iterator<Item = (&'a str, &'a Scenario)>,
) -> Result<(), Error> {
    let mut done: Vec<&str> = vec![];
    for (label, s) in scenarios {
        if !done.contains(&label) {
            super::preview::write(s, &dir.join(preview_file(label)), "--out")?;
            done.push(label);
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_file_safe() {
        assert_eq!(slug("scenarios/my maze.toml"), "scenarios_my_maze.toml");
        assert_eq!(preview_file("open-field"), "scenarios/open-field.svg");
        assert_eq!(replay_file(12), "replays/run-12.html");
        assert_eq!(player_files(), ["replays/player.js", "replays/player.css"]);
    }
}
