//! Scenario files: every built-in validates; every rejection rule rejects with the file, the
//! field and the reason.

use magbench_env::scenario::{builtin_names, parse_scenario};
use magbench_env::{InputError, Scenario};

#[test]
fn every_builtin_scenario_validates() {
    for name in builtin_names() {
        let s = Scenario::load(name).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(s.name, name);
        assert!(s.agents() >= 2);
        for i in 0..s.legs.len() {
            let c = s.checker_for_leg(i);
            assert!(
                c.is_valid(&s.legs[i].goal.agents),
                "{name} leg {i} goal invalid"
            );
        }
        assert!(s.checker_for_leg(0).is_valid(&s.start));
    }
    let cargo = Scenario::load("cargo-delivery").unwrap();
    assert_eq!(cargo.legs.len(), 2);
    assert!(cargo.legs[1].obstacles.is_some());
    // the leg-1 goal (the start of leg 2) is also clear in the switched map
    assert!(
        cargo
            .checker_for_leg(1)
            .is_valid(&cargo.legs[0].goal.agents)
    );
}

/// A small valid scenario, mutated one field at a time by the tests.
const GOOD: &str = include_str!("../data/good.toml");

fn reject(text: &str) -> InputError {
    match parse_scenario(text, "bad.toml") {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => {
            assert_eq!(e.file, "bad.toml");
            e
        }
    }
}

fn assert_names(e: &InputError, field: &str, reason_part: &str) {
    assert_eq!(e.field, field, "wrong field in: {e}");
    assert!(
        e.reason.contains(reason_part),
        "reason {:?} lacks {:?}",
        e.reason,
        reason_part
    );
}

#[test]
fn the_good_file_parses() {
    parse_scenario(GOOD, "good.toml").unwrap();
}

#[test]
fn rejects_unknown_keys() {
    let e = reject(&GOOD.replace("tolerance = 0.5", "tolerance = 0.5\ncolour = \"red\""));
    assert_names(&e, "goal.colour", "unknown field `colour`");
    let e = reject(&GOOD.replace("polygon = ", "polygn = "));
    assert!(e.field.starts_with("world.obstacles[0]"), "{e}");
    assert!(e.reason.contains("unknown field `polygn`"), "{e}");
}

#[test]
fn rejects_nan_and_infinity() {
    let e = reject(&GOOD.replace("width = 30.0", "width = nan"));
    assert_names(&e, "world.width", "finite");
    let e = reject(&GOOD.replace("[3.0, 5.0], [5.0, 5.0]", "[3.0, inf], [5.0, 5.0]"));
    assert_names(&e, "start.agents[0][1]", "finite");
}

#[test]
fn rejects_degenerate_and_self_intersecting_polygons() {
    let e = reject(&GOOD.replace(
        "[[10.0, 0.0], [12.0, 0.0], [12.0, 8.0], [10.0, 8.0]]",
        "[[10.0, 0.0], [12.0, 8.0], [12.0, 0.0], [10.0, 8.0]]",
    ));
    assert_names(&e, "world.obstacles[0].polygon", "self-intersecting");
    let e = reject(&GOOD.replace(
        "[[10.0, 0.0], [12.0, 0.0], [12.0, 8.0], [10.0, 8.0]]",
        "[[10.0, 0.0], [11.0, 0.0], [12.0, 0.0]]",
    ));
    assert_names(&e, "world.obstacles[0].polygon", "degenerate");
}

#[test]
fn rejects_start_or_goal_in_collision_or_outside_proximity() {
    let e = reject(&GOOD.replace("[[3.0, 5.0], [5.0, 5.0]]", "[[3.0, 5.0], [10.5, 5.0]]"));
    assert_names(&e, "start.agents[1]", "collision");
    let e = reject(&GOOD.replace(
        "[[25.0, 15.0], [27.5, 15.0]]",
        "[[25.0, 15.0], [29.8, 15.0]]",
    ));
    assert_names(&e, "goal.agents[1]", "collision");
    let e = reject(&GOOD.replace("[[3.0, 5.0], [5.0, 5.0]]", "[[3.0, 5.0], [4.1, 5.0]]"));
    assert_names(&e, "start.agents", "proximity range");
    let e = reject(&GOOD.replace(
        "[[25.0, 15.0], [27.5, 15.0]]",
        "[[20.0, 15.0], [27.5, 15.0]]",
    ));
    assert_names(&e, "goal.agents", "proximity range");
}

#[test]
fn rejects_non_positive_tolerance() {
    assert_names(
        &reject(&GOOD.replace("tolerance = 0.5", "tolerance = 0.0")),
        "goal.tolerance",
        "> 0",
    );
    assert_names(
        &reject(&GOOD.replace("tolerance = 0.5", "tolerance = -1.0")),
        "goal.tolerance",
        "> 0",
    );
}

#[test]
fn rejects_agent_count_mismatch() {
    let e = reject(&GOOD.replace(
        "[[25.0, 15.0], [27.5, 15.0]]",
        "[[25.0, 15.0], [27.5, 15.0], [26.0, 17.0]]",
    ));
    assert_names(&e, "goal.agents", "counts must match");
}

#[test]
fn rejects_goal_and_legs_together_or_neither() {
    let both = format!(
        "{GOOD}\n[[legs]]\ngoal = {{ agents = [[25.0, 15.0], [27.5, 15.0]], tolerance = 0.5 }}\n"
    );
    assert_names(&reject(&both), "legs", "never both");
    let neither = GOOD.split("[goal]").next().unwrap().to_string();
    assert_names(&reject(&neither), "goal", "missing");
}

#[test]
fn rejects_bad_physics_override_and_syntax() {
    let e = reject(&format!("{GOOD}\n[physics]\nr_min = 0.9\n"));
    assert_names(&e, "physics.r_min", "> 1 BL");
    let e = reject(&format!("{GOOD}\n[physics]\nviscosity = 2.0\n"));
    assert!(
        e.field.starts_with("physics") && e.reason.contains("unknown field `viscosity`"),
        "{e}"
    );
    let e = reject("name = \"x\"\n[world\n");
    assert!(e.reason.contains("invalid TOML"), "{e}");
}

#[test]
fn missing_file_is_a_clear_error() {
    let e = Scenario::load("/nonexistent/maze.toml").unwrap_err();
    assert!(
        e.reason.contains("no such file") && e.reason.contains("micro-factory"),
        "{e}"
    );
}

/// Reproducers: inputs that panicked, hung or passed `check` and failed later.
#[test]
fn huge_coordinates_are_rejected_naming_the_vertex() {
    for x in ["1e308", "1e25", "-1e20"] {
        let e = reject(&GOOD.replace(
            "[[10.0, 0.0], [12.0, 0.0]",
            &format!("[[{x}, 0.0], [12.0, 0.0]"),
        ));
        assert_names(
            &e,
            "world.obstacles[0].polygon[0]",
            "outside the 30 × 20 BL world",
        );
    }
    // a vertex just outside the walls is fine (obstacles may overlap them)
    assert!(parse_scenario(&GOOD.replace("[10.0, 0.0]", "[10.0, -1.0]"), "ok.toml").is_ok());
    let e = reject(&GOOD.replace(
        "polygon = [[10.0, 0.0], [12.0, 0.0], [12.0, 8.0], [10.0, 8.0]]",
        "circle = { center = [1e300, 5.0], radius = 1.0 }",
    ));
    assert_names(&e, "world.obstacles[0].circle.center", "outside");
    let e = reject(&GOOD.replace(
        "polygon = [[10.0, 0.0], [12.0, 0.0], [12.0, 8.0], [10.0, 8.0]]",
        "circle = { center = [15.0, 5.0], radius = 1e300 }",
    ));
    assert_names(&e, "world.obstacles[0].circle.radius", "at most");
    let e = reject(&GOOD.replace("[3.0, 5.0], [5.0, 5.0]", "[3.0, 5.0], [1e30, 5.0]"));
    assert_names(&e, "start.agents[1]", "outside the world");
}

#[test]
fn a_huge_world_is_rejected() {
    let e = reject(&GOOD.replace("width = 30.0", "width = 1e20"));
    assert_names(&e, "world.width", "at most 10000 BL");
}

#[test]
fn a_tiny_integration_step_is_rejected() {
    let e = reject(&format!("{GOOD}[physics]\ndt_s = 1e-12\n"));
    assert_names(&e, "physics.dt_s", "must be in [0.0001, 0.05]");
}

#[test]
fn a_10000_vertex_polygon_is_refused_with_the_bound() {
    let n = 10_000;
    let ring: Vec<String> = (0..n)
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / n as f64;
            format!("[{}, {}]", 15.0 + 3.0 * a.cos(), 10.0 + 3.0 * a.sin())
        })
        .collect();
    let text = GOOD.replace(
        "[[10.0, 0.0], [12.0, 0.0], [12.0, 8.0], [10.0, 8.0]]",
        &format!("[{}]", ring.join(", ")),
    );
    let e = reject(&text);
    assert_names(&e, "world.obstacles[0].polygon", "at most 2000 vertices");
}

#[test]
fn a_later_map_covering_an_earlier_goal_is_rejected() {
    let text = include_str!("../data/leg-blocks-earlier-goal.toml");
    let e = reject(text);
    assert_names(&e, "legs[1].obstacles", "leg 2 starts at leg 1's goal");
}

#[test]
fn a_first_leg_map_covering_the_start_is_refused() {
    let text = GOOD.replace(
        "[goal]\nagents = [[25.0, 15.0], [27.5, 15.0]]\ntolerance = 0.5\n",
        "[[legs]]\ngoal = { agents = [[25.0, 15.0], [27.5, 15.0]], tolerance = 0.5 }\nobstacles = [{ circle = { center = [4.0, 5.0], radius = 2.0 } }]\n",
    );
    let e = reject(&text);
    assert_names(&e, "legs[0].obstacles", "leg 1 starts at the start");
}

#[test]
fn fixed_size_arrays_take_exactly_their_size() {
    let e = reject(&GOOD.replace("[3.0, 5.0], [5.0, 5.0]", "[4, 4, 999], [5.0, 5.0]"));
    assert_names(&e, "start.agents[0]", "invalid length 3");
    let text = GOOD.replace(
        "polygon = [[10.0, 0.0], [12.0, 0.0], [12.0, 8.0], [10.0, 8.0]]",
        "circle = { center = [10.0, 4.0, 1.0], radius = 1.0 }",
    );
    let e = reject(&text);
    assert_names(&e, "world.obstacles[0].circle.center", "invalid length 3");
}

#[test]
fn a_misspelt_table_is_named() {
    let e = reject(&GOOD.replace("[world]", "[wrold]"));
    assert!(
        e.reason.contains("is `wrold` a misspelling of `world`?"),
        "{e}"
    );
    let e = reject(&GOOD.replace("tolerance", "tolerence"));
    assert!(e.reason.contains("did you mean `tolerance`?"), "{e}");
}

#[test]
fn a_missing_field_is_not_blamed_on_a_field_beside_it() {
    // preset camera.misses: `close_range_bl` is a field of its own, not a misspelt `close_prob`
    let text = magbench_env::plant::DisturbancePreset::builtin_text("hardware").unwrap();
    let mut section = "";
    let cut: Vec<&str> = text
        .lines()
        .filter(|l| {
            if l.starts_with('[') {
                section = l.trim();
            }
            !(section == "[camera.misses]" && l.starts_with("close_prob"))
        })
        .collect();
    let e = magbench_env::input::parse_toml::<magbench_env::plant::DisturbancePreset>(
        &cut.join("\n"),
        "p.toml",
    )
    .unwrap_err();
    assert!(e.reason.contains("missing field `close_prob`"), "{e}");
    assert!(!e.reason.contains("misspelling"), "{e}");
}

#[test]
fn self_touching_polygons_are_refused() {
    // vertex 2 lies on edge 4–5: the polygon pinches to a point
    let text = GOOD.replace(
        "polygon = [[10.0, 0.0], [12.0, 0.0], [12.0, 8.0], [10.0, 8.0]]",
        "polygon = [[10.0, 0.0], [14.0, 0.0], [12.0, 4.0], [14.0, 8.0], [10.0, 8.0], [12.0, 4.0]]",
    );
    let e = reject(&text);
    assert_names(&e, "world.obstacles[0].polygon", "");
    // vertex 3 touches edge 0 inside it
    let text = GOOD.replace(
        "polygon = [[10.0, 0.0], [12.0, 0.0], [12.0, 8.0], [10.0, 8.0]]",
        "polygon = [[10.0, 0.5], [14.0, 0.5], [14.0, 8.0], [12.0, 0.5], [10.0, 8.0]]",
    );
    let e = reject(&text);
    assert_names(&e, "world.obstacles[0].polygon", "");
    // two vertices at one place, apart in the ring
    let text = GOOD.replace(
        "polygon = [[10.0, 0.0], [12.0, 0.0], [12.0, 8.0], [10.0, 8.0]]",
        "polygon = [[10.0, 0.5], [12.0, 4.0], [14.0, 0.5], [14.0, 8.0], [12.0, 4.0], [10.0, 8.0]]",
    );
    let e = reject(&text);
    assert_names(&e, "world.obstacles[0].polygon", "");
}

#[test]
fn names_a_goal_outside_the_starts_invariant_set() {
    // a square is symmetric about its centroid and every field keeps it so; a kite is 0.375 BL
    // from the nearest such formation
    let square = GOOD.replace(
        "[[3.0, 5.0], [5.0, 5.0]]",
        "[[3.0, 3.0], [5.0, 3.0], [5.0, 5.0], [3.0, 5.0]]",
    );
    let kite = "[[20.0, 15.0], [22.0, 16.0], [24.0, 15.0], [22.0, 12.5]]";
    let load = |text: &str| parse_scenario(text, "t.toml").expect("a valid scenario");
    let s = load(
        &square
            .replace("[[25.0, 15.0], [27.5, 15.0]]", kite)
            .replace("tolerance = 0.5", "tolerance = 0.3"),
    );
    let (leg, field, reason) = s.symmetric_leg().expect("a goal off the symmetric set");
    assert_eq!((leg, field.as_str()), (0, "goal.agents"));
    assert!(
        reason.contains("symmetric about its centroid")
            && reason.contains("0↔2, 1↔3")
            && reason.contains("0.375"),
        "{reason}"
    );
    // within tolerance of a symmetric formation, or from an asymmetric start, there is no note
    let near = load(
        &square
            .replace("[[25.0, 15.0], [27.5, 15.0]]", kite)
            .replace("tolerance = 0.5", "tolerance = 0.4"),
    );
    assert_eq!(near.symmetric_leg(), None);
    let kite_start = GOOD.replace(
        "[[3.0, 5.0], [5.0, 5.0]]",
        "[[3.0, 4.0], [5.0, 5.0], [7.0, 4.0], [5.0, 1.5]]",
    );
    let square_goal = "[[20.0, 13.0], [22.0, 13.0], [22.0, 15.0], [20.0, 15.0]]";
    let free = load(&kite_start.replace("[[25.0, 15.0], [27.5, 15.0]]", square_goal));
    assert_eq!(free.symmetric_leg(), None);
    // no built-in's goal lies off its start's symmetric set
    for name in builtin_names() {
        assert_eq!(
            Scenario::load(name).unwrap().symmetric_leg(),
            None,
            "{name}"
        );
    }
}

#[test]
fn names_a_goal_that_turns_a_start_no_field_turns() {
    // a square has no spin moment; the goal is the square turned by 45° about its centre
    let square = GOOD.replace(
        "[[3.0, 5.0], [5.0, 5.0]]",
        "[[3.0, 3.0], [5.0, 3.0], [5.0, 5.0], [3.0, 5.0]]",
    );
    let h = std::f64::consts::SQRT_2;
    let goal = format!(
        "[[21.0, {:.6}], [{:.6}, 14.0], [21.0, {:.6}], [{:.6}, 14.0]]",
        14.0 - h,
        21.0 + h,
        14.0 + h,
        21.0 - h
    );
    let load = |text: &str| parse_scenario(text, "t.toml").expect("a valid scenario");
    let turned = |s: &Scenario| {
        let goal = &s.legs[0].goal;
        magbench_env::team_spin::turn_note(&s.start, &goal.agents, goal.tolerance)
    };
    let s = load(&square.replace("[[25.0, 15.0], [27.5, 15.0]]", &goal));
    let reason = turned(&s).expect("a turned square");
    assert!(reason.contains("turned by 45.0°"), "{reason}");
    // the square moved without a turn, and a kite (which a field turns) turned, are not noted
    let moved = "[[20.0, 13.0], [22.0, 13.0], [22.0, 15.0], [20.0, 15.0]]";
    assert_eq!(
        turned(&load(
            &square.replace("[[25.0, 15.0], [27.5, 15.0]]", moved)
        )),
        None
    );
    let kite_start = GOOD.replace(
        "[[3.0, 5.0], [5.0, 5.0]]",
        "[[3.0, 4.0], [5.0, 5.0], [7.0, 4.0], [5.0, 1.5]]",
    );
    // the kite turned by 90° about its centroid
    let kite_turned = "[[20.625, 12.0], [19.625, 14.0], [20.625, 16.0], [23.125, 14.0]]";
    let kite = load(&kite_start.replace("[[25.0, 15.0], [27.5, 15.0]]", kite_turned));
    let (angle, left) = magbench_env::team_spin::best_turn(&kite.start, &kite.legs[0].goal.agents);
    assert!((angle.to_degrees() - 90.0).abs() < 1e-9 && left < 1e-9);
    assert_eq!(turned(&kite), None);
}
