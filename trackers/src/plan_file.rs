//! Plan files: a [`Plan`] as JSON, read back bit for bit.
//!
//! The pair dynamics amplify a one-ulp difference in a control or a start into BL at the end of
//! a long plan, so a plan read from a file must be the plan that was written. serde_json writes
//! the shortest exact representation of every f64; this crate enables its `float_roundtrip`
//! feature so that reading it back is exact too (without it, parsing can be off by one ulp).

use std::path::Path;

use magbench_env::{InputError, Scenario};
use magbench_planners::{MadeFor, Plan, PlanError, PlanningSetup, validate_path};

/// Longest plan accepted (s of motion): an hour, far beyond any scenario's. A plan is resampled
/// at every integration step to be tracked; 1e10 s would need terabytes.
pub const MAX_PLAN_DURATION_S: f64 = 3600.0;

/// Reads and checks a plan file for a team of `agents` (its form only).
pub fn read_plan(path: &Path, agents: usize) -> Result<Plan, InputError> {
    let file = path.display().to_string();
    let text = magbench_env::input::read_text(path, &file)?;
    parse_plan(&text, &file, agents)
}

/// Checks a well-formed plan against the first leg of `scenario`: at most
/// [`MAX_PLAN_DURATION_S`] long, every state inside the world, and then the planners' own
/// validator from the plan's start under `setup` — controls within the coil's limits (its
/// elevation range, and no elevation where the medium does not carry the out-of-plane force),
/// durations in whole control periods (the frames of the rig that will run it), no collision
/// or proximity violation along any edge, and every stored state what the planning model
/// replays. `file` names the plan in errors.
pub fn check_plan(
    plan: &Plan,
    scenario: &Scenario,
    file: &str,
    setup: &PlanningSetup,
) -> Result<(), InputError> {
    let bad = |field: String, reason: String| InputError::new(file, field, reason);
    let total: f64 = plan.durations.iter().sum();
    if total.is_nan() || total > MAX_PLAN_DURATION_S {
        return Err(bad(
            "durations".into(),
            format!("the plan lasts {total} s; at most {MAX_PLAN_DURATION_S} s"),
        ));
    }
    let w = &scenario.world;
    for (k, s) in plan.states.iter().enumerate() {
        if let Some((i, p)) = s.iter().enumerate().find(|(_, p)| !w.contains(**p)) {
            return Err(bad(
                format!("states[{k}][{i}]"),
                format!(
                    "({}, {}) is outside the world [0, {}] × [0, {}] of {}",
                    p.x, p.y, w.width, w.height, scenario.name
                ),
            ));
        }
    }
    let problem = setup.problem(scenario, 0, Some(plan.start()), 0);
    validate_path(&problem, plan).map(|_| ()).map_err(|e| {
        let field = match &e {
            PlanError::Malformed(_) | PlanError::WrongStart { .. } => "states".to_string(),
            PlanError::InvalidStart => "states[0]".to_string(),
            PlanError::BadControl { edge, .. } | PlanError::InvalidMotion { edge } => {
                format!("controls[{edge}]")
            }
            PlanError::BadDuration { edge, .. } => format!("durations[{edge}]"),
            PlanError::ReplayMismatch { edge, .. } => format!("states[{}]", edge + 1),
            PlanError::NotInGoal { .. } => "states".to_string(),
        };
        bad(
            field,
            format!(
                "{e} (the plan is not a valid motion for leg 1 of {})",
                scenario.name
            ),
        )
    })
}

/// Checks that `plan` was made for the first leg of `scenario`: the scenario it names (by name
/// and content hash), its leg and its team, and its start within the goal tolerance of the
/// scenario's start (agents in the same order). A plan file without a `made_for` record (written
/// before plans named their scenario) is checked by its start alone. `file` names the plan.
pub fn check_origin(plan: &Plan, scenario: &Scenario, file: &str) -> Result<(), InputError> {
    let bad = |field: &str, reason: String| InputError::new(file, field, reason);
    if let Some(m) = &plan.made_for {
        let here = MadeFor::new(scenario, 1);
        if m.scenario != here.scenario || m.scenario_hash != here.scenario_hash {
            return Err(bad(
                "made_for.scenario",
                format!(
                    "the plan was made for scenario {:?} (content {}), not {:?} (content {})",
                    m.scenario, m.scenario_hash, here.scenario, here.scenario_hash
                ),
            ));
        }
        if m.leg != 1 {
            return Err(bad(
                "made_for.leg",
                format!(
                    "the plan was made for leg {}; a plan file replaces leg 1",
                    m.leg
                ),
            ));
        }
        if m.agents != here.agents {
            return Err(bad(
                "made_for.agents",
                format!(
                    "the plan is for {} agents, {} has {}",
                    m.agents, scenario.name, here.agents
                ),
            ));
        }
    }
    let tol = scenario.legs[0].goal.tolerance;
    let start = plan.start();
    if start.len() != scenario.agents() {
        return Err(bad(
            "states[0]",
            format!(
                "the plan moves {} agents, {} has {}",
                start.len(),
                scenario.name,
                scenario.agents()
            ),
        ));
    }
    for (i, (p, q)) in start.iter().zip(&scenario.start).enumerate() {
        let d = (p - q).norm();
        if d.is_nan() || d > tol {
            return Err(bad(
                &format!("states[0][{i}]"),
                format!(
                    "the plan starts agent {i} at ({}, {}), {d:.3} BL from the scenario's start ({}, {}); at most the goal tolerance {tol} BL (is it another scenario's plan, or are its agents in another order?)",
                    p.x, p.y, q.x, q.y
                ),
            ));
        }
    }
    Ok(())
}

/// The plan as JSON, stamped with the leg (1 for the first) of `scenario` it was made for.
pub fn plan_json_for(plan: &Plan, scenario: &Scenario, leg: usize) -> String {
    let mut p = plan.clone();
    p.made_for = Some(MadeFor::new(scenario, leg));
    plan_json(&p)
}

/// Parses and checks plan JSON `text` (`file` names it in errors, with the field path of
/// a malformed value; unknown keys are refused).
pub fn parse_plan(text: &str, file: &str, agents: usize) -> Result<Plan, InputError> {
    let plan: Plan = magbench_env::input::parse_json(text, file)?;
    let bad = |field: &str, reason: String| InputError::new(file, field, reason);
    if plan.states.is_empty() || plan.states.len() != plan.controls.len() + 1 {
        return Err(bad(
            "states",
            "needs one more state than there are controls".into(),
        ));
    }
    if plan.durations.len() != plan.controls.len() {
        return Err(bad("durations", "needs one duration per control".into()));
    }
    if let Some(k) = plan.states.iter().position(|s| s.len() != agents) {
        return Err(bad(
            &format!("states[{k}]"),
            format!("needs {agents} agents, has {}", plan.states[k].len()),
        ));
    }
    if let Some(k) = plan
        .durations
        .iter()
        .position(|d| !d.is_finite() || *d <= 0.0)
    {
        return Err(bad(
            &format!("durations[{k}]"),
            format!("must be a finite number > 0, got {}", plan.durations[k]),
        ));
    }
    if let Some(k) = plan.controls.iter().position(|u| !u.is_finite()) {
        return Err(bad(
            &format!("controls[{k}]"),
            "every number must be finite".into(),
        ));
    }
    if plan
        .states
        .iter()
        .flatten()
        .any(|p| !p.x.is_finite() || !p.y.is_finite())
    {
        return Err(bad("states", "every number must be finite".into()));
    }
    Ok(plan)
}

/// The plan as JSON (exact: the shortest round-trip representation of every number).
pub fn plan_json(plan: &Plan) -> String {
    serde_json::to_string(plan).expect("a plan serializes")
}

#[cfg(test)]
mod tests {
    use super::*;
    use magbench_env::{Control, Vec2};
    use magbench_planners::Problem;

    /// The frame period of a 60 fps camera.
    const F: f64 = 1.0 / 60.0;

    /// The default setup on a rig whose frames last `period` seconds.
    fn at(period: f64) -> PlanningSetup {
        PlanningSetup::default().in_frames_of(period)
    }

    /// A short valid plan on open-field, and the scenario.
    fn valid() -> (Plan, Scenario) {
        let s = Scenario::load("open-field").unwrap();
        let p = Problem::from_scenario(&s, 0, None, 0);
        let mut plan = Plan::at(&s.start);
        let mut x = s.start.clone();
        let mut out = x.clone();
        let d = 1.0 / 60.0;
        for _ in 0..5 {
            // the field at the magic angle to the pair: it turns without closing in
            let phi = (x[1] - x[0]).y.atan2((x[1] - x[0]).x);
            let u = Control::planar(phi + 0.955, 0.02, 0.01);
            assert!(p.checker.motion_valid(&p.model, &x, &u, d, &mut out));
            plan.push(u, d, out.clone());
            x.copy_from_slice(&out);
        }
        (plan, s)
    }

    #[test]
    fn plans_are_validated_like_scenarios() {
        let (plan, s) = valid();
        check_plan(&plan, &s, "p.json", &at(F)).unwrap();
        // reproducers: a 1e10 s duration, a state at x = 1e20, a huge gradient
        let mut long = plan.clone();
        long.durations[2] = 1e10;
        let e = check_plan(&long, &s, "p.json", &at(F)).unwrap_err();
        assert_eq!((e.file.as_str(), e.field.as_str()), ("p.json", "durations"));
        let mut far = plan.clone();
        far.states[3][1].x = 1e20;
        assert_eq!(
            check_plan(&far, &s, "p.json", &at(F)).unwrap_err().field,
            "states[3][1]"
        );
        let mut strong = plan.clone();
        strong.controls[1].grad[0] = 1e3;
        assert_eq!(
            check_plan(&strong, &s, "p.json", &at(F)).unwrap_err().field,
            "controls[1]"
        );
        let mut alpha = plan.clone();
        alpha.controls[0].alpha = 1e19;
        assert_eq!(
            check_plan(&alpha, &s, "p.json", &at(F)).unwrap_err().field,
            "controls[0]"
        );
        // a state the controls do not lead to
        let mut moved = plan.clone();
        moved.states[4][0].y += 0.5;
        let e = check_plan(&moved, &s, "p.json", &at(F)).unwrap_err();
        assert_eq!(e.field, "states[4]", "{e}");
        // a duration off the control period
        let mut odd = plan.clone();
        odd.durations[0] = 0.1234;
        assert_eq!(
            check_plan(&odd, &s, "p.json", &at(F)).unwrap_err().field,
            "durations[0]"
        );
        // a plan in 60 fps frames does not fit a 25 fps rig: its frames are the plan's periods
        let e = check_plan(&plan, &s, "p.json", &at(1.0 / 25.0)).unwrap_err();
        assert_eq!(e.field, "durations[0]", "{e}");
        assert!(e.reason.contains("control period 0.04 s"), "{e}");
    }

    #[test]
    fn an_elevated_plan_is_checked_for_the_rigs_medium() {
        // trio-triangle without its [medium]: the plant's medium decides
        let mut s = Scenario::load("trio-triangle").unwrap();
        let iface = s.medium.take().unwrap();
        let interface = at(F).on_plant(&iface, 90.0);
        let p = interface.problem(&s, 0, None, 0);
        let mut plan = Plan::at(&s.start);
        let mut x = s.start.clone();
        let mut out = x.clone();
        for _ in 0..5 {
            let u = Control {
                alpha: 35f64.to_radians(),
                ..Control::planar(0.4, 0.02, 0.01)
            };
            assert!(p.checker.motion_valid(&p.model, &x, &u, F, &mut out));
            plan.push(u, F, out.clone());
            x.copy_from_slice(&out);
        }
        check_plan(&plan, &s, "p.json", &interface).unwrap();
        // in bulk (the default setup's plant) nothing carries f_z: the elevation is refused
        let e = check_plan(&plan, &s, "p.json", &at(F)).unwrap_err();
        assert_eq!(e.field, "controls[0]", "{e}");
        assert!(
            e.reason.contains("does not carry the out-of-plane force"),
            "{e}"
        );
        // nor beyond the coil's range
        let flat = at(F).on_plant(&iface, 20.0);
        let e = check_plan(&plan, &s, "p.json", &flat).unwrap_err();
        assert_eq!(e.field, "controls[0]", "{e}");
        assert!(e.reason.contains("elevation within ±20°"), "{e}");
    }

    #[test]
    fn plans_of_another_scenario_or_start_are_refused() {
        let (plan, s) = valid();
        check_origin(&plan, &s, "p.json").unwrap();
        let stamped = parse_plan(&plan_json_for(&plan, &s, 1), "p.json", 2).unwrap();
        check_origin(&stamped, &s, "p.json").unwrap();
        // another scenario's
        let other = Scenario::load("trio-triangle").unwrap();
        let mut foreign = stamped.clone();
        foreign.made_for = Some(MadeFor::new(&other, 1));
        let e = check_origin(&foreign, &s, "p.json").unwrap_err();
        assert_eq!(e.field, "made_for.scenario", "{e}");
        // agents swapped
        let mut swapped = plan.clone();
        for st in &mut swapped.states {
            st.swap(0, 1);
        }
        let e = check_origin(&swapped, &s, "p.json").unwrap_err();
        assert_eq!(e.field, "states[0][0]", "{e}");
        // a zero-edge plan far from the start
        let mut far = Plan::at(&s.start);
        far.states[0][0].x += 5.0;
        far.states[0][1].x += 5.0;
        let e = check_origin(&far, &s, "p.json").unwrap_err();
        assert!(e.reason.contains("from the scenario's start"), "{e}");
    }

    #[test]
    fn round_trip_is_bit_exact() {
        // numbers whose decimal form needs all 17 digits
        let mut plan = Plan::at(&[
            Vec2::new(0.1 + 0.2, 1.0 / 3.0),
            Vec2::new(2.0f64.sqrt(), std::f64::consts::PI),
        ]);
        for k in 0..50 {
            let x = (k as f64 * 0.7368).sin() * 1e-3 + 1.0 / 7.0;
            plan.push(
                Control::planar(x * 3.1, x * 0.0123, -x * 0.0456),
                0.1 + 1.0 / 60.0,
                vec![Vec2::new(x, 1.0 - x), Vec2::new(x * 9.87, x / 3.0)],
            );
        }
        let back = parse_plan(&plan_json(&plan), "mem", 2).unwrap();
        assert_eq!(back, plan);
    }

    #[test]
    fn rejects_malformed_plans() {
        let e = parse_plan(
            "{\"states\":[],\"controls\":[],\"durations\":[]}",
            "p.json",
            2,
        )
        .unwrap_err();
        assert_eq!((e.file.as_str(), e.field.as_str()), ("p.json", "states"));
        let one = "{\"states\":[[[0,0],[2,0]]],\"controls\":[],\"durations\":[]}";
        assert!(parse_plan(one, "p.json", 2).is_ok());
        assert_eq!(parse_plan(one, "p.json", 3).unwrap_err().field, "states[0]");
        let neg = "{\"states\":[[[0,0],[2,0]],[[0,0],[2,0]]],\"controls\":[{\"theta\":0,\"alpha\":0,\"grad\":[0,0]}],\"durations\":[-1]}";
        assert_eq!(
            parse_plan(neg, "p.json", 2).unwrap_err().field,
            "durations[0]"
        );
        assert!(
            parse_plan("nope", "p.json", 2)
                .unwrap_err()
                .reason
                .contains("expected")
        );
        let e = parse_plan(
            &one.replace("\"controls\"", "\"colour\":1,\"controls\""),
            "p.json",
            2,
        )
        .unwrap_err();
        assert!(e.reason.contains("unknown field `colour`"), "{e}");
        let e = parse_plan(
            &one.replace("[[0,0],[2,0]]", "[[0,0,9],[2,0]]"),
            "p.json",
            2,
        )
        .unwrap_err();
        assert_eq!(e.field, "states[0][0]", "{e}");
    }
}
