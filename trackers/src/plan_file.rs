//! Plan files: a [`Plan`] as JSON, read back bit for bit.
//!
//! The pair dynamics amplify a one-ulp difference in a control or a start into BL at the end of
//! a long plan, so a plan read from a file must be the plan that was written. serde_json writes
//! the shortest exact representation of every f64; this crate enables its `float_roundtrip`
//! feature so that reading it back is exact too (without it, parsing can be off by one ulp).

use std::path::Path;

use magbench_env::InputError;
use magbench_planners::Plan;

/// Reads and checks a plan file for a team of `agents`.
pub fn read_plan(path: &Path, agents: usize) -> Result<Plan, InputError> {
    let file = path.display().to_string();
    let text = magbench_env::input::read_text(path, &file)?;
    parse_plan(&text, &file, agents)
}

/// Parses and checks plan JSON `text` (`file` names it in errors).
pub fn parse_plan(text: &str, file: &str, agents: usize) -> Result<Plan, InputError> {
    let plan: Plan = serde_json::from_str(text)
        .map_err(|e| InputError::new(file, "", format!("not a plan: {e}")))?;
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
                .contains("not a plan")
        );
    }
}
