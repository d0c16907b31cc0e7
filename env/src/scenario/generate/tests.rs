//! Every family at several parameter values and seeds gives valid files, byte for byte the
//! same for the same seed; impossible parameters are refused with the parameter and reason.

use super::*;
use crate::params::owned;
use crate::scenario::difficulty::measure;

/// (family, parameters) cases spanning each family's range.
pub(crate) fn cases() -> Vec<(&'static str, Vec<(String, String)>)> {
    vec![
        ("serpentine", owned(&[])),
        (
            "serpentine",
            owned(&[("walls", "1"), ("gap", "2.5"), ("thickness", "0.3")]),
        ),
        (
            "serpentine",
            owned(&[
                ("walls", "5"),
                ("gap", "3"),
                ("spacing", "3"),
                ("height", "10"),
            ]),
        ),
        ("corridor", owned(&[])),
        (
            "corridor",
            owned(&[("bends", "0"), ("length", "12"), ("width", "2.5")]),
        ),
        (
            "corridor",
            owned(&[("bends", "6"), ("length", "60"), ("width", "3")]),
        ),
        ("clutter", owned(&[])),
        ("clutter", owned(&[("density", "0")])),
        (
            "clutter",
            owned(&[("density", "0.25"), ("size_min", "1"), ("size_max", "3")]),
        ),
        ("rooms", owned(&[])),
        ("rooms", owned(&[("rooms", "2"), ("door", "2.5")])),
        (
            "rooms",
            owned(&[("rooms", "12"), ("width", "40"), ("height", "30")]),
        ),
        ("short-moves", owned(&[])),
        (
            "short-moves",
            owned(&[("move", "swap"), ("separation", "1.5")]),
        ),
        (
            "short-moves",
            owned(&[("move", "shift"), ("angle", "90"), ("distance", "1")]),
        ),
        (
            "short-moves",
            owned(&[("angle", "30"), ("separation", "3")]),
        ),
        ("team", owned(&[("agents", "2")])),
        ("team", owned(&[])),
        (
            "team",
            owned(&[
                ("agents", "4"),
                ("start", "grid"),
                ("goal", "ring"),
                ("rotation", "45"),
            ]),
        ),
        (
            "team",
            owned(&[
                ("agents", "5"),
                ("start", "random"),
                ("goal", "random"),
                ("spacing", "1.6"),
            ]),
        ),
        (
            "team",
            owned(&[("agents", "8"), ("spacing", "1.4"), ("distance", "4")]),
        ),
        (
            "team",
            owned(&[
                ("agents", "10"),
                ("start", "triangle"),
                ("goal", "ring"),
                ("spacing", "1.5"),
            ]),
        ),
    ]
}

#[test]
fn every_family_at_several_values_and_seeds_gives_valid_problems_with_a_corridor() {
    let mut seen = std::collections::BTreeSet::new();
    for (family, params) in cases() {
        for seed in [0, 1, 17] {
            for index in 0..2 {
                let g = generate("t", family, &params, seed, index)
                    .unwrap_or_else(|e| panic!("{family} {params:?} seed {seed}: {e}"));
                let again = parse_scenario(&g.text, &g.file_name).unwrap();
                assert_eq!(again, g.scenario);
                assert!(
                    g.text
                        .contains(&format!("generator version {GENERATOR_VERSION}"))
                );
                assert!(
                    g.text
                        .contains(&format!("family {family}, seed {seed}, index {index}"))
                );
                assert_eq!(g.file_name, format!("{family}-s{seed}-{index}.toml"));
                let d = measure(&g.scenario);
                if g.scenario.agents() == 2 {
                    assert!(
                        d.path_length_bl.is_some() && d.passage_ratio >= 1.0,
                        "{family} {params:?} seed {seed}: {d:?}"
                    );
                }
            }
        }
        seen.insert(family);
    }
    assert_eq!(
        seen.len(),
        families().iter().count(),
        "a family without a test case"
    );
}

#[test]
fn the_same_seed_gives_the_same_bytes_and_another_seed_other_bytes() {
    for e in families().iter() {
        let e = e.name();
        let a = generate("t", e, &[], 5, 3).unwrap().text;
        let b = generate("t", e, &[], 5, 3).unwrap().text;
        assert_eq!(a, b, "{e}");
        let c = generate("t", e, &[], 6, 3).unwrap().text;
        let d = generate("t", e, &[], 5, 4).unwrap().text;
        assert_ne!(
            a.lines().skip(4).collect::<Vec<_>>(),
            c.lines().skip(4).collect::<Vec<_>>()
        );
        assert_ne!(
            a.lines().skip(4).collect::<Vec<_>>(),
            d.lines().skip(4).collect::<Vec<_>>()
        );
    }
}

/// (family, parameters, the field of the error, a part of its reason).
type Case = (
    &'static str,
    Vec<(&'static str, &'static str)>,
    &'static str,
    &'static str,
);

/// The error of `family` with `params`, as text; panics if it is accepted.
fn refused(family: &str, params: &[(&str, &str)]) -> InputError {
    match generate("<command line>", family, &owned(params), 0, 0) {
        Ok(_) => panic!("{family} {params:?} was accepted"),
        Err(e) => e,
    }
}

#[test]
fn impossible_parameters_are_refused_naming_the_parameter_and_the_reason() {
    let cases: Vec<Case> = vec![
        (
            "serpentine",
            vec![("gap", "2")],
            "param.gap",
            "turning width r_min + 1 = 2.25 BL",
        ),
        (
            "serpentine",
            vec![("gap", "15.5")],
            "param.gap",
            "less than 1 BL of wall",
        ),
        (
            "serpentine",
            vec![("spacing", "1")],
            "param.spacing",
            "narrower",
        ),
        (
            "serpentine",
            vec![("walls", "0")],
            "param.walls",
            "must be in [1, 32]",
        ),
        (
            "corridor",
            vec![("width", "2.3")],
            "param.width",
            "narrower",
        ),
        (
            "corridor",
            vec![("bends", "5"), ("length", "20")],
            "param.length",
            "5 bend(s)",
        ),
        (
            "clutter",
            vec![("size_min", "3"), ("size_max", "1")],
            "param.size_max",
            "size_min",
        ),
        (
            "clutter",
            vec![("density", "0.6"), ("size_max", "4"), ("size_min", "3")],
            "param.density",
            "no valid problem",
        ),
        ("rooms", vec![("rooms", "100")], "param.rooms", "do not fit"),
        ("rooms", vec![("door", "2")], "param.door", "narrower"),
        (
            "short-moves",
            vec![("angle", "5")],
            "param.angle",
            "within the goal tolerance",
        ),
        (
            "short-moves",
            vec![("separation", "1.2")],
            "param.separation",
            "proximity range",
        ),
        (
            "short-moves",
            vec![("move", "hop")],
            "param.move",
            "turn, swap, shift",
        ),
        (
            "team",
            vec![("agents", "8"), ("start", "row")],
            "param.spacing",
            "outside the proximity range",
        ),
        ("team", vec![("agents", "17")], "param.agents", "[2, 16]"),
        (
            "team",
            vec![("distance", "0")],
            "param.distance",
            "nothing to plan",
        ),
    ];
    for (family, params, field, reason) in cases {
        let e = refused(family, &params);
        assert_eq!(e.file, "<command line>");
        assert_eq!(e.field, field, "{family} {params:?}: {e}");
        assert!(e.reason.contains(reason), "{family} {params:?}: {e}");
    }
    let e = refused("spiral", &[]);
    assert!(
        e.field == "family" && e.reason.contains("serpentine"),
        "{e}"
    );
    let e = refused("rooms", &[("doors", "2")]);
    assert!(e.field == "param.doors" && e.reason.contains("door"), "{e}");
}

#[test]
fn the_list_names_every_family_and_parameter_with_its_range() {
    let l = list();
    for e in families().iter() {
        assert!(l.contains(e.name()));
        for p in e.make().params() {
            assert!(l.contains(&*p.name) && l.contains(&p.range), "{}", p.name);
        }
    }
}

#[test]
fn a_triangle_of_six_is_a_patch_of_the_hexagonal_lattice() {
    let params = owned(&[
        ("agents", "6"),
        ("start", "triangle"),
        ("goal", "triangle"),
        ("spacing", "2"),
    ]);
    let g = generate("t", "team", &params, 3, 0).unwrap();
    let a = &g.scenario.start;
    let mut d: Vec<f64> = vec![];
    for i in 0..a.len() {
        for j in (i + 1)..a.len() {
            d.push((a[i] - a[j]).norm());
        }
    }
    d.sort_by(f64::total_cmp);
    // rows of 1, 2 and 3 at spacing 2: nine neighbour pairs at 2, three at 2√3, three at 4
    let near = |x: f64, v: f64| (x - v).abs() < 2e-3;
    assert!(d[..9].iter().all(|&x| near(x, 2.0)), "{d:?}");
    assert!(
        d[9..12].iter().all(|&x| near(x, 2.0 * 3f64.sqrt())),
        "{d:?}"
    );
    assert!(d[12..].iter().all(|&x| near(x, 4.0)), "{d:?}");
}
