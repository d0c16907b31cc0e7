//! The difficulty measures against values computed by hand on simple maps.

use super::*;
use crate::scenario::parse_scenario;

fn scenario(obstacles: &str, start: &str, goal: &str) -> Scenario {
    let text = format!(
        "name = \"t\"\n[world]\nwidth = 30.0\nheight = 20.0\n{obstacles}\n[start]\nagents = {start}\n\
         [goal]\nagents = {goal}\ntolerance = 0.5\n"
    );
    parse_scenario(&text, "t").unwrap()
}

fn close(a: f64, b: f64, tol: f64, what: &str) {
    assert!(
        (a - b).abs() <= tol,
        "{what}: {a} is not within {tol} of {b}"
    );
}

#[test]
fn an_empty_box_is_all_free_with_a_straight_path() {
    let s = scenario(
        "",
        "[[4.0, 10.0], [6.0, 10.0]]",
        "[[24.0, 9.0], [24.0, 11.5]]",
    );
    let d = measure(&s);
    assert_eq!(d.free_fraction, 1.0);
    assert_eq!(d.grid_bl, 0.1);
    close(d.min_width_bl, 2.25, 1e-12, "min width");
    close(d.path_clearance_bl, 1.125, 1e-12, "clearance");
    // the widest path's narrowest place is at the start: its centroid (5, 10) is 5 BL from
    // the left wall (its cell centre 4.95 BL from the top wall)
    close(d.narrowest_passage_bl, 10.0, 0.2, "narrowest passage");
    close(d.passage_ratio, 10.0 / 2.25, 0.1, "ratio");
    // centroid (5, 10) to (24, 10.25), in a straight line
    let straight = (19.0f64.powi(2) + 0.25f64.powi(2)).sqrt();
    close(d.path_length_bl.unwrap(), straight, 1e-9, "path length");
    assert_eq!(d.path_turns, Some(0));
    close(d.centroid_move_bl, straight, 1e-12, "centroid move");
    close(d.span_start_bl, 2.0, 1e-12, "span at start");
    close(d.span_goal_bl, 2.5, 1e-12, "span at goal");
    close(d.rotation_deg, 90.0, 1e-9, "rotation");
    close(d.shape_change_bl, 0.25, 1e-12, "shape change");
}

#[test]
fn a_wall_with_a_gap_gives_the_gap_as_the_passage_and_a_path_around_its_corners() {
    // a 2 BL thick wall across the field at x = 14..16 with a 3 BL gap at y = 8..11
    let wall = "[[world.obstacles]]\npolygon = [[14.0, 0.0], [16.0, 0.0], [16.0, 8.0], [14.0, 8.0]]\n\
                [[world.obstacles]]\npolygon = [[14.0, 11.0], [16.0, 11.0], [16.0, 20.0], [14.0, 20.0]]\n";
    let s = scenario(
        wall,
        "[[4.0, 15.0], [6.0, 15.0]]",
        "[[24.0, 15.0], [26.0, 15.0]]",
    );
    let d = measure(&s);
    close(d.free_fraction, 1.0 - 34.0 / 600.0, 0.005, "free fraction");
    close(d.narrowest_passage_bl, 3.0, 0.2, "narrowest passage");
    close(d.passage_ratio, 3.0 / 2.25, 0.1, "ratio");
    // centroid (5, 15) to (25, 15) under the corners (14, 11) and (16, 11), kept r = 1.125 BL
    // away: a tangent to each corner's circle, its arc down to y = 11 − r, and 2 BL between
    let r = 1.125;
    let d_corner = (9.0f64.powi(2) + 4.0f64.powi(2)).sqrt();
    let tangent = (d_corner * d_corner - r * r).sqrt();
    let arc = 270f64.to_radians() - (4.0f64.atan2(-9.0) + (r / d_corner).acos());
    let by_hand = 2.0 * (tangent + r * arc) + 2.0;
    close(d.path_length_bl.unwrap(), by_hand, 0.25, "path length");
    // a bend down past the first corner, one back past the second: 2 turns of arc each
    assert_eq!(d.path_turns, Some(2), "{d:?}");
    close(
        d.path_turning_deg.unwrap(),
        2.0 * arc.to_degrees(),
        8.0,
        "turning",
    );
    close(d.rotation_deg, 0.0, 1e-12, "rotation");
}

#[test]
fn a_closed_wall_leaves_no_path_and_no_passage() {
    let wall =
        "[[world.obstacles]]\npolygon = [[14.0, 0.0], [16.0, 0.0], [16.0, 20.0], [14.0, 20.0]]\n";
    let s = scenario(
        wall,
        "[[4.0, 15.0], [6.0, 15.0]]",
        "[[24.0, 15.0], [26.0, 15.0]]",
    );
    let d = measure(&s);
    assert_eq!(d.path_length_bl, None);
    assert_eq!(d.path_turns, None);
    assert_eq!(d.narrowest_passage_bl, 0.0);
    let cols = d.columns();
    assert_eq!(cols.len(), COLUMNS.len());
    assert_eq!(cols[6], ("path_length_bl", String::new()));
}

#[test]
fn a_swap_is_a_half_turn() {
    let s = scenario(
        "",
        "[[4.0, 10.0], [6.0, 10.0]]",
        "[[6.0, 10.0], [4.0, 10.0]]",
    );
    let d = measure(&s);
    close(d.rotation_deg, 180.0, 1e-9, "rotation");
    close(d.centroid_move_bl, 0.0, 1e-12, "centroid");
    assert_eq!(d.path_length_bl, Some(0.0));
}
