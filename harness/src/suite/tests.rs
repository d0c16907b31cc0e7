use super::*;

fn repo_suite(name: &str) -> Suite {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../suites")
        .join(name);
    Suite::load(&dir).unwrap()
}

/// The stored files match SHA256SUMS and the manifest's hash, and the recipe redraws them
/// byte for byte.
#[test]
fn frozen_suites_match_their_hashes_and_recipes() {
    for name in ["pair-100", "team-30"] {
        let s = repo_suite(name);
        assert_eq!(s.name, name);
        assert_eq!(s.generator_version, GENERATOR_VERSION, "{name}");
        let problems = s.check(true).unwrap();
        assert!(problems.is_empty(), "{name}: {problems:?}");
    }
    assert_eq!(repo_suite("pair-100").stored_files().len(), 100);
    assert_eq!(repo_suite("team-30").stored_files().len(), 30);
}

#[test]
fn an_edited_file_breaks_the_check() {
    let tmp = tempfile::tempdir().unwrap();
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("../suites/team-30");
    std::fs::create_dir_all(tmp.path().join("scenarios")).unwrap();
    for f in [MANIFEST, SUMS] {
        std::fs::copy(src.join(f), tmp.path().join(f)).unwrap();
    }
    let s = Suite::load(tmp.path()).unwrap();
    for (n, t) in files_in(&src) {
        std::fs::write(tmp.path().join("scenarios").join(n), t).unwrap();
    }
    assert!(s.check(false).unwrap().is_empty());
    let (n, t) = &s.stored_files()[0];
    std::fs::write(tmp.path().join("scenarios").join(n), t.replace("0", "1")).unwrap();
    let problems = s.check(false).unwrap();
    assert!(
        problems[0].contains("do not match SHA256SUMS"),
        "{problems:?}"
    );
}

#[test]
fn the_bench_experiment_lists_the_files_and_optional_planners_present() {
    let s = repo_suite("team-30");
    let text = s.experiment_text(&|p| p == "ompl:rrt");
    let t: toml::Table = toml::from_str(&text).unwrap();
    assert_eq!(t["name"].as_str(), Some("team-30-v1"));
    assert_eq!(t["scenarios"].as_array().unwrap().len(), 30);
    let planners = t["planners"].as_array().unwrap();
    assert_eq!(planners.last().unwrap().as_str(), Some("ompl:rrt"));
    let text = s.experiment_text(&|_| false);
    assert!(!text.contains("ompl:rrt"));
}
