//! The splitter: a multibond joined to its scalar components, whose components take
//! different causalities. The anchor of a spring-damper is driven along x (a flow
//! source), held along y (a flow source) and pushed along z by a constant force (an
//! effort source), and the damper is three scalar dampers: along x and y the damper
//! computes its force from the stretch rate, along z (the anchor is massless and
//! pushed) it computes the stretch rate from the force. No single stroke per multibond
//! describes that; the model compiles and its equations are checked against ones
//! written by hand from the physics. The same mass driven through a transformer
//! (`Levered`) or a gyrator (`Gyrated`) with a scalar modulus checks the two-ports
//! taken apart by component, each component taking its own causality through them.

mod common;
use common::seeded_states;

use bgdsl_runtime::{bond_graph, Model, PowerBalance};

bond_graph! {
    /// A point mass on a spring-damper whose anchor moves on three different terms.
    ///
    /// ```text
    /// Sf drive ⇀ guide.0 │
    /// Sf hold  ⇀ guide.1 │ guide ⇀ 1 anchor ⇀ 0 force ⇀ 1 v ⇀ I[3] mass
    /// Se push  ⇀ guide.2 │                      force ⇀ 1 stretch ⇀ C[3] spring
    ///                                                    stretch ⇀ dampers ⇀ { R dx, R dy, R dz }
    /// ```
    pub model Anchored {
        param m = 2.0 in "kg";
        param k = 50.0 in "N/m";
        param c = 3.0 in "N·s/m";
        param cz = 4.0 in "N·s/m";
        param vx = 0.3 in "m/s";
        param push = 1.5 in "N";

        I[3] mass = m;
        C[3] spring = k;
        1 v;
        1 anchor;
        0 force;
        1 stretch;
        Split[3] guide;
        Split[3] dampers;
        Sf drive = vx;
        Sf hold = 0.0;
        Se pushed = push;
        R dx = c;
        R dy = c;
        R dz = cz;

        drive -> guide.0;
        hold -> guide.1;
        pushed -> guide.2;
        guide -> anchor -> force -> v -> mass;
        force -> stretch -> spring;
        stretch -> dampers;
        dampers.0 -> dx;
        dampers.1 -> dy;
        dampers.2 -> dz;

        output anchor_velocity: Vector3 = anchor.f;
        output spring_force: Vector3 = spring.e;
    }
}

/// The same system by hand. The anchor is massless, so along z the push balances the
/// spring-damper: `push = k q_z + c_z (v_az − v_mz)`, which gives the anchor's speed.
fn hand_derivatives(p: &AnchoredParams, x: &[f64; 6]) -> [f64; 6] {
    let (momentum, stretch) = (&x[0..3], &x[3..6]);
    let v_mass: Vec<f64> = momentum.iter().map(|p_i| p_i / p.m).collect();
    let v_anchor = [p.vx, 0.0, v_mass[2] + (p.push - p.k * stretch[2]) / p.cz];
    let damping = [p.c, p.c, p.cz];
    let mut dx = [0.0; 6];
    for i in 0..3 {
        let rate = v_anchor[i] - v_mass[i];
        dx[i] = p.k * stretch[i] + damping[i] * rate;
        dx[3 + i] = rate;
    }
    dx
}

#[test]
fn mixed_causality_across_components_gives_the_hand_written_equations() {
    let model = Anchored::default();
    assert_eq!(
        Anchored::STATE_NAMES,
        [
            "mass.p_x",
            "mass.p_y",
            "mass.p_z",
            "spring.q_x",
            "spring.q_y",
            "spring.q_z"
        ]
    );
    for x in seeded_states::<6>(0x5eed_cafe, 100) {
        let mut dx = [0.0; 6];
        model.derivatives(0.0, &x, &mut dx);
        let expected = hand_derivatives(&model.params, &x);
        for i in 0..6 {
            let scale = expected[i].abs().max(1.0);
            assert!(
                (dx[i] - expected[i]).abs() <= 1e-14 * scale,
                "component {i} at {x:?}: generated {} vs hand {}",
                dx[i],
                expected[i]
            );
        }
    }
}

#[test]
fn the_anchor_moves_as_each_axis_dictates() {
    let model = Anchored::default();
    let x = [0.2, -0.4, 0.6, 0.01, 0.02, 0.03];
    let mut y = [0.0; 6];
    model.outputs(0.0, &x, &mut y);
    let p = &model.params;
    // x: driven, y: held, z: whatever the push and the spring-damper leave.
    let v_az = x[2] / p.m + (p.push - p.k * x[5]) / p.cz;
    assert_eq!(y[0], p.vx);
    assert_eq!(y[1], 0.0);
    assert!((y[2] - v_az).abs() < 1e-15, "{} vs {v_az}", y[2]);
    // Along z the spring-damper's force is the push.
    let force_z = p.k * x[5] + p.cz * (v_az - x[2] / p.m);
    assert!((force_z - p.push).abs() < 1e-12);
    assert_eq!(&y[3..6], &[p.k * x[3], p.k * x[4], p.k * x[5]]);
}

#[test]
fn the_splitter_conserves_power() {
    // d(stored)/dt = input − dissipated at any state: the splitter neither stores nor
    // loses anything, whichever way each component's effort goes.
    let model = Anchored::default();
    for x in seeded_states::<6>(0x5eed_cafe, 50) {
        let Some(PowerBalance {
            input, dissipated, ..
        }) = model.power_balance(0.0, &x)
        else {
            panic!("generated models give their power balance");
        };
        let mut dx = [0.0; 6];
        model.derivatives(0.0, &x, &mut dx);
        // Stored energy: |p|² / 2m + k |q|² / 2, so its rate is v·dp/dt + k q·dq/dt.
        let rate: f64 = (0..3)
            .map(|i| x[i] / model.params.m * dx[i] + model.params.k * x[3 + i] * dx[3 + i])
            .sum();
        let scale = input.abs().max(dissipated.abs()).max(1.0);
        assert!(
            (rate - (input - dissipated)).abs() <= 1e-12 * scale,
            "at {x:?}: dE/dt = {rate}, input − dissipated = {}",
            input - dissipated
        );
    }
}

#[test]
fn the_causal_graph_shows_the_components_and_the_inserted_splitters() {
    let graph = Anchored::GRAPH;
    let connected = |index: usize| graph.bonds.iter().any(|b| b.from == index || b.to == index);
    let names: Vec<String> = graph
        .elements
        .iter()
        .enumerate()
        .filter(|&(i, e)| e.kind == bgdsl_runtime::ElementKind::Split && connected(i))
        .map(|(_, e)| format!("{}.{}", e.group, e.name))
        .collect();
    // The written splitters are taken apart (their components are 0-junctions); one
    // splitter goes in front of each whole-vector element the split junctions meet.
    assert_eq!(names, ["v.split6", "stretch.split8"]);
    let anchor_parts = graph
        .elements
        .iter()
        .filter(|e| e.group == "anchor" && e.kind == bgdsl_runtime::ElementKind::One)
        .count();
    assert_eq!(anchor_parts, 3);
    // The anchor's components disagree: along x and y the guide brings flow in (its
    // stroke is at the junction's far end), along z it brings effort.
    let stroke_into_anchor: Vec<bool> = (0..3)
        .map(|i| {
            let part = graph
                .elements
                .iter()
                .position(|e| e.group == "anchor" && e.name == i.to_string())
                .expect("the anchor's component");
            let guide_part = graph
                .elements
                .iter()
                .position(|e| e.group == "guide" && e.name == i.to_string())
                .expect("the guide's component");
            let bond = graph
                .bonds
                .iter()
                .find(|b| b.from == guide_part && b.to == part)
                .expect("the bond from the guide's component to the anchor's");
            bond.stroke_at == part
        })
        .collect();
    assert_eq!(stroke_into_anchor, [false, false, true]);
}

bond_graph! {
    /// The anchored mass of [`Anchored`] driven through a lever: a 3-D transformer with
    /// a scalar ratio between the guide and the anchor. Along x the lever passes on the
    /// guide's flow (it computes its port 2 flow), along z the guide's push (it computes
    /// its port 2 effort from the effort on port 1): a scalar TF on a multibond is taken
    /// apart by component, so its components take these different causalities.
    pub model Levered {
        param m = 2.0 in "kg";
        param k = 50.0 in "N/m";
        param c = 3.0 in "N·s/m";
        param cz = 4.0 in "N·s/m";
        param vx = 0.3 in "m/s";
        param push = 1.5 in "N";
        param ratio = 2.5;

        I[3] mass = m;
        C[3] spring = k;
        TF lever = ratio;
        1 v;
        1 anchor;
        0 force;
        1 stretch;
        Split[3] guide;
        Split[3] dampers;
        Sf drive = vx;
        Sf hold = 0.0;
        Se pushed = push;
        R dx = c;
        R dy = c;
        R dz = cz;

        drive -> guide.0;
        hold -> guide.1;
        pushed -> guide.2;
        guide -> lever -> anchor -> force -> v -> mass;
        force -> stretch -> spring;
        stretch -> dampers;
        dampers.0 -> dx;
        dampers.1 -> dy;
        dampers.2 -> dz;

        output anchor_velocity: Vector3 = anchor.f;
        output lever_effort_in: Vector3 = lever.e1;
        output lever_flow_out: Vector3 = lever.f2;
    }
}

/// The levered system by hand: a TF of ratio n has `f2 = n f1` and `e1 = n e2`, so the
/// anchor moves at n vx along x, and along z it is pushed with push / n.
fn levered_by_hand(p: &LeveredParams, x: &[f64; 6]) -> ([f64; 6], [f64; 3]) {
    let (momentum, stretch) = (&x[0..3], &x[3..6]);
    let v_mass: Vec<f64> = momentum.iter().map(|p_i| p_i / p.m).collect();
    let force_z = p.push / p.ratio;
    let v_anchor = [
        p.ratio * p.vx,
        0.0,
        v_mass[2] + (force_z - p.k * stretch[2]) / p.cz,
    ];
    let damping = [p.c, p.c, p.cz];
    let mut dx = [0.0; 6];
    for i in 0..3 {
        let rate = v_anchor[i] - v_mass[i];
        dx[i] = p.k * stretch[i] + damping[i] * rate;
        dx[3 + i] = rate;
    }
    (dx, v_anchor)
}

#[test]
fn a_scalar_transformer_on_a_multibond_takes_causality_by_component() {
    let model = Levered::default();
    let p = &model.params;
    for x in seeded_states::<6>(0x5eed_cafe, 100) {
        let mut dx = [0.0; 6];
        model.derivatives(0.0, &x, &mut dx);
        let (expected, v_anchor) = levered_by_hand(p, &x);
        for i in 0..6 {
            assert!(
                (dx[i] - expected[i]).abs() <= 1e-13 * expected[i].abs().max(1.0),
                "component {i} at {x:?}: generated {} vs hand {}",
                dx[i],
                expected[i]
            );
        }
        let mut y = [0.0; 9];
        model.outputs(0.0, &x, &mut y);
        for i in 0..3 {
            assert!((y[i] - v_anchor[i]).abs() <= 1e-13, "anchor {i}: {y:?}");
            // The lever's port 2 flow is the anchor's; its port 1 effort is n times
            // the force it passes on (push along z).
            assert!((y[6 + i] - v_anchor[i]).abs() <= 1e-13, "f2 {i}: {y:?}");
        }
        assert!((y[5] - p.push).abs() <= 1e-12, "e1_z = push: {y:?}");
        // Along x and y the force on the anchor is the spring-damper's.
        let force_x = p.k * x[3] + p.c * (v_anchor[0] - x[0] / p.m);
        assert!((y[3] - p.ratio * force_x).abs() <= 1e-12 * force_x.abs().max(1.0));
    }
    // Power: the lever neither stores nor loses anything.
    for x in seeded_states::<6>(0x5eed_cafe, 20) {
        let balance = model.power_balance(0.0, &x).expect("an account");
        let mut dx = [0.0; 6];
        model.derivatives(0.0, &x, &mut dx);
        let rate: f64 = (0..3)
            .map(|i| x[i] / p.m * dx[i] + p.k * x[3 + i] * dx[3 + i])
            .sum();
        let scale = balance.input.abs().max(balance.dissipated.abs()).max(1.0);
        assert!((rate - (balance.input - balance.dissipated)).abs() <= 1e-12 * scale);
    }
}

bond_graph! {
    /// The anchored mass of [`Anchored`] driven through a gyrator of modulus r: a 3-D
    /// GY with a scalar modulus between the guide and the anchor, taken apart by
    /// component. A gyrator swaps effort and flow, so along x an effort source moves
    /// the anchor at `f2 = e1 / r` (the GY runs backwards: it receives both efforts),
    /// along y a zero effort holds it, and along z a flow source pushes it with
    /// `e2 = r f1` (the GY runs forwards: it receives both flows).
    pub model Gyrated {
        param m = 2.0 in "kg";
        param k = 50.0 in "N/m";
        param c = 3.0 in "N·s/m";
        param cz = 4.0 in "N·s/m";
        /// the effort set along x, which the gyrator turns into the speed ex / r
        param ex = 0.6;
        /// the flow set along z, which the gyrator turns into the push r wz
        param wz = 0.5;
        /// the gyrator's modulus, e2 = r f1
        param r = 0.8;

        I[3] mass = m;
        C[3] spring = k;
        GY gyro = r;
        1 v;
        1 anchor;
        0 force;
        1 stretch;
        Split[3] guide;
        Split[3] dampers;
        Se drive = ex;
        Se hold = 0.0;
        Sf pushed = wz;
        R dx = c;
        R dy = c;
        R dz = cz;

        drive -> guide.0;
        hold -> guide.1;
        pushed -> guide.2;
        guide -> gyro -> anchor -> force -> v -> mass;
        force -> stretch -> spring;
        stretch -> dampers;
        dampers.0 -> dx;
        dampers.1 -> dy;
        dampers.2 -> dz;

        output anchor_velocity: Vector3 = anchor.f;
        output gyro_e1: Vector3 = gyro.e1;
        output gyro_f1: Vector3 = gyro.f1;
        output gyro_e2: Vector3 = gyro.e2;
    }
}

/// The gyrated system by hand: a GY of modulus r has `e2 = r f1` and `e1 = r f2`.
/// Along x and y the anchor moves at e1 / r and the force the spring-damper puts on
/// it comes back as f1 = e2 / r; along z it is pushed with r wz and e1 = r f2.
/// Returns the derivatives, the anchor's velocity and the GY's e1, f1 and e2.
fn gyrated_by_hand(p: &GyratedParams, x: &[f64; 6]) -> ([f64; 6], [f64; 3], [[f64; 3]; 3]) {
    let (momentum, stretch) = (&x[0..3], &x[3..6]);
    let v_mass: Vec<f64> = momentum.iter().map(|p_i| p_i / p.m).collect();
    let force_z = p.r * p.wz;
    let v_anchor = [
        p.ex / p.r,
        0.0,
        v_mass[2] + (force_z - p.k * stretch[2]) / p.cz,
    ];
    let damping = [p.c, p.c, p.cz];
    let mut dx = [0.0; 6];
    let mut port = [[0.0; 3]; 3];
    for i in 0..3 {
        let rate = v_anchor[i] - v_mass[i];
        // The force on the anchor: the spring-damper's (the push along z).
        let e2 = p.k * stretch[i] + damping[i] * rate;
        dx[i] = e2;
        dx[3 + i] = rate;
        port[0][i] = p.r * v_anchor[i];
        port[1][i] = e2 / p.r;
        port[2][i] = e2;
    }
    (dx, v_anchor, port)
}

#[test]
fn a_scalar_gyrator_on_a_multibond_takes_causality_by_component() {
    let model = Gyrated::default();
    let p = &model.params;
    assert_eq!(Gyrated::STATE_NAMES, Anchored::STATE_NAMES);
    let close = |generated: f64, hand: f64| (generated - hand).abs() <= 1e-12 * hand.abs().max(1.0);
    for x in seeded_states::<6>(0x5eed_cafe, 100) {
        let mut dx = [0.0; 6];
        model.derivatives(0.0, &x, &mut dx);
        let (expected, v_anchor, port) = gyrated_by_hand(p, &x);
        for i in 0..6 {
            assert!(
                close(dx[i], expected[i]),
                "component {i} at {x:?}: generated {} vs hand {}",
                dx[i],
                expected[i]
            );
        }
        let mut y = [0.0; 12];
        model.outputs(0.0, &x, &mut y);
        for i in 0..3 {
            assert!(close(y[i], v_anchor[i]), "anchor {i}: {y:?}");
            for (signal, values) in port.iter().enumerate() {
                assert!(
                    close(y[3 * (signal + 1) + i], values[i]),
                    "port signal {signal}, component {i}: {y:?} vs {port:?}"
                );
            }
        }
        // What each source sets: e1 along x and y, f1 along z.
        assert_eq!([y[3], y[4]], [p.ex, 0.0]);
        assert_eq!(y[8], p.wz);
        // Along z the push is r wz.
        assert!(close(y[11], p.r * p.wz), "{y:?}");
    }
    // Power: the gyrator neither stores nor loses anything, and the sources supply
    // ex f1_x (along x) and wz e1_z (along z).
    for x in seeded_states::<6>(0x5eed_cafe, 20) {
        let balance = model.power_balance(0.0, &x).expect("an account");
        let (_, v_anchor, port) = gyrated_by_hand(p, &x);
        let supplied = p.ex * port[1][0] + p.wz * port[0][2];
        assert!(
            close(balance.input, supplied),
            "{} vs {supplied}",
            balance.input
        );
        let mut dx = [0.0; 6];
        model.derivatives(0.0, &x, &mut dx);
        let rate: f64 = (0..3)
            .map(|i| x[i] / p.m * dx[i] + p.k * x[3 + i] * dx[3 + i])
            .sum();
        let dissipated: f64 = [p.c, p.c, p.cz]
            .iter()
            .enumerate()
            .map(|(i, damping)| damping * (v_anchor[i] - x[i] / p.m).powi(2))
            .sum();
        assert!(
            close(balance.dissipated, dissipated),
            "{} vs {dissipated}",
            balance.dissipated
        );
        let scale = balance.input.abs().max(balance.dissipated.abs()).max(1.0);
        assert!((rate - (balance.input - balance.dissipated)).abs() <= 1e-12 * scale);
    }
}

#[test]
fn the_gyrators_components_take_their_strokes_from_their_sources() {
    let graph = Gyrated::GRAPH;
    let find = |group: &str, name: String| {
        graph
            .elements
            .iter()
            .position(|e| e.group == group && e.name == name)
            .unwrap_or_else(|| panic!("component {group}.{name}"))
    };
    // A GY receives both efforts or both flows: along x and y (effort sources) the
    // stroke is at the gyrator's component on both its bonds, along z at neither.
    let strokes: Vec<[bool; 2]> = (0..3)
        .map(|i| {
            let part = find("gyro", i.to_string());
            let (guide, anchor) = (find("guide", i.to_string()), find("anchor", i.to_string()));
            let stroke = |from: usize, to: usize| {
                graph
                    .bonds
                    .iter()
                    .find(|b| b.from == from && b.to == to)
                    .expect("a component's bond")
                    .stroke_at
                    == part
            };
            [stroke(guide, part), stroke(part, anchor)]
        })
        .collect();
    assert_eq!(strokes, [[true, true], [true, true], [false, false]]);
}
