//! Each term of the plant, switched on alone (with its `hardware` values), changes the plant in
//! the direction its physics says.

use std::f64::consts::FRAC_PI_2;
use std::sync::Arc;

use magbench_env::collision::CollisionWorld;
use magbench_env::model::Kinematics;
use magbench_env::plant::dynamics::{Dynamics, State};
use magbench_env::plant::{DisturbancePreset, Plant};
use magbench_env::{
    Coil, Control, LocalView, MAX_AGENTS, PhysicalParams, PlanningModel, TriaxialMaxwell, Vec2,
    Vec3, World,
};

/// The `hardware` preset with only `term` on (`None`: every term off).
fn alone(term: Option<&str>) -> DisturbancePreset {
    let mut p = DisturbancePreset::hardware();
    for t in DisturbancePreset::TERMS {
        p.set_enabled(t, Some(t) == term).unwrap();
    }
    p
}

fn world() -> World {
    World {
        width: 40.0,
        height: 30.0,
        obstacles: vec![],
    }
}

fn plant(preset: &DisturbancePreset, start: &[Vec2], seed: u64) -> Plant {
    let p = PhysicalParams::default();
    let coil: Arc<dyn Coil> = Arc::new(TriaxialMaxwell::new(p.gradient_limit()));
    let mut plant = Plant::new(
        &p,
        coil,
        Arc::new(CollisionWorld::new(&world(), 0.5)),
        preset,
        seed,
        start,
    );
    plant.set_coil_centre(Vec2::new(20.0, 15.0));
    plant
}

fn pair(r: f64, phi: f64) -> [Vec2; 2] {
    LocalView::new(20.0, 15.0, r, phi).to_pair()
}

fn separation(p: &Plant) -> f64 {
    (p.positions()[1] - p.positions()[0]).norm()
}

fn angle(b: Vec3) -> f64 {
    b.y.atan2(b.x)
}

#[test]
fn with_every_term_off_the_dynamics_are_the_planning_kinematics() {
    let p = PhysicalParams::default();
    let preset = alone(None);
    let d = Dynamics::draw(&preset, &p, 3, 1);
    let coil = TriaxialMaxwell::new(p.gradient_limit());
    // the planning model in the preset's medium (the interface: half the bulk drag)
    let k = PlanningModel::new(&p)
        .in_medium(&p, &preset.medium)
        .kinematics;
    assert_eq!(k.force_coeff, 2.0 * Kinematics::nominal(&p).force_coeff);
    let pos = [
        Vec2::new(3.0, 4.0),
        Vec2::new(5.1, 4.6),
        Vec2::new(3.7, 6.3),
    ];
    let mut s = State {
        p: [Vec2::zeros(); MAX_AGENTS],
        m: [Vec3::zeros(); MAX_AGENTS],
    };
    s.p[..3].copy_from_slice(&pos);
    for u in [
        Control::planar(0.3, 0.05, -0.02),
        Control::planar(2.2, -0.08, 0.07),
    ] {
        let mut v = [Vec2::zeros(); 3];
        k.velocities(&pos, &coil.actuation(&u), &mut v);
        let c = d.field.target(&u, 0.0);
        let r = d.rates(0.0, &c, Vec2::zeros(), &s);
        for (i, (a, b)) in r.p.iter().zip(&v).enumerate() {
            assert!((a - b).norm() < 1e-12, "agent {i}: {a} vs {b}");
        }
    }
    assert!(d.is_exact_pair());
}

#[test]
fn hydrodynamic_interaction_slows_the_relative_approach() {
    let start = pair(2.5, 0.3);
    let u = Control::planar(0.3, 0.0, 0.0); // ψ = 0: attraction along the separation
    let approach = |preset: &DisturbancePreset| {
        let mut p = plant(preset, &start, 1);
        p.run(&u, 0.1);
        assert!(!p.stuck());
        2.5 - separation(&p)
    };
    let (dry, wet) = (
        approach(&alone(None)),
        approach(&alone(Some("hydrodynamics"))),
    );
    assert!(
        wet > 0.0 && wet < 0.8 * dry,
        "approach {wet} with HI, {dry} without"
    );
}

#[test]
fn hydrodynamic_interaction_speeds_a_common_pull() {
    // a pair side by side along x pulled along x moves faster together than one agent alone
    let start = pair(1.5, 0.0);
    let g = PhysicalParams::default().gradient_limit();
    // the field along y (ψ = 90°: the pair repels) and the gradient along y: a pull across
    // the separation, where the Rotne–Prager coupling is 3a/4r + a³/2r³ ≈ 0.27
    let u = Control::planar(FRAC_PI_2, 0.0, g);
    let moved = |preset: &DisturbancePreset| {
        let mut p = plant(preset, &start, 1);
        let c0 = (p.positions()[0] + p.positions()[1]) * 0.5;
        p.run(&u, 0.05);
        ((p.positions()[0] + p.positions()[1]) * 0.5 - c0).y
    };
    let (dry, wet) = (moved(&alone(None)), moved(&alone(Some("hydrodynamics"))));
    assert!(
        dry > 0.0 && wet > 1.15 * dry,
        "pull {wet} with HI, {dry} without"
    );
}

#[test]
fn capillary_attraction_pulls_agents_together() {
    // at the magic angle the dipole force has no radial part: only capillarity closes the gap
    let magic = (1.0f64 / 3.0).sqrt().acos();
    let start = pair(4.0, 0.0);
    let end = |preset: &DisturbancePreset| {
        let mut p = plant(preset, &start, 1);
        for _ in 0..600 {
            // keep ψ at the magic angle as the pair turns
            let d = p.positions()[1] - p.positions()[0];
            p.run(
                &Control::planar(d.y.atan2(d.x) + magic, 0.0, 0.0),
                1.0 / 60.0,
            );
        }
        separation(&p)
    };
    let (dry, wet) = (end(&alone(None)), end(&alone(Some("capillary"))));
    assert!(wet < dry - 0.01, "capillary {wet}, none {dry}");
    // and only at an interface
    let mut bulk = alone(Some("capillary"));
    bulk.medium = magbench_env::plant::Medium::Bulk;
    let mut bulk_dry = alone(None);
    bulk_dry.medium = magbench_env::plant::Medium::Bulk;
    assert_eq!(end(&bulk), end(&bulk_dry));
}

#[test]
fn coil_lag_delays_the_field() {
    let start = pair(4.0, 0.0);
    let preset = alone(Some("coil_lag"));
    let mut p = plant(&preset, &start, 1);
    p.run(&Control::planar(0.0, 0.0, 0.0), 0.1);
    assert!(
        angle(p.fields().unwrap()[0]).abs() < 1e-12,
        "settled on the first command"
    );
    p.step(&Control::planar(FRAC_PI_2, 0.0, 0.0));
    let a1 = angle(p.fields().unwrap()[0]);
    assert!(a1 > 0.1 && a1 < FRAC_PI_2 - 0.1, "one step after: {a1}");
    for _ in 0..12 {
        p.step(&Control::planar(FRAC_PI_2, 0.0, 0.0));
    }
    let a2 = angle(p.fields().unwrap()[0]);
    assert!(
        a2 > a1 && (a2 - FRAC_PI_2).abs() < 0.02,
        "after 0.1 s: {a2}"
    );
    // without the term the field turns at once
    let mut q = plant(&alone(None), &start, 1);
    q.run(&Control::planar(0.0, 0.0, 0.0), 0.1);
    q.step(&Control::planar(FRAC_PI_2, 0.0, 0.0));
    assert!((angle(q.fields().unwrap()[0]) - FRAC_PI_2).abs() < 1e-12);
}

#[test]
fn magnet_lag_makes_the_moments_follow_the_field_with_its_time_constant() {
    let start = pair(4.0, 0.0);
    let p0 = PhysicalParams::default();
    let mut p = plant(&alone(Some("magnet_lag")), &start, 1);
    p.run(&Control::planar(0.0, 0.0, 0.0), 0.05);
    let m = p.moments().unwrap()[0];
    assert!((m - Vec3::x()).norm() < 1e-9, "aligned before the turn");
    // turn the field by 60°: tan(Δ/2) decays as exp(−t/τ), τ = πηd³·½/(mB) at the interface
    let turn = 60f64.to_radians();
    let tau = magbench_env::plant::rotation_time(&p0, 0.5);
    p.step(&Control::planar(turn, 0.0, 0.0));
    let h = p.dt();
    let delta = turn - angle(p.moments().unwrap()[0]);
    let expect = 2.0 * ((turn / 2.0).tan() * (-h / tau).exp()).atan();
    assert!(delta > 0.0, "the moment lags the field");
    assert!(
        (delta - expect).abs() < 1e-3,
        "Δ = {delta}, closed form {expect}"
    );
}

#[test]
fn a_coil_centre_offset_bends_the_field_angle() {
    let start = [Vec2::new(20.0, 15.0), Vec2::new(30.0, 15.0)];
    let g = PhysicalParams::default().gradient_limit();
    let u = Control::planar(FRAC_PI_2, g, 0.0);
    let mut centred = alone(Some("nonuniform_field"));
    centred.nonuniform_field.centre_offset_mm = 0.0;
    let mut p = plant(&centred, &start, 1);
    p.step(&u);
    let b = p.fields().unwrap();
    // at the coil centre the field is the command; 10 BL (5 mm) out along x, G_x adds
    // G_x·5 mm along x: the field leans toward +x (the agents moved a little in the step)
    assert!((angle(b[0]) - FRAC_PI_2).abs() < 1e-5);
    let expect = (5e-3f64).atan2(g * 5e-3);
    assert!(
        (angle(b[1]) - expect).abs() < 1e-4,
        "{} vs {expect}",
        angle(b[1])
    );
    // with the hardware offset the agent at the map centre feels a bent field too
    let mut bent = 0.0f64;
    for seed in 0..8 {
        let mut q = plant(&alone(Some("nonuniform_field")), &start, seed);
        q.step(&u);
        bent = bent.max((angle(q.fields().unwrap()[0]) - FRAC_PI_2).abs());
    }
    assert!(
        bent > 0.1f64.to_radians(),
        "largest bend at the centre {bent}"
    );
}

#[test]
fn calibration_and_ambient_field_turn_the_field() {
    let start = pair(4.0, 0.0);
    let u = Control::planar(FRAC_PI_2, 0.0, 0.0);
    let off = |term: &str| {
        (0..10)
            .map(|seed| {
                let mut p = plant(&alone(Some(term)), &start, seed);
                p.step(&u);
                (angle(p.fields().unwrap()[0]) - FRAC_PI_2).abs()
            })
            .fold(0.0f64, f64::max)
    };
    let cal = off("coil_calibration");
    assert!(
        cal > 0.2f64.to_radians() && cal < 5f64.to_radians(),
        "{cal}"
    );
    // 19 µT across 5 mT: at most 0.22°
    let amb = off("ambient_field");
    assert!(
        amb > 0.05f64.to_radians() && amb <= 0.2178f64.to_radians(),
        "{amb}"
    );
}

#[test]
fn gradient_cross_talk_pulls_across_the_commanded_axis() {
    // field along y, gradient along x only: a pure Maxwell x gradient cannot pull along y
    let start = [Vec2::new(20.0, 15.0)];
    let g = PhysicalParams::default().gradient_limit();
    let u = Control::planar(FRAC_PI_2, g, 0.0);
    let mut off_axis = 0.0f64;
    for seed in 0..6 {
        let mut p = plant(&alone(Some("coil_calibration")), &start, seed);
        p.run(&u, 1.0);
        off_axis = off_axis.max((p.positions()[0].x - 20.0).abs());
    }
    let mut q = plant(&alone(None), &start, 0);
    q.run(&u, 1.0);
    assert!((q.positions()[0].x - 20.0).abs() < 1e-12);
    assert!(
        off_axis > 1e-3,
        "cross-talk moved the agent {off_axis} BL along x"
    );
}

#[test]
fn heterogeneity_makes_the_agents_move_unequally() {
    let start = pair(2.5, 0.0);
    let u = Control::planar(FRAC_PI_2, 0.0, 0.0); // repulsion along x
    let com = |preset: &DisturbancePreset, seed: u64| {
        let mut p = plant(preset, &start, seed);
        p.run(&u, 0.5);
        ((p.positions()[0] + p.positions()[1]) * 0.5 - Vec2::new(20.0, 15.0)).norm()
    };
    assert!(
        com(&alone(None), 1) < 1e-12,
        "identical agents: the centre stays"
    );
    let moved = (0..5)
        .map(|s| com(&alone(Some("heterogeneity")), s))
        .fold(0.0, f64::max);
    assert!(moved > 1e-3, "unequal drags move the centre: {moved}");
    let f = Dynamics::draw(
        &alone(Some("heterogeneity")),
        &PhysicalParams::default(),
        2,
        3,
    );
    assert_ne!(f.factors.moment[0], f.factors.moment[1]);
    assert_ne!(f.factors.contact_angle[0], f.factors.contact_angle[1]);
}

#[test]
fn flow_carries_the_agents() {
    let start = pair(5.0, 0.0);
    let u = Control::planar((1.0f64 / 3.0).sqrt().acos(), 0.0, 0.0);
    let mut still = plant(&alone(None), &start, 2);
    let mut carried = plant(&alone(Some("flow")), &start, 2);
    for _ in 0..300 {
        still.run(&u, 1.0 / 60.0);
        carried.run(&u, 1.0 / 60.0);
    }
    let d = (carried.positions()[0] - still.positions()[0]).norm();
    // 0.02 BL/s RMS for 5 s
    assert!(d > 0.005 && d < 0.5, "carried {d} BL");
}

#[test]
fn field_jitter_and_brownian_motion_perturb_the_plant() {
    let start = pair(3.0, 0.5);
    let u = Control::planar(1.4, 0.02, 0.0);
    let end = |term: Option<&str>| {
        let mut p = plant(&alone(term), &start, 4);
        p.run(&u, 1.0);
        p.positions().to_vec()
    };
    let base = end(None);
    for t in ["field_error", "brownian"] {
        assert_ne!(end(Some(t)), base, "{t} changed nothing");
    }
}

#[test]
fn switching_one_term_leaves_the_others_draws_alone() {
    let p = PhysicalParams::default();
    let all = Dynamics::draw(&DisturbancePreset::hardware(), &p, 2, 11);
    let mut no_flow = DisturbancePreset::hardware();
    no_flow.set_enabled("flow", false).unwrap();
    let fewer = Dynamics::draw(&no_flow, &p, 2, 11);
    assert_eq!(all.factors, fewer.factors);
    assert_eq!(all.field.bias, fewer.field.bias);
}

#[test]
fn the_hardware_plant_runs_a_micro_factory_minute_without_blowing_up() {
    let start = pair(3.0, 0.4);
    let mut p = plant(&DisturbancePreset::hardware(), &start, 5);
    assert!(!p.is_exact());
    let magic = (1.0f64 / 3.0).sqrt().acos();
    for k in 0..3600 {
        let d = p.positions()[1] - p.positions()[0];
        let sign = if k % 120 < 60 { 1.0 } else { -1.0 };
        p.run(
            &Control::planar(d.y.atan2(d.x) + sign * magic, 0.02, -0.02),
            1.0 / 60.0,
        );
        if p.stuck() {
            break;
        }
    }
    for q in p.positions() {
        assert!(q.x.is_finite() && q.y.is_finite());
    }
    for m in p.moments().unwrap() {
        assert!((m.norm() - 1.0).abs() < 1e-12);
    }
}

#[test]
fn extreme_but_valid_presets_run_without_panicking() {
    use magbench_env::plant::{Camera, Medium};
    let mut p = DisturbancePreset::hardware();
    p.coil_lag.field_tau_ms = 1000.0;
    p.coil_lag.field_slew_mt_per_s = 1e-9;
    p.nonuniform_field.centre_offset_mm = 100.0;
    p.ambient_field.field_ut = 10_000.0;
    p.coil_calibration.axis_gain_error = 0.5;
    p.coil_calibration.gradient_crosstalk = 0.5;
    p.heterogeneity.moment_spread = 1.0;
    p.heterogeneity.drag_spread = 1.0;
    p.flow.rms_speed_bl_s = 100.0;
    p.flow.length_bl = 1e-6;
    if let Medium::Interface(i) = &mut p.medium {
        i.contact_angle_deg = 170.0;
        i.contact_angle_spread_deg = 30.0;
    }
    p.camera.latency.frames = 100.0;
    p.camera.latency.jitter_frames = 10.0;
    p.check().unwrap();
    for seed in 0..3 {
        let mut plant = plant(&p, &pair(3.0, 0.2), seed);
        let mut camera = Camera::new(p.camera.clone(), seed);
        for k in 0..120 {
            plant.run(&Control::planar(k as f64 * 0.3, 0.05, -0.05), 1.0 / 60.0);
            let o = camera.capture(k as f64 / 60.0, plant.positions()).unwrap();
            assert_eq!(o.agents.len(), 2);
        }
        assert!(plant.stuck() || plant.positions().iter().all(|q| q.x.is_finite()));
    }
}

#[test]
fn at_an_interface_the_plant_and_the_planning_model_share_the_half_drag() {
    // the ideal preset's terms in the hardware medium: the plant follows the planning model
    // of that medium, at twice the bulk speed
    let p = PhysicalParams::default();
    let interface = DisturbancePreset::hardware().medium;
    let mut wet = DisturbancePreset::ideal();
    wet.medium = interface.clone();
    // the field across the pair: it pushes the agents apart (they never touch)
    let start = pair(2.5, 0.4);
    let u = Control::planar(0.4 + FRAC_PI_2, 0.02, -0.01);
    let mut plant_wet = plant(&wet, &start, 3);
    plant_wet.run(&u, 0.5);
    let model = PlanningModel::new(&p).in_medium(&p, &interface);
    let mut expect = [Vec2::zeros(); 2];
    model.propagate(&start, &u, 0.5, &mut expect);
    for (a, b) in plant_wet.positions().iter().zip(&expect) {
        assert!((a - b).norm() < 1e-12, "plant {a} vs model {b}");
    }
    let mut plant_dry = plant(&DisturbancePreset::ideal(), &start, 3);
    plant_dry.run(&u, 1.0);
    for (a, b) in plant_wet.positions().iter().zip(plant_dry.positions()) {
        assert!(
            (a - b).norm() < 1e-9,
            "interface at 0.5 s {a} vs bulk at 1 s {b}"
        );
    }
}

#[test]
fn the_contact_line_keeps_a_pinned_magnet_in_the_plane() {
    // hardware: pinning torque 2.2 nN·m > mB = 2.1 nN·m, so a tilted field does not tilt it
    let start = pair(4.0, 0.0);
    let tilted = Control {
        theta: 0.3,
        alpha: 0.5,
        grad: [0.0, 0.0],
    };
    let elevation = |preset: &DisturbancePreset| {
        let mut q = plant(preset, &start, 1);
        q.run(&Control::planar(0.3, 0.0, 0.0), 0.05);
        q.run(&tilted, 0.2);
        let m = q.moments().unwrap()[0];
        m.z.atan2(m.x.hypot(m.y))
    };
    let pinned = alone(Some("magnet_lag"));
    assert!(elevation(&pinned).abs() < 1e-9, "{}", elevation(&pinned));
    let mut free = pinned.clone();
    if let magbench_env::plant::Medium::Interface(i) = &mut free.medium {
        i.contact_angle_hysteresis_deg = 0.0;
    }
    assert!(
        (elevation(&free) - 0.5).abs() < 1e-6,
        "{}",
        elevation(&free)
    );
}
