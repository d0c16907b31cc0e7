//! Whether a file in `docs/measured/` still measures the current code: its header names the git
//! revision it was measured at, its [`Measure`] names the source paths its figures depend on,
//! and git says whether any of those paths changed since. A file whose every changed line is
//! blank or a comment where it stands ([`is_comment`]), or that moved whole, changed no figure
//! and does not count.

use std::collections::{BTreeSet, HashMap};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::{Arc, Mutex, OnceLock};

use thiserror::Error;

use super::header::{ParseError, parse};
use super::measures::Measure;

/// Why a generated file may not hold what its measurement gives on the current code.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Staleness {
    /// The header's revision had uncommitted changes outside `docs/measured/`: the measured
    /// code is in no commit.
    Dirty {
        /// The revision named, without `+dirty`.
        revision: String,
    },
    /// Source paths the measurement depends on changed in commits after the measured one.
    Changed {
        /// The revision named.
        revision: String,
        /// The changed files, relative to the repository root.
        files: Vec<String>,
    },
    /// The header names no git revision (`magbench: … (git unknown)` or none).
    NoRevision,
}

impl std::fmt::Display for Staleness {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Staleness::Dirty { revision } => write!(
                f,
                "measured on a tree with uncommitted changes (git {}+dirty)",
                short(revision)
            ),
            Staleness::Changed { revision, files } => {
                let shown: Vec<&str> = files.iter().take(4).map(String::as_str).collect();
                let more = match files.len().saturating_sub(shown.len()) {
                    0 => String::new(),
                    n => format!(" and {n} more"),
                };
                write!(
                    f,
                    "measured at {}; since then {}{more} changed",
                    short(revision),
                    shown.join(", ")
                )
            }
            Staleness::NoRevision => write!(f, "its header names no git revision"),
        }
    }
}

fn short(revision: &str) -> &str {
    &revision[..revision.len().min(10)]
}

/// Why freshness could not be decided.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum FreshnessError {
    /// `git` could not run or failed.
    #[error("git {args}: {reason}")]
    Git {
        /// The arguments given.
        args: String,
        /// What went wrong (git's stderr).
        reason: String,
    },
    /// The revision a header names is not in this clone's history (a shallow clone, or a
    /// revision never pushed).
    #[error(
        "revision {0} is not in this repository's history (a shallow clone? `git fetch --unshallow`)"
    )]
    UnknownRevision(String),
    /// The file is not a generated file.
    #[error("header: {0}")]
    Header(#[from] ParseError),
}

/// The revision named in a header's `magbench` value (`0.1.0 (git REV)` or `(git REV+dirty)`)
/// and whether it is marked dirty; `None` when it names none.
pub fn revision(version: &str) -> Option<(String, bool)> {
    let rest = &version[version.find("(git ")? + 5..];
    let rev = &rest[..rest.find(')')?];
    let (rev, dirty) = match rev.strip_suffix("+dirty") {
        Some(r) => (r, true),
        None => (rev, false),
    };
    let hex = rev.len() >= 7 && rev.chars().all(|c| c.is_ascii_hexdigit());
    hex.then(|| (rev.to_string(), dirty))
}

/// The git pathspecs of the source a measurement's figures depend on: its own file (the
/// experiment, bench, test, example or script), its declared [`Measure::depends`] and the
/// files of the planners and trackers it names ([`Measure::named_files`], read under `root`).
pub fn pathspecs(root: &Path, m: &Measure) -> Vec<String> {
    let mut v: Vec<String> = m.own_files();
    v.extend(m.named_files(root).iter().map(|f| f.to_string()));
    v.extend(
        m.depends
            .iter()
            .flat_map(|g| g.iter())
            .map(|p| p.to_string()),
    );
    v
}

/// Whether the generated file `text` (its whole content) is stale for measurement `m`: the
/// [`staleness`] of the revision its header's `magbench` line names.
pub fn file_staleness(
    root: &Path,
    m: &Measure,
    text: &str,
) -> Result<Option<Staleness>, FreshnessError> {
    let header = parse(text)?;
    staleness(root, m, header.field("magbench").unwrap_or_default())
}

/// Whether the generated file with header value `version` (its `magbench` line) is stale for
/// measurement `m` in the git repository at `root`: `Ok(None)` when the file names a clean
/// revision and no path of [`pathspecs`] changed between it and `HEAD`.
pub fn staleness(
    root: &Path,
    m: &Measure,
    version: &str,
) -> Result<Option<Staleness>, FreshnessError> {
    let Some((revision, dirty)) = revision(version) else {
        return Ok(Some(Staleness::NoRevision));
    };
    let object = format!("{revision}^{{commit}}");
    if git(root, &["cat-file", "-e", &object]).is_err() {
        return Err(FreshnessError::UnknownRevision(revision));
    }
    if dirty {
        return Ok(Some(Staleness::Dirty { revision }));
    }
    let named = m.named_files(root);
    let files: Vec<String> = code_changes(root, &revision)?
        .iter()
        .filter(|f| depends_on(m, &named, f))
        .cloned()
        .collect();
    Ok((!files.is_empty()).then_some(Staleness::Changed { revision, files }))
}

/// Whether `line` of file `path` is blank or a comment where it stands: `//` (doc comments
/// included) in Rust, `#` in TOML, Python and shell. A line inside a string literal that begins
/// like a comment would be misread; in any other kind of file no line is a comment.
pub fn is_comment(path: &str, line: &str) -> bool {
    let t = line.trim();
    if t.is_empty() {
        return true;
    }
    match path.rsplit_once('.').map(|(_, ext)| ext) {
        Some("rs") => t.starts_with("//"),
        Some("toml" | "py" | "sh") => t.starts_with('#'),
        _ => false,
    }
}

/// The files changed between `revision` and `HEAD` (by their names at `HEAD`, in path order) in
/// a line that is not blank and not a comment ([`is_comment`]), or as binary files; read once
/// per repository and pair of revisions. A file moved whole, under git's rename detection, has no such line.
fn code_changes(root: &Path, revision: &str) -> Result<Arc<BTreeSet<String>>, FreshnessError> {
    type Cache = Mutex<HashMap<(PathBuf, String, String), Arc<BTreeSet<String>>>>;
    static CACHE: OnceLock<Cache> = OnceLock::new();
    let head = git(root, &["rev-parse", "HEAD"])?.trim().to_string();
    let key = (root.to_path_buf(), revision.to_string(), head.clone());
    let cache = CACHE.get_or_init(Cache::default);
    if let Some(hit) = cache.lock().ok().and_then(|c| c.get(&key).cloned()) {
        return Ok(hit);
    }
    let diff = git(
        root,
        &[
            "diff",
            "-U0",
            "-M",
            "--no-color",
            "--no-ext-diff",
            revision,
            &head,
        ],
    )?;
    let mut code = BTreeSet::new();
    let mut current: Option<String> = None;
    for line in diff.lines() {
        if let Some(rest) = line.strip_prefix("diff --git ") {
            current = rest.rsplit_once(" b/").map(|(_, b)| b.to_string());
            continue;
        }
        let Some(file) = &current else { continue };
        if line.starts_with("+++ ") || line.starts_with("--- ") {
            continue;
        }
        let changed = line.strip_prefix('+').or_else(|| line.strip_prefix('-'));
        if line.starts_with("Binary files ") || changed.is_some_and(|t| !is_comment(file, t)) {
            code.insert(file.clone());
        }
    }
    let code = Arc::new(code);
    if let Ok(mut c) = cache.lock() {
        c.insert(key, code.clone());
    }
    Ok(code)
}

/// Whether the figures of `m` depend on the repository file `path`: its own files, the files of
/// the planners and trackers it names (`named`), or a group of [`Measure::depends`] that holds
/// it. Within a group the longest path that covers `path` decides (`harness/src` with
/// `:!harness/src/regress` leaves out that folder and holds the rest); each group decides
/// alone, so one group's exclusion never hides a path another group declares.
fn depends_on(m: &Measure, named: &[&str], path: &str) -> bool {
    let covers = |spec: &str| {
        let spec = spec.trim_end_matches('/');
        path == spec
            || path
                .strip_prefix(spec)
                .is_some_and(|rest| rest.starts_with('/'))
    };
    let own = m.own_files();
    own.iter().any(|f| covers(f))
        || named.iter().any(|f| covers(f))
        || m.depends.iter().any(|group| {
            group
                .iter()
                .map(|s| match s.strip_prefix(":!") {
                    Some(excluded) => (excluded, false),
                    None => (*s, true),
                })
                .filter(|(spec, _)| covers(spec))
                .max_by_key(|(spec, _)| spec.len())
                .is_some_and(|(_, included)| included)
        })
}

/// Runs `git -C root ARGS` and returns its stdout.
fn git(root: &Path, args: &[&str]) -> Result<String, FreshnessError> {
    let failed = |reason: String| FreshnessError::Git {
        args: args.join(" "),
        reason,
    };
    let out = Command::new("git")
        .arg("-C")
        .arg(root)
        .args(args)
        .output()
        .map_err(|e| failed(e.to_string()))?;
    if !out.status.success() {
        return Err(failed(String::from_utf8_lossy(&out.stderr).trim().into()));
    }
    Ok(String::from_utf8_lossy(&out.stdout).into_owned())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::docs::measures::{Kind, Source};
    use crate::docs::tables::planning;

    /// A measurement of `exp.toml` depending on `src/` but `src/docs`.
    const M: Measure = Measure {
        name: "m",
        source: Source::Sweep {
            experiment: "exp.toml",
            quick_seeds: 1,
            table: Kind::Runs(planning),
            figures: &[],
        },
        feature: None,
        depends: &[&["src", ":!src/docs"]],
    };

    /// A git repository with `exp.toml`, `src/a.rs`, `src/docs/b.rs` and `other.rs` committed;
    /// returns it and the commit.
    fn repo() -> (tempfile::TempDir, String) {
        let dir = tempfile::tempdir().unwrap();
        let root = dir.path();
        for (f, text) in [
            ("exp.toml", "x"),
            ("src/a.rs", "a"),
            ("src/docs/b.rs", "b"),
            ("other.rs", "o"),
        ] {
            let p = root.join(f);
            std::fs::create_dir_all(p.parent().unwrap()).unwrap();
            std::fs::write(p, text).unwrap();
        }
        let rev = commit(root, "first");
        (dir, rev)
    }

    fn commit(root: &Path, msg: &str) -> String {
        let id = [
            "-c",
            "user.name=t",
            "-c",
            "user.email=t@t",
            "-c",
            "commit.gpgsign=false",
        ];
        git(root, &["init", "-q"]).unwrap();
        git(root, &["add", "-A"]).unwrap();
        let mut args = id.to_vec();
        args.extend(["commit", "-q", "-m", msg]);
        git(root, &args).unwrap();
        git(root, &["rev-parse", "HEAD"])
            .unwrap()
            .trim()
            .to_string()
    }

    /// The staleness of a file measured at `rev` when `file` changed since.
    fn changed(rev: &str, file: &str) -> Result<Option<Staleness>, FreshnessError> {
        Ok(Some(Staleness::Changed {
            revision: rev.to_string(),
            files: vec![file.to_string()],
        }))
    }

    fn version(rev: &str) -> String {
        format!("0.1.0 (git {rev})")
    }

    #[test]
    fn a_file_measured_at_head_is_fresh() {
        let (dir, rev) = repo();
        assert_eq!(staleness(dir.path(), &M, &version(&rev)), Ok(None));
    }

    #[test]
    fn a_change_to_an_undeclared_or_excluded_path_keeps_it_fresh() {
        let (dir, rev) = repo();
        std::fs::write(dir.path().join("other.rs"), "o2").unwrap();
        std::fs::write(dir.path().join("src/docs/b.rs"), "b2").unwrap();
        commit(dir.path(), "second");
        assert_eq!(staleness(dir.path(), &M, &version(&rev)), Ok(None));
    }

    /// Two groups: one that excludes `src/docs`, one that declares `src/docs/b.rs`.
    const TWO: Measure = Measure {
        name: "two",
        source: Source::Sweep {
            experiment: "exp.toml",
            quick_seeds: 1,
            table: Kind::Runs(planning),
            figures: &[],
        },
        feature: None,
        depends: &[&["src", ":!src/docs"], &["src/docs/b.rs"]],
    };

    #[test]
    fn one_groups_exclusion_does_not_hide_a_path_another_group_declares() {
        let (dir, rev) = repo();
        std::fs::write(dir.path().join("src/docs/b.rs"), "b2").unwrap();
        commit(dir.path(), "second");
        assert_eq!(
            staleness(dir.path(), &TWO, &version(&rev)),
            changed(&rev, "src/docs/b.rs")
        );
        assert_eq!(staleness(dir.path(), &M, &version(&rev)), Ok(None));
    }

    #[test]
    fn within_a_group_the_longest_covering_path_decides() {
        let group: &[&[&str]] = &[&["src", ":!src/docs", "src/docs/b.rs"]];
        let m = Measure {
            depends: group,
            ..M
        };
        assert!(depends_on(&m, &[], "src/a.rs"));
        assert!(depends_on(&m, &[], "src/docs/b.rs"));
        assert!(!depends_on(&m, &[], "src/docs/c.rs"));
        assert!(!depends_on(&m, &[], "srcx/a.rs"));
        assert!(depends_on(&m, &[], "exp.toml"));
        // a planner's file, excluded by the group, counts when the measurement runs it
        assert!(depends_on(&m, &["src/docs"], "src/docs/c.rs"));
    }

    #[test]
    fn a_change_to_a_declared_path_or_its_own_file_makes_it_stale() {
        for file in ["src/a.rs", "exp.toml"] {
            let (dir, rev) = repo();
            std::fs::write(dir.path().join(file), "changed").unwrap();
            commit(dir.path(), "second");
            assert_eq!(
                staleness(dir.path(), &M, &version(&rev)),
                changed(&rev, file),
                "{file}"
            );
        }
    }

    #[test]
    fn a_change_to_comments_only_keeps_it_fresh_and_one_line_of_code_makes_it_stale() {
        let (dir, rev) = repo();
        let root = dir.path();
        // "a" stays the file's last line, without a newline, so only comment lines change
        std::fs::write(root.join("src/a.rs"), "/// what a does\n\n// why\na").unwrap();
        std::fs::write(root.join("exp.toml"), "# the experiment\nx").unwrap();
        commit(root, "comments");
        assert_eq!(staleness(root, &M, &version(&rev)), Ok(None));
        std::fs::write(root.join("src/a.rs"), "/// what a does\na2\n").unwrap();
        commit(root, "code");
        assert_eq!(
            staleness(root, &M, &version(&rev)),
            changed(&rev, "src/a.rs")
        );
    }

    #[test]
    fn a_file_moved_whole_keeps_it_fresh_and_a_moved_file_edited_makes_it_stale() {
        let (dir, rev) = repo();
        let root = dir.path();
        std::fs::create_dir_all(root.join("src/moved")).unwrap();
        std::fs::rename(root.join("src/a.rs"), root.join("src/moved/a.rs")).unwrap();
        commit(root, "moved");
        assert_eq!(staleness(root, &M, &version(&rev)), Ok(None));
        std::fs::write(root.join("src/moved/a.rs"), "a\nb").unwrap();
        commit(root, "edited");
        // a one-line file edited is no longer git's rename of the old one: both names count
        match staleness(root, &M, &version(&rev)) {
            Ok(Some(Staleness::Changed { files, .. })) => {
                assert!(files.contains(&"src/moved/a.rs".to_string()), "{files:?}")
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn a_comment_is_known_by_the_files_kind_and_a_binary_change_counts() {
        assert!(is_comment("x.rs", "  //! doc"));
        assert!(is_comment("x.rs", ""));
        assert!(!is_comment("x.rs", "# not rust"));
        assert!(is_comment("x.toml", "# note"));
        assert!(is_comment("x.py", "#!/usr/bin/env python3"));
        assert!(!is_comment("x.toml", "seeds = 5 # a note after a value"));
        assert!(!is_comment("x.md", "<!-- no comment rule for Markdown -->"));
        assert!(!is_comment("Makefile", "# no extension"));
        let (dir, rev) = repo();
        std::fs::write(dir.path().join("src/data.bin"), [0u8, 159, 146, 150]).unwrap();
        commit(dir.path(), "binary");
        assert_eq!(
            staleness(dir.path(), &M, &version(&rev)),
            changed(&rev, "src/data.bin")
        );
    }

    #[test]
    fn a_dirty_tree_or_no_revision_is_stale_and_an_unknown_one_an_error() {
        let (dir, rev) = repo();
        let dirty = format!("0.1.0 (git {rev}+dirty)");
        assert_eq!(
            staleness(dir.path(), &M, &dirty),
            Ok(Some(Staleness::Dirty { revision: rev }))
        );
        assert_eq!(
            staleness(dir.path(), &M, "0.1.0 (git unknown)"),
            Ok(Some(Staleness::NoRevision))
        );
        let unknown = "0.1.0 (git 0123456789abcdef0123456789abcdef01234567)";
        assert!(matches!(
            staleness(dir.path(), &M, unknown),
            Err(FreshnessError::UnknownRevision(_))
        ));
    }

    #[test]
    fn reads_the_revision_and_its_dirty_mark() {
        let clean = "0.1.0 (git 9c6638f3cc9a36be300ef68e065623af26489037)";
        assert_eq!(
            revision(clean),
            Some(("9c6638f3cc9a36be300ef68e065623af26489037".into(), false))
        );
        assert_eq!(
            revision("0.1.0 (git 9c6638f+dirty)"),
            Some(("9c6638f".into(), true))
        );
        assert_eq!(revision("0.1.0 (git unknown)"), None);
        assert_eq!(revision("0.1.0"), None);
    }

    /// A script that imports `magbench` runs the package's own Python modules besides the
    /// binding's Rust core: the binding's measurements depend on every module, so a change to
    /// one stales them.
    #[test]
    fn the_bindings_measurements_depend_on_every_module_of_the_package() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
        let modules: Vec<String> = std::fs::read_dir(root.join("python/magbench"))
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|name| name.ends_with(".py"))
            .map(|name| format!("python/magbench/{name}"))
            .collect();
        assert!(!modules.is_empty(), "python/magbench holds no module");
        for name in ["python-overhead", "python-rrt", "python-plugins"] {
            let m = crate::docs::measures::MEASURES
                .iter()
                .find(|m| m.name == name)
                .expect(name);
            for module in &modules {
                assert!(
                    depends_on(m, &[], module),
                    "{name} does not depend on {module}"
                );
            }
        }
    }
}
