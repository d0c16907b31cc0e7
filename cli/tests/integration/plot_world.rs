//! The world-map renderer writes non-trivial SVG and PNG files for every built-in scenario,
//! and the GIF animator writes a multi-frame GIF.

use magbench::plot::anim::{Frame, GifOptions, render_gif};
use magbench::plot::world::{WorldPlot, render};
use magbench_env::scenario::builtin_names;
use magbench_env::{Scenario, Vec2};

fn straight(a: Vec2, b: Vec2, n: usize) -> Vec<Vec2> {
    (0..=n)
        .map(|k| a + (b - a) * (k as f64 / n as f64))
        .collect()
}

#[test]
fn renders_every_builtin_scenario_as_svg_and_png() {
    let dir = tempfile::tempdir().unwrap();
    for name in builtin_names() {
        let s = Scenario::load(name).unwrap();
        let mut p = WorldPlot::scenario(&s);
        let goal = &s.final_goal().agents;
        p.planned = s
            .start
            .iter()
            .zip(goal)
            .map(|(a, b)| straight(*a, *b, 20))
            .collect();
        p.tracked = p
            .planned
            .iter()
            .map(|path| path.iter().map(|q| q + Vec2::new(0.2, -0.1)).collect())
            .collect();
        p.tree = vec![
            (s.start[0], s.start[0] + Vec2::new(3.0, 2.0)),
            (s.start[0], s.start[0] + Vec2::new(1.0, 4.0)),
        ];
        let stem = dir.path().join("maps").join(name);
        let files = render(&p, &stem).unwrap();
        assert_eq!(files.len(), 2);
        let svg = std::fs::read_to_string(stem.with_extension("svg")).unwrap();
        assert!(svg.starts_with("<svg"), "{name}: not an SVG");
        assert!(
            svg.contains("x (BL)") && svg.contains("y (BL)"),
            "{name}: axis labels missing"
        );
        assert!(
            svg.contains("<polyline") || svg.contains("<path"),
            "{name}: no lines"
        );
        let png = std::fs::read(stem.with_extension("png")).unwrap();
        assert_eq!(&png[1..4], b"PNG", "{name}: not a PNG");
        assert!(
            png.len() > 10_000,
            "{name}: PNG suspiciously small ({} bytes)",
            png.len()
        );
    }
}

#[test]
fn png_text_is_rendered_with_the_embedded_font() {
    // A map with and without a title differ only by the title's pixels: if no font were
    // available the two PNGs would have identical text areas. Compare decoded file sizes as a
    // cheap proxy: text adds non-white pixels, so the titled PNG must be larger.
    let dir = tempfile::tempdir().unwrap();
    let s = Scenario::load("open-field").unwrap();
    let mut a = WorldPlot::scenario(&s);
    a.title = Some("A LONG TITLE WITH MANY GLYPHS ψ φ r — 0123456789".into());
    let mut b = WorldPlot::scenario(&s);
    b.title = Some(String::new());
    render(&a, &dir.path().join("a")).unwrap();
    render(&b, &dir.path().join("b")).unwrap();
    let la = std::fs::metadata(dir.path().join("a.png")).unwrap().len();
    let lb = std::fs::metadata(dir.path().join("b.png")).unwrap().len();
    assert!(
        la > lb + 500,
        "title text did not change the PNG ({la} vs {lb} bytes)"
    );
}

#[test]
fn animates_agents_to_a_gif() {
    let dir = tempfile::tempdir().unwrap();
    let s = Scenario::load("micro-factory").unwrap();
    let base = WorldPlot::scenario(&s);
    let goal = &s.final_goal().agents;
    let frames: Vec<Frame> = (0..=30)
        .map(|k| {
            let t = k as f64 / 30.0;
            Frame {
                time_s: t * 10.0,
                agents: s
                    .start
                    .iter()
                    .zip(goal)
                    .map(|(a, b)| a + (b - a) * t * 0.2)
                    .collect(),
            }
        })
        .collect();
    let path = dir.path().join("anim").join("run.gif");
    let opts = GifOptions {
        max_frames: 10,
        width_px: 400,
        ..GifOptions::default()
    };
    render_gif(&base, &frames, &path, &opts).unwrap();
    let gif = std::fs::read(&path).unwrap();
    assert_eq!(&gif[..3], b"GIF");
    // decoded, not counted by byte pattern (0x21 0xF9 also occurs inside compressed data)
    let mut d = gif::DecodeOptions::new()
        .read_info(std::fs::File::open(&path).unwrap())
        .unwrap();
    let mut frames_in_file = 0;
    while d.read_next_frame().unwrap().is_some() {
        frames_in_file += 1;
    }
    assert_eq!(frames_in_file, 10, "expected 10 frames");
}

/// The first frame of the GIF at `path` as RGBA pixels.
fn first_frame(path: &std::path::Path) -> Vec<u8> {
    let mut opts = gif::DecodeOptions::new();
    opts.set_color_output(gif::ColorOutput::RGBA);
    let mut d = opts.read_info(std::fs::File::open(path).unwrap()).unwrap();
    d.read_next_frame().unwrap().unwrap().buffer.to_vec()
}

#[test]
fn a_three_agent_gif_draws_the_third_agent_in_its_colour() {
    use magbench::plot::palette;
    let dir = tempfile::tempdir().unwrap();
    let s = Scenario::load("trio-triangle").unwrap();
    let base = WorldPlot::scenario(&s);
    let frames = vec![Frame {
        time_s: 0.0,
        agents: s.start.clone(),
    }];
    let path = dir.path().join("run.gif");
    render_gif(&base, &frames, &path, &GifOptions::default()).unwrap();
    let px = first_frame(&path);
    // GIF frames are quantised to 256 colours: near the palette colour, not exactly it
    let near = |c: plotters::style::RGBColor| {
        px.chunks(4)
            .filter(|p| {
                (p[0] as i32 - c.0 as i32).abs() <= 24
                    && (p[1] as i32 - c.1 as i32).abs() <= 24
                    && (p[2] as i32 - c.2 as i32).abs() <= 24
            })
            .count()
    };
    for i in 0..3 {
        assert!(
            near(palette::agent(i)) > 150,
            "agent {}: {}",
            i + 1,
            near(palette::agent(i))
        );
    }
    // a fourth agent's colour is nowhere
    assert!(near(palette::agent(3)) < 10, "{}", near(palette::agent(3)));
}
