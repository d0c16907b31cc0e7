//! `cargo xtask lines`: each crate's share of the project's non-test lines, as a Markdown table.
//!
//! A line counts when it is not blank, in a `.rs` file of a crate's sources (`src/`, and
//! `benches/` for the benches crate), before the file's first `#[cfg(test)]`; files named
//! `tests.rs` or `*_tests.rs` and folders named `tests` are test code and do not count.

use std::path::Path;

use magbench::table::Table;

/// The project's crates: package name and folder.
pub const CRATES: [(&str, &str); 13] = [
    ("magbench-env", "env"),
    ("magbench-planners", "planners"),
    ("magbench-trackers", "trackers"),
    ("magbench-drivers", "drivers"),
    ("magbench-analysis", "analysis"),
    ("magbench-plot", "plot"),
    ("magbench-store", "store"),
    ("magbench-harness", "harness"),
    ("magbench", "cli"),
    ("magbench-benches", "benches"),
    ("magbench-python", "python"),
    ("xtask", "xtask"),
    ("my-magbench", "examples/plugin-crate"),
];

/// The non-test lines of the Rust source `text`: not blank, before the first `#[cfg(test)]`.
pub fn non_test_lines(text: &str) -> usize {
    text.lines()
        .map(str::trim)
        .take_while(|l| !l.starts_with("#[cfg(test)]"))
        .filter(|l| !l.is_empty())
        .count()
}

/// Whether `path` (a file or folder name) holds test code only.
fn is_test(name: &str) -> bool {
    name == "tests" || name == "tests.rs" || name.ends_with("_tests.rs")
}

/// The non-test lines of the `.rs` files under `dir`, recursively.
pub fn lines_under(dir: &Path) -> std::io::Result<usize> {
    let mut n = 0;
    if !dir.is_dir() {
        return Ok(0);
    }
    for entry in std::fs::read_dir(dir)? {
        let entry = entry?;
        let path = entry.path();
        let name = entry.file_name().to_string_lossy().into_owned();
        if is_test(&name) {
            continue;
        }
        if path.is_dir() {
            n += lines_under(&path)?;
        } else if name.ends_with(".rs") {
            n += non_test_lines(&std::fs::read_to_string(&path)?);
        }
    }
    Ok(n)
}

/// The non-test lines of crate folder `folder` of the repository at `root`.
pub fn crate_lines(root: &Path, folder: &str) -> std::io::Result<usize> {
    let sources = if folder == "benches" {
        "benches"
    } else {
        "src"
    };
    lines_under(&root.join(folder).join(sources))
}

/// Every crate's package name, folder and non-test lines, largest first.
pub fn counts(root: &Path) -> std::io::Result<Vec<(&'static str, &'static str, usize)>> {
    let mut counts = CRATES
        .iter()
        .map(|&(name, folder)| Ok((name, folder, crate_lines(root, folder)?)))
        .collect::<std::io::Result<Vec<_>>>()?;
    counts.sort_by(|a, b| b.2.cmp(&a.2).then(a.0.cmp(b.0)));
    Ok(counts)
}

/// The table of every crate's non-test lines and share, largest first.
pub fn table(root: &Path) -> std::io::Result<Table> {
    let counts = counts(root)?;
    let total: usize = counts.iter().map(|c| c.2).sum();
    let mut t = Table::new(&["crate", "folder", "non-test lines", "share"]);
    for (name, folder, n) in counts {
        let share = 100.0 * n as f64 / total.max(1) as f64;
        t.row(vec![
            format!("`{name}`"),
            format!("`{folder}/`"),
            n.to_string(),
            format!("{share:.1}%"),
        ]);
    }
    t.row(vec![
        "total".into(),
        String::new(),
        total.to_string(),
        "100%".into(),
    ]);
    Ok(t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blank_lines_and_the_test_module_do_not_count() {
        let text = "//! doc\n\nfn a() {}\n\n#[cfg(test)]\nmod tests {\n    fn t() {}\n}\n";
        assert_eq!(non_test_lines(text), 2);
        assert_eq!(non_test_lines(""), 0);
    }

    #[test]
    fn test_files_and_folders_do_not_count() {
        let dir = tempfile::tempdir().unwrap();
        let src = dir.path().join("c/src");
        std::fs::create_dir_all(src.join("tests")).unwrap();
        std::fs::create_dir_all(src.join("m")).unwrap();
        std::fs::write(src.join("lib.rs"), "mod m;\nfn f() {}\n").unwrap();
        std::fs::write(src.join("m/mod.rs"), "fn g() {}\n").unwrap();
        std::fs::write(src.join("m/tests.rs"), "fn t() {}\n").unwrap();
        std::fs::write(src.join("m/x_tests.rs"), "fn t() {}\n").unwrap();
        std::fs::write(src.join("tests/a.rs"), "fn t() {}\n").unwrap();
        std::fs::write(src.join("notes.md"), "text\n").unwrap();
        assert_eq!(crate_lines(dir.path(), "c").unwrap(), 3);
    }

    #[test]
    fn no_crate_holds_more_than_a_quarter_of_the_project_s_lines() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
        let counts = counts(&root).unwrap();
        let total: usize = counts.iter().map(|c| c.2).sum();
        for (name, _, n) in counts {
            assert!(4 * n <= total, "{name} holds {n} of {total} non-test lines");
        }
    }

    #[test]
    fn every_crate_folder_of_the_repository_exists() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
        for (name, folder) in CRATES {
            assert!(
                root.join(folder).join("Cargo.toml").is_file(),
                "{name}: {folder}/Cargo.toml"
            );
        }
    }
}
