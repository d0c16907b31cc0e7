//! Frozen problem suites: `suites/NAME/` holds a manifest `suite.toml` (name, version, the
//! generator version, the recipe as `[[generated]]` tables, the default benchmark and the
//! suite's hash), the generated scenario files in `scenarios/` and their hashes in
//! `SHA256SUMS` (the format `sha256sum -c` checks). The suite's hash is the SHA-256 of
//! `SHA256SUMS`. docs/suites.md, "Frozen suites".

use std::path::{Path, PathBuf};

use magbench_env::InputError;
use magbench_env::scenario::generate::GENERATOR_VERSION;
use serde::Deserialize;
use sha2::{Digest, Sha256};

use crate::experiment::generated::expand;
use crate::experiment::hex;

/// The manifest file of a suite folder.
pub const MANIFEST: &str = "suite.toml";
/// The hash list of a suite folder.
pub const SUMS: &str = "SHA256SUMS";

/// The benchmark `bench --suite` runs.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SuiteBench {
    /// Planner seeds per problem.
    pub seeds: u64,
    /// Planners (every build has them).
    pub planners: Vec<String>,
    /// Planners added when the build has them (`ompl:*` with the `ompl` feature).
    #[serde(default)]
    pub optional_planners: Vec<String>,
    /// The experiment's `[limits]` table.
    pub limits: toml::Table,
}

/// A suite's manifest.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Suite {
    /// Name, e.g. `pair-100`.
    pub name: String,
    /// The suite's version: cite "pair-100 v1".
    pub version: u32,
    /// The generator version that drew the files.
    pub generator_version: u32,
    /// What the suite holds.
    pub description: String,
    /// SHA-256 of `SHA256SUMS` (empty before the first freeze).
    #[serde(default)]
    pub sha256: String,
    /// The benchmark of `bench --suite`.
    pub bench: SuiteBench,
    /// The recipe: `[[generated]]` tables as in experiment files.
    pub generated: Vec<toml::Value>,
    /// The folder it was read from.
    #[serde(skip)]
    pub dir: PathBuf,
    /// The manifest's text.
    #[serde(skip)]
    pub text: String,
}

/// The suite folder of `name_or_dir`: a folder holding `suite.toml`, else `suites/NAME` in
/// the working directory, else in the source tree this binary was built from.
pub fn locate(name_or_dir: &str) -> PathBuf {
    let direct = PathBuf::from(name_or_dir);
    if direct.join(MANIFEST).exists() {
        return direct;
    }
    let local = Path::new("suites").join(name_or_dir);
    if local.join(MANIFEST).exists() {
        return local;
    }
    let built = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../suites")
        .join(name_or_dir);
    if built.join(MANIFEST).exists() {
        built
    } else {
        local
    }
}

/// The generated files of a recipe: `(file name, text)` in recipe order.
pub type Files = Vec<(String, String)>;

impl Suite {
    /// Reads `dir/suite.toml`.
    pub fn load(dir: &Path) -> Result<Suite, InputError> {
        let path = dir.join(MANIFEST);
        let file = path.display().to_string();
        let text = magbench_env::input::read_text(&path, &file)?;
        let mut s: Suite = toml::from_str(&text).map_err(|e: toml::de::Error| {
            InputError::new(&file, "suite", e.message().to_string())
        })?;
        s.dir = dir.to_path_buf();
        s.text = text;
        Ok(s)
    }

    /// The manifest's path as errors name it.
    pub fn file(&self) -> String {
        self.dir.join(MANIFEST).display().to_string()
    }

    /// Draws the recipe's files with this build's generator.
    pub fn regenerate(&self) -> Result<Files, InputError> {
        Ok(expand(&self.generated, &self.file())?
            .into_iter()
            .map(|(_, g)| (g.file_name, g.text))
            .collect())
    }

    /// The `SHA256SUMS` text of `files`, in file-name order.
    pub fn sums(files: &Files) -> String {
        let mut lines: Vec<String> = files
            .iter()
            .map(|(n, t)| format!("{}  scenarios/{n}\n", hex(&Sha256::digest(t.as_bytes()))))
            .collect();
        lines.sort_by(|a, b| a[66..].cmp(&b[66..]));
        lines.concat()
    }

    /// Writes the recipe's files, `SHA256SUMS` and the manifest's `sha256`; returns the hash.
    pub fn freeze(&mut self) -> Result<String, crate::Error> {
        let files = self.regenerate()?;
        let folder = self.dir.join("scenarios");
        if folder.exists() {
            std::fs::remove_dir_all(&folder)?;
        }
        std::fs::create_dir_all(&folder)?;
        for (n, t) in &files {
            std::fs::write(folder.join(n), t)?;
        }
        let sums = Suite::sums(&files);
        std::fs::write(self.dir.join(SUMS), &sums)?;
        let hash = hex(&Sha256::digest(sums.as_bytes()));
        let text: String = self
            .text
            .lines()
            .map(|l| {
                if l.starts_with("sha256 =") {
                    format!("sha256 = \"{hash}\"\n")
                } else if l.starts_with("generator_version =") {
                    format!("generator_version = {GENERATOR_VERSION}\n")
                } else {
                    format!("{l}\n")
                }
            })
            .collect();
        std::fs::write(self.dir.join(MANIFEST), &text)?;
        self.text = text;
        self.sha256 = hash.clone();
        Ok(hash)
    }

    /// Checks the stored files against `SHA256SUMS`, `SHA256SUMS` against the manifest's hash,
    /// and with `redraw` (when this build's generator version is the suite's) the stored files
    /// against a fresh draw of the recipe; returns the problems found.
    pub fn check(&self, redraw: bool) -> Result<Vec<String>, InputError> {
        let mut problems = vec![];
        let sums_path = self.dir.join(SUMS);
        let sums = std::fs::read_to_string(&sums_path).unwrap_or_default();
        let hash = hex(&Sha256::digest(sums.as_bytes()));
        if hash != self.sha256 {
            problems.push(format!(
                "{SUMS} hashes to {hash}, the manifest records {}",
                self.sha256
            ));
        }
        let stored = self.stored_files();
        if Suite::sums(&stored) != sums {
            problems.push(format!("the files in scenarios/ do not match {SUMS}"));
        }
        if !redraw {
            return Ok(problems);
        }
        if self.generator_version == GENERATOR_VERSION {
            let fresh = self.regenerate()?;
            let mut a = fresh.clone();
            a.sort();
            if a != stored {
                let differ = a
                    .iter()
                    .filter(|f| !stored.contains(f))
                    .map(|f| f.0.as_str())
                    .take(5)
                    .collect::<Vec<_>>();
                problems.push(format!(
                    "the recipe draws {} files, {} stored; differing: {}",
                    a.len(),
                    stored.len(),
                    differ.join(", ")
                ));
            }
        } else {
            problems.push(format!(
                "drawn by generator version {}, this build has {GENERATOR_VERSION}: the stored files are the suite, the recipe no longer redraws them",
                self.generator_version
            ));
        }
        Ok(problems)
    }

    /// The files in `scenarios/`, sorted by name.
    pub fn stored_files(&self) -> Files {
        files_in(&self.dir)
    }

    /// The experiment text `bench --suite` runs: the stored files (relative to `scenarios/`),
    /// the suite's planners (with those of `optional` this build has), seeds and limits.
    pub fn experiment_text(&self, has_planner: &dyn Fn(&str) -> bool) -> String {
        let files: Vec<String> = self.stored_files().into_iter().map(|f| f.0).collect();
        let mut planners = self.bench.planners.clone();
        planners.extend(
            self.bench
                .optional_planners
                .iter()
                .filter(|p| has_planner(p.split('{').next().unwrap_or(p)))
                .cloned(),
        );
        let mut t = toml::Table::new();
        t.insert(
            "name".into(),
            format!("{}-v{}", self.name, self.version).into(),
        );
        t.insert(
            "description".into(),
            format!(
                "suite {} v{} (sha256 {}): {}",
                self.name, self.version, self.sha256, self.description
            )
            .into(),
        );
        t.insert(
            "scenarios".into(),
            toml::Value::Array(files.into_iter().map(Into::into).collect()),
        );
        t.insert(
            "planners".into(),
            toml::Value::Array(planners.into_iter().map(Into::into).collect()),
        );
        t.insert("seeds".into(), (self.bench.seeds as i64).into());
        t.insert("limits".into(), self.bench.limits.clone().into());
        toml::to_string(&t).unwrap_or_default()
    }
}

/// The files in `dir/scenarios/`, sorted by name.
pub fn files_in(dir: &Path) -> Files {
    let mut v: Files = std::fs::read_dir(dir.join("scenarios"))
        .into_iter()
        .flatten()
        .flatten()
        .filter_map(|e| {
            let name = e.file_name().to_string_lossy().to_string();
            std::fs::read_to_string(e.path()).ok().map(|t| (name, t))
        })
        .collect();
    v.sort();
    v
}

#[cfg(test)]
mod tests;
