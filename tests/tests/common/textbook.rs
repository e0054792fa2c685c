//! The textbook catalogue of rigid connections and algebraic loops (issue 12): small
//! bond graphs that SCAP cannot complete without an opt-in, each with a closed form or
//! an independent reference in the test files that use it (`rigid_connections.rs`,
//! `loops.rs`, `rigid_mechanisms.rs`), and shared with the allocation test and the
//! `implicit_eval` bench.
//!
//! Not part of `common/mod.rs`: only the binaries that need these models include this
//! file (`#[path = "common/textbook.rs"] mod textbook;`).
#![allow(dead_code)]

use bgdsl_runtime::bond_graph;

bond_graph! {
    /// Two inertias joined by a rigid gear (one degree of freedom), a damper on the
    /// output shaft, driven by a constant plus a sinusoidal torque. The output shaft's
    /// inertia takes derivative causality: ω₂ = n ω₁, so
    /// (j1 + n² j2) ω̇₁ = τ(t) − n² c ω₁.
    #[allow(derivative_causality)]
    pub model Gear {
        /// input shaft inertia, kg·m²
        param j1 = 0.2;
        /// output shaft inertia, kg·m²
        param j2 = 0.05;
        /// gear ratio ω₂/ω₁
        param n = 3.0;
        /// damping on the output shaft, N·m·s/rad
        param c = 0.1;
        /// constant torque, N·m
        param torque = 1.0;
        /// amplitude of the sinusoidal torque, N·m
        param amplitude = 0.0;
        /// angular frequency of the sinusoidal torque, rad/s
        param omega = 5.0;

        Se motor = torque + amplitude * (omega * t).sin();
        I shaft1 = j1;
        I shaft2 = j2;
        R damper = c;
        1 w1;
        1 w2;
        TF gear = n;

        motor -> w1 -> shaft1;
        w1 -> gear -> w2 -> { shaft2, damper };

        output w1_speed = w1.f;
        output w2_speed = shaft2.f;
        output shaft2_torque = shaft2.e;
        output gear_torque = gear.e2;
    }
}

bond_graph! {
    /// Two masses glued together on one 1-junction, pushed by a constant force and
    /// held by a spring: a = F/(m1 + m2) without the spring, ω = √(k/(m1 + m2)) with it.
    #[allow(derivative_causality)]
    pub model GluedMasses {
        /// first mass, kg
        param m1 = 1.0;
        /// second mass, kg
        param m2 = 3.0;
        /// stiffness, N/m
        param k = 100.0;
        /// force, N
        param force = 2.0;

        Se push = force;
        I first = m1;
        I second = m2;
        C spring = k;
        1 v;

        push -> v -> { first, second, spring };

        output x = spring.q;
        output speed = v.f;
        output second_force = second.e;
    }
}

bond_graph! {
    /// Two capacitors in parallel on one 0-junction, charged from a source through a
    /// resistor: the time constant is R (C1 + C2) with C2 = 1/k2.
    ///
    /// The second (dependent) capacitor's law is the plain parameter `k2`, its
    /// stiffness: a parameter expression there (`1.0 / c2`) does not compile yet
    /// (`tests/pending/dependent_storage_law_expression.rs`, issue 12).
    #[allow(derivative_causality)]
    pub model ParallelCapacitors {
        /// source voltage, V
        param e0 = 2.0;
        /// series resistance, Ω
        param r = 1000.0;
        /// first capacitance, F
        param c1 = 1.0e-6;
        /// second capacitance, F (its law a parameter expression, as the first's)
        param c2 = 3.0e-6;

        Se source = e0;
        R resistor = r;
        C cap1 = 1.0 / c1;
        C cap2 = 1.0 / c2;
        1 current;
        0 node;

        source -> current -> { resistor, node };
        node -> { cap1, cap2 };

        output voltage = node.e;
        output i2 = cap2.f;
    }
}

bond_graph! {
    /// A mass shaken by a velocity source v = A sin ωt: the mass has no state of its
    /// own (derivative causality), the source delivers F = m A ω cos ωt. The position is
    /// a kinematic state.
    #[allow(derivative_causality)]
    pub model ShakenMass {
        /// mass, kg
        param m = 2.0;
        /// velocity amplitude, m/s
        param a = 0.1;
        /// angular frequency, rad/s
        param omega = 10.0;

        Sf shaker = a * (omega * t).sin();
        I mass = m;
        1 v;

        shaker -> v -> mass;

        state x: f64 = 0.0 in "m";
        der x = v.f;

        output force = shaker.e;
        output mass_force = mass.e;
    }
}

bond_graph! {
    /// The mass shaken by a velocity source without the kinematic position: a model
    /// with no state at all, whose outputs still say what the source must deliver.
    #[allow(derivative_causality)]
    pub model ShakenMassAlone {
        /// mass, kg
        param m = 2.0;
        /// velocity amplitude, m/s
        param a = 0.1;
        /// angular frequency, rad/s
        param omega = 10.0;

        Sf shaker = a * (omega * t).sin();
        I mass = m;
        1 v;

        shaker -> v -> mass;

        output force = shaker.e;
    }
}

bond_graph! {
    /// A mass on a spring, held by two dampers in series (one force, velocities
    /// adding: a 0-junction): an algebraic loop, equivalent to one damper
    /// r1 r2 / (r1 + r2).
    pub model SeriesDampers {
        /// first damper, N·s/m
        param r1 = 2.0;
        /// second damper, N·s/m
        param r2 = 3.0;
        /// mass, kg
        param m = 1.0;
        /// stiffness, N/m
        param k = 10.0;

        I mass = m;
        C spring = k;
        #[allow(algebraic_loops)]
        R d1 = r1;
        R d2 = r2;
        1 v;
        0 series;

        v -> { mass, spring, series };
        series -> { d1, d2 };

        init spring.q = 0.1;

        output x = spring.q;
        output speed = v.f;
        output damper_force = series.e;
    }
}

bond_graph! {
    /// MTT's `aRC` example (`mtt/lib/examples/AlgebraicLoops/aRC`, P. Gawthrop): a
    /// source e1 in series with two resistors r_1 and r_2 on one 1-junction and a
    /// capacitor c on a 0-junction whose effort is the output e2. The two resistors
    /// in series form an algebraic loop; the reduced ODE is
    /// dq/dt = (e1 − q/c)/(r_1 + r_2).
    #[allow(algebraic_loops)]
    pub model Arc {
        /// source voltage, V
        param e1 = 1.0;
        /// first resistance, Ω
        param r_1 = 1.0;
        /// second resistance, Ω
        param r_2 = 2.0;
        /// capacitance, F
        param c = 0.1;

        Se source = e1;
        R r1 = r_1;
        R r2 = r_2;
        C cap = 1.0 / c;
        1 current;
        0 node;

        source -> current -> { r1, r2, node };
        node -> cap;

        output e2 = node.e;
        output i = current.f;
    }
}

bond_graph! {
    /// A purely resistive divider, r1 over r2 across a source: an algebraic loop and
    /// no state at all; its output is e0 r2/(r1 + r2).
    #[allow(algebraic_loops)]
    pub model Divider {
        /// source voltage, V
        param e0 = 10.0;
        /// upper resistance, Ω
        param r1 = 1000.0;
        /// lower resistance, Ω
        param r2 = 3000.0;

        Se source = e0;
        R upper = r1;
        R lower = r2;
        1 top;

        source -> top -> { upper, lower };

        output v_out = lower.e;
        output i = top.f;
    }
}

bond_graph! {
    /// A resistive divider (r1 over r2) loaded by a resistor r3 and a capacitor c in
    /// series: an algebraic loop through the divider. Seen from the load, the divider
    /// is its Thévenin equivalent e0 r2/(r1 + r2) behind r1 r2/(r1 + r2).
    #[allow(algebraic_loops)]
    pub model LoadedDivider {
        /// source voltage, V
        param e0 = 10.0;
        /// upper resistance, Ω
        param r1 = 1000.0;
        /// lower resistance, Ω
        param r2 = 3000.0;
        /// load resistance, Ω
        param r3 = 250.0;
        /// load capacitance, F
        param c = 1.0e-6;

        Se source = e0;
        R upper = r1;
        R lower = r2;
        R load_r = r3;
        C load_c = 1.0 / c;
        1 top;
        0 out;
        1 load;

        source -> top -> { upper, out };
        out -> { lower, load };
        load -> { load_r, load_c };

        output v_out = out.e;
        output v_c = load_c.e;
    }
}

bond_graph! {
    /// A source, a resistor, a diode (Shockley's law, i = Is (exp(v/Vt) − 1)) and a
    /// capacitor in series: a non-linear algebraic loop through the resistor and the
    /// diode.
    pub model DiodeRc {
        /// source voltage, V
        param e0 = 1.5;
        /// series resistance, Ω
        param r = 100.0;
        /// saturation current, A
        param i_s = 1.0e-9;
        /// thermal voltage times the ideality factor, V
        param vt = 0.05;
        /// capacitance, F
        param c = 10.0e-6;

        Se source = e0;
        #[allow(algebraic_loops)]
        R resistor = r;
        R diode { f = i_s * ((e / vt).exp() - 1.0) };
        C cap = 1.0 / c;
        1 current;

        source -> current -> { resistor, diode, cap };

        output i = current.f;
        output v_c = cap.e;
        output v_diode = diode.e;
    }
}

bond_graph! {
    /// A mass held by two dampers in series whose second law, f = e² + b e + 1, cannot
    /// be met at rest: with r1 = 1 the loop e = v − e² − b e − 1 has no real solution
    /// for v < 1 − (1 + b)²/4 (b = 0.1234567, an odd number so that no Newton iterate
    /// lands exactly where the loop's derivative vanishes), so the first evaluation
    /// must fail and say so.
    #[allow(algebraic_loops)]
    pub model ImpossibleLoop {
        /// mass, kg
        param m = 1.0;
        /// first damper, N·s/m
        param r1 = 1.0;

        I mass = m;
        R d1 = r1;
        R d2 { f = e * e + 0.1234567 * e + 1.0 };
        1 v;
        0 series;

        v -> { mass, series };
        series -> { d1, d2 };

        output force = series.e;
    }
}

bond_graph! {
    /// The unsolvable loop of [`ImpossibleLoop`] with b = 0: f = e² + 1. Newton's
    /// iterates from zero meet the point where the loop's derivative vanishes exactly
    /// (e = −1/2), which is no redundant constraint: the loop has no solution.
    #[allow(algebraic_loops)]
    pub model UnluckyLoop {
        /// mass, kg
        param m = 1.0;
        /// first damper, N·s/m
        param r1 = 1.0;

        I mass = m;
        R d1 = r1;
        R d2 { f = e * e + 1.0 };
        1 v;
        0 series;

        v -> { mass, series };
        series -> { d1, d2 };
    }
}

bond_graph! {
    /// A rigid slider-crank in the vertical plane: crank (inertia jc about its pivot,
    /// length r, angle θ from the slide's axis), connecting rod (mass mr, inertia jr
    /// about its centre, length l, centre at its middle, its weight acting), slider
    /// (mass ms) on the x-axis, a torque on the crank. One degree of freedom: the
    /// crank's momentum; θ and the slider's position are kinematic states. Every
    /// other inertia sees a velocity the crank sets through a configuration-dependent
    /// transformer whose modulus is the derivative of its coordinate by θ:
    ///
    /// - slider: x_B = r cos θ + s, s = √(l² − r² sin² θ), so x_B' = −r sin θ − r² sin θ cos θ / s;
    /// - rod centre: G = (A + B)/2 with A = r (cos θ, sin θ): G_x' = (−r sin θ + x_B')/2, G_y' = r cos θ / 2;
    /// - rod angle: sin φ = −r sin θ / l, φ' = −r cos θ / s.
    #[allow(derivative_causality)]
    pub model SliderCrank {
        /// crank length, m
        param r = 0.1;
        /// rod length, m
        param l = 0.3;
        /// crank inertia about its pivot, kg·m²
        param jc = 0.01;
        /// rod mass, kg
        param mr = 0.4;
        /// rod inertia about its centre, kg·m²
        param jr = 0.003;
        /// slider mass, kg
        param ms = 0.6;
        /// gravity, m/s²
        param g = 9.81;
        /// constant drive torque, N·m
        param tau = 0.0;
        /// amplitude of a sinusoidal drive torque, N·m
        param tau1 = 0.0;
        /// its angular frequency, rad/s
        param omega_d = 7.0;
        /// initial crank angle, rad
        param theta0 = 0.3;
        /// initial crank speed, rad/s
        param w0 = 8.0;

        Se drive = tau + tau1 * (omega_d * t).sin();
        I crank = jc;
        1 w;
        MTF rod_x = 0.5 * (-r * theta.sin()
            + (-r * theta.sin() - r * r * theta.sin() * theta.cos()
                / (l * l - r * r * theta.sin() * theta.sin()).sqrt()));
        MTF rod_y = 0.5 * r * theta.cos();
        MTF rod_turn = -r * theta.cos() / (l * l - r * r * theta.sin() * theta.sin()).sqrt();
        MTF slide = -r * theta.sin()
            - r * r * theta.sin() * theta.cos() / (l * l - r * r * theta.sin() * theta.sin()).sqrt();
        1 vgx;
        1 vgy;
        1 wr;
        1 vs;
        I rod_mx = mr;
        I rod_my = mr;
        I rod_spin = jr;
        I slider = ms;
        Se rod_weight = -mr * g;

        drive -> w -> { crank, rod_x, rod_y, rod_turn, slide };
        rod_x -> vgx -> rod_mx;
        rod_y -> vgy -> rod_my;
        rod_weight -> vgy;
        rod_turn -> wr -> rod_spin;
        slide -> vs -> slider;

        state theta: f64 = theta0 in "rad";
        der theta = w.f;
        state x_slider: f64 = r * theta0.cos() + (l * l - r * r * theta0.sin() * theta0.sin()).sqrt() in "m";
        der x_slider = vs.f;
        init crank.p = jc * w0;

        output omega = w.f;
        output slider_speed = vs.f;
        output slider_force = slider.e;
        output drive_torque = drive.e;
    }
}

bond_graph! {
    /// A rigid four-bar linkage (crank-rocker) in the vertical plane: ground O2 O4 of
    /// length d on the x-axis, crank O2 A of length a (inertia j2 about O2, angle θ),
    /// coupler A B of length b (mass m3, inertia j3 about its centre, its weight
    /// acting), rocker O4 B of length c (inertia j4 about O4, mass m4 with its centre
    /// at its middle, its weight acting). One degree of freedom, the crank's momentum;
    /// θ and the coupler and rocker angles θ3, θ4 are kinematic states. The angular
    /// velocity ratios follow from the loop closure a e^{iθ} + b e^{iθ3} − c e^{iθ4} = d:
    /// θ3' = a sin(θ4 − θ)/(b sin(θ3 − θ4)), θ4' = a sin(θ − θ3)/(c sin(θ4 − θ3)).
    #[allow(derivative_causality)]
    pub model FourBar {
        /// crank length, m
        param a = 0.1;
        /// coupler length, m
        param b = 0.35;
        /// rocker length, m
        param c = 0.3;
        /// ground length, m
        param d = 0.4;
        /// crank inertia about O2, kg·m²
        param j2 = 0.01;
        /// coupler mass, kg
        param m3 = 0.5;
        /// coupler inertia about its centre, kg·m²
        param j3 = 0.005;
        /// rocker inertia about O4, kg·m²
        param j4 = 0.015;
        /// rocker mass, kg
        param m4 = 0.4;
        /// gravity, m/s²
        param g = 9.81;
        /// constant drive torque, N·m
        param tau = 0.0;
        /// initial crank angle, rad
        param theta0 = 0.0;
        /// initial coupler angle, rad: the closed form's at theta0 = 0 (open assembly);
        /// set it with theta0 (see `four_bar_angles` in rigid_mechanisms.rs)
        param theta3_0 = 0.9479697413828937;
        /// initial rocker angle, rad: the closed form's at theta0 = 0
        param theta4_0 = 1.8959394827657874;
        /// initial crank speed, rad/s
        param w0 = 6.0;

        Se drive = tau;
        I crank = j2;
        1 w;
        MTF coupler_x = -a * theta.sin()
            - 0.5 * b * theta3.sin() * a * (theta4 - theta).sin() / (b * (theta3 - theta4).sin());
        MTF coupler_y = a * theta.cos()
            + 0.5 * b * theta3.cos() * a * (theta4 - theta).sin() / (b * (theta3 - theta4).sin());
        MTF coupler_turn = a * (theta4 - theta).sin() / (b * (theta3 - theta4).sin());
        MTF rocker_turn = a * (theta - theta3).sin() / (c * (theta4 - theta3).sin());
        1 vgx;
        1 vgy;
        1 w3;
        1 w4;
        I coupler_mx = m3;
        I coupler_my = m3;
        I coupler_spin = j3;
        I rocker = j4;
        Se coupler_weight = -m3 * g;
        MSe rocker_weight = -m4 * g * 0.5 * c * theta4.cos();

        drive -> w -> { crank, coupler_x, coupler_y, coupler_turn, rocker_turn };
        coupler_x -> vgx -> coupler_mx;
        coupler_y -> vgy -> coupler_my;
        coupler_weight -> vgy;
        coupler_turn -> w3 -> coupler_spin;
        rocker_turn -> w4 -> rocker;
        rocker_weight -> w4;

        state theta: f64 = theta0 in "rad";
        der theta = w.f;
        state theta3: f64 = theta3_0 in "rad";
        der theta3 = w3.f;
        state theta4: f64 = theta4_0 in "rad";
        der theta4 = w4.f;
        init crank.p = j2 * w0;

        output omega = w.f;
        output rocker_speed = w4.f;
        output drive_torque = drive.e;
    }
}
