//! `magbench figures` writes every paper figure as SVG (vector) and PNG.

use std::process::Command;

#[test]
fn figures_are_written_as_svg_and_png() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("figs");
    let o = Command::new(env!("CARGO_BIN_EXE_magbench"))
        .args([
            "figures",
            "--out",
            out.to_str().unwrap(),
            "--maze-iterations",
            "1500",
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for f in [
        "fig1-force-along-path",
        "fig4a-cspace",
        "fig4b-world",
        "force-ellipse",
        "larc-margin",
        "micro-factory",
    ] {
        let svg = std::fs::read_to_string(out.join(format!("{f}.svg"))).unwrap();
        assert!(svg.starts_with("<svg") && svg.len() > 5000, "{f}.svg");
        let png = std::fs::read(out.join(format!("{f}.png"))).unwrap();
        assert!(&png[1..4] == b"PNG" && png.len() > 20_000, "{f}.png");
    }
    let ellipse = std::fs::read_to_string(out.join("force-ellipse.svg")).unwrap();
    assert!(
        ellipse.contains("54.74°") && ellipse.contains("radial force"),
        "ψ = ±54.74° and axis labels must be marked"
    );
    let larc = std::fs::read_to_string(out.join("larc-margin.svg")).unwrap();
    assert!(larc.contains("ψ = θ_B − φ (deg)"));
    let o = Command::new(env!("CARGO_BIN_EXE_magbench"))
        .args(["figures", "--maze-iterations", "0"])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
}
