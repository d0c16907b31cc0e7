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
    // the angles labelled "f_r = 0" are where the physics' radial force vanishes, to the
    // label's two decimals (|df_r/dψ| ≤ 3 per radian: at most 3 × 0.005° = 2.7e-4)
    let ellipse = std::fs::read_to_string(out.join("force-ellipse.svg")).unwrap();
    let zero = regex::Regex::new(r"ψ = ([+−])(\d+\.\d\d)°: f_r = 0").unwrap();
    let labelled: Vec<f64> = zero
        .captures_iter(&ellipse)
        .map(|c| {
            let deg: f64 = c[2].parse().unwrap();
            if &c[1] == "−" { -deg } else { deg }
        })
        .collect();
    assert_eq!(labelled.len(), 2, "both zero-force angles are labelled");
    assert!(labelled[0] > 0.0 && labelled[1] < 0.0, "{labelled:?}");
    for deg in labelled {
        let (f_r, _) = magbench_env::controllability::velocity_ellipse(deg.to_radians());
        assert!(
            f_r.abs() <= 2.7e-4,
            "f_r at the labelled ψ = {deg}° is {f_r}"
        );
    }
    assert!(
        ellipse.contains("radial force"),
        "the axis labels are marked"
    );
    let larc = std::fs::read_to_string(out.join("larc-margin.svg")).unwrap();
    assert!(larc.contains("ψ = θ_B − φ (deg)"));
    let o = Command::new(env!("CARGO_BIN_EXE_magbench"))
        .args(["figures", "--maze-iterations", "0"])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
}
