//! Embeds the versions of key crates (from the workspace's Cargo.lock) for results manifests.

fn main() {
    let lock = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../Cargo.lock");
    println!("cargo:rerun-if-changed={}", lock.display());
    let wanted = [
        "magbench",
        "magbench-env",
        "magbench-planners",
        "magbench-trackers",
        "magbench-drivers",
        "nalgebra",
        "parry2d-f64",
        "kiddo",
        "rand",
        "rand_chacha",
        "rayon",
        "plotters",
        "statrs",
        "csv",
        "toml",
        "serde",
    ];
    let text = std::fs::read_to_string(&lock).unwrap_or_default();
    let mut out = vec![];
    let mut name: Option<String> = None;
    for line in text.lines() {
        let line = line.trim();
        if line == "[[package]]" {
            name = None;
        } else if let Some(v) = line.strip_prefix("name = ") {
            name = Some(v.trim_matches('"').to_string());
        } else if let Some((v, n)) = line
            .strip_prefix("version = ")
            .zip(name.take())
            .filter(|(_, n)| wanted.contains(&n.as_str()))
        {
            out.push(format!("{n}={}", v.trim_matches('"')));
        }
    }
    println!("cargo:rustc-env=MAGBENCH_CRATE_VERSIONS={}", out.join(";"));
}
