//! The sign convention of sources: an Se sets its bond's effort and an Sf its bond's
//! flow, both counted in the half arrow's direction, whichever way the arrow points
//! (the textbooks' and 20-sim's convention). A bond pointing into a source makes it a
//! sink: it absorbs `e·f`. Each model below drives the same system twice, once with
//! the bond leaving the source and once with it entering, and its equations, its
//! outputs and its power balance are checked against ones written by hand.

mod common;
use common::{assert_close, seeded_states};

use bgdsl_runtime::{bond_graph, Model, PowerBalance};

bond_graph! {
    /// Two damped masses pushed by the same force: mass `a` by a source whose bond
    /// leaves it, mass `b` by one whose bond enters it (so the force acts against
    /// `b`'s velocity, the arrow's direction).
    pub model EffortSources {
        param m = 2.0 in "kg";
        param c = 0.5 in "N·s/m";
        param force = 3.0 in "N";

        Se out_a = force;
        Se in_b = force;
        I ma = m;
        I mb = m;
        R da = c;
        R db = c;
        1 va;
        1 vb;

        out_a -> va -> { ma, da };
        vb -> in_b;
        vb -> { mb, db };

        output e_a = out_a.e;
        output f_a = out_a.f;
        output e_b = in_b.e;
        output f_b = in_b.f;
    }
}

bond_graph! {
    /// Two masses on springs whose far ends are moved at the same speed: through
    /// spring `a` by a source whose bond leaves it, through spring `b` by one whose
    /// bond enters it (so the flow runs from the junction into the source).
    pub model FlowSources {
        param m = 2.0 in "kg";
        param k = 40.0 in "N/m";
        param speed = 0.7 in "m/s";

        Sf out_a = speed;
        Sf in_b = speed;
        C ka = k;
        C kb = k;
        I ma = m;
        I mb = m;
        0 sa;
        0 sb;
        1 wa;
        1 wb;

        out_a -> sa;
        sa -> ka;
        sa -> wa -> ma;
        sb -> in_b;
        sb -> kb;
        sb -> wb -> mb;

        output e_a = out_a.e;
        output f_a = out_a.f;
        output e_b = in_b.e;
        output f_b = in_b.f;
    }
}

bond_graph! {
    /// The modulated sources follow the same convention: a force and a speed that
    /// grow with time, each on a bond entering its source.
    pub model ModulatedSources {
        param m = 2.0 in "kg";
        param k = 40.0 in "N/m";
        param rate = 1.5;

        MSe push = rate * t;
        MSf drive = rate * t;
        I m1 = m;
        I m2 = m;
        C spring = k;
        1 v1;
        0 s;
        1 v2;

        v1 -> push;
        v1 -> m1;
        s -> drive;
        s -> spring;
        s -> v2 -> m2;

        output f_push = push.f;
        output f_drive = drive.f;
    }
}

bond_graph! {
    /// Three-dimensional sources on bonds entering them: a force on a free mass, and a
    /// velocity moving the far end of a spring holding a second mass.
    pub model VectorSources {
        param m = 2.0 in "kg";
        param k = 40.0 in "N/m";
        param fx = 1.0 in "N";
        param fy = -2.0 in "N";
        param fz = 0.5 in "N";
        param vx = 0.3 in "m/s";
        param vy = -0.1 in "m/s";
        param vz = 0.2 in "m/s";

        Se[3] push = vec3(fx, fy, fz);
        Sf[3] drive = vec3(vx, vy, vz);
        I[3] m1 = m;
        I[3] m2 = m;
        C[3] spring = k;
        1 v1;
        0 s;
        1 v2;

        v1 -> push;
        v1 -> m1;
        s -> drive;
        s -> spring;
        s -> v2 -> m2;

        output f_drive: Vector3 = drive.f;
    }
}

bond_graph! {
    /// A spring's far end moved along each axis by a scalar flow source on a component
    /// of a splitter: along x and z the bond enters the source, along y it leaves it.
    pub model SplitFlowSources {
        param m = 2.0 in "kg";
        param k = 40.0 in "N/m";
        param vx = 0.3 in "m/s";
        param vy = -0.1 in "m/s";
        param vz = 0.2 in "m/s";

        Split[3] guide;
        Sf dx = vx;
        Sf dy = vy;
        Sf dz = vz;
        C[3] spring = k;
        I[3] mass = m;
        0 s;
        1 v;

        guide.0 -> dx;
        dy -> guide.1;
        guide.2 -> dz;
        guide -> s;
        s -> spring;
        s -> v -> mass;

        output fx = dx.f;
        output fy = dy.f;
        output fz = dz.f;
    }
}

use bgdsl_runtime::multibond::vec3;

/// The derivatives at `x` and time `t`.
fn derivatives<M: Model>(model: &M, t: f64, x: &[f64]) -> Vec<f64> {
    let mut dx = vec![0.0; M::N_STATES];
    model.derivatives(t, x, &mut dx);
    dx
}

/// The outputs at `x` and time `t`.
fn outputs<M: Model>(model: &M, t: f64, x: &[f64]) -> Vec<f64> {
    let mut y = vec![0.0; M::N_OUTPUTS];
    model.outputs(t, x, &mut y);
    y
}

fn balance<M: Model>(model: &M, t: f64, x: &[f64]) -> PowerBalance<f64> {
    model
        .power_balance(t, x)
        .expect("generated models keep an energy account")
}

#[test]
fn an_effort_source_pushes_along_its_half_arrow_either_way() {
    let model = EffortSources::default();
    let p = &model.params;
    assert_eq!(EffortSources::STATE_NAMES, ["ma.p", "mb.p"]);
    for x in seeded_states::<2>(0x5eed_50ce, 50) {
        let (va, vb) = (x[0] / p.m, x[1] / p.m);
        // a: the force pushes along va. b: the bond vb -> in_b takes the force out of
        // the junction, so it acts against vb: a 1-junction with all its bonds
        // pointing out has e_b + e_mb + e_db = 0.
        let hand = [p.force - p.c * va, -p.force - p.c * vb];
        assert_close(&derivatives(&model, 0.0, &x), &hand, "dp/dt");
        // e and f of a source are its bond's: the effort it sets and the flow along
        // the half arrow (for b, the junction's flow, as the arrow leaves it).
        let hand = [p.force, va, p.force, vb];
        assert_close(&outputs(&model, 0.0, &x), &hand, "outputs");
        // Supplied power: F·va by a; b absorbs F·vb.
        let account = balance(&model, 0.0, &x);
        let supplied = p.force * va - p.force * vb;
        assert_close(&[account.input], &[supplied], "input power");
        assert_close(
            &[account.dissipated],
            &[p.c * (va * va + vb * vb)],
            "dissipated power",
        );
    }
}

#[test]
fn a_flow_source_moves_along_its_half_arrow_either_way() {
    let model = FlowSources::default();
    let p = &model.params;
    assert_eq!(FlowSources::STATE_NAMES, ["ka.q", "kb.q", "ma.p", "mb.p"]);
    for x in seeded_states::<4>(0x5eed_50ce, 50) {
        let [qa, qb, pa, pb] = x;
        let (va, vb) = (pa / p.m, pb / p.m);
        // a: the source's flow enters sa, so the spring stretches at speed − va.
        // b: the bond sb -> in_b carries the speed out of sb (all of sb's bonds point
        // out: f_in_b + f_kb + f_wb = 0), so the spring stretches at −speed − vb.
        let hand = [p.speed - va, -p.speed - vb, p.k * qa, p.k * qb];
        assert_close(&derivatives(&model, 0.0, &x), &hand, "derivatives");
        // An Sf's f is its value whichever way its bond points.
        let hand = [p.k * qa, p.speed, p.k * qb, p.speed];
        assert_close(&outputs(&model, 0.0, &x), &hand, "outputs");
        // a supplies k qa · speed; b absorbs k qb · speed.
        let account = balance(&model, 0.0, &x);
        let supplied = p.k * qa * p.speed - p.k * qb * p.speed;
        assert_close(&[account.input], &[supplied], "input power");
        // And the account closes: dE/dt = input (nothing dissipates).
        let dx = derivatives(&model, 0.0, &x);
        let rate = p.k * qa * dx[0] + p.k * qb * dx[1] + va * dx[2] + vb * dx[3];
        assert_close(&[rate], &[account.input], "dE/dt");
    }
}

#[test]
fn modulated_sources_follow_the_same_convention() {
    let model = ModulatedSources::default();
    let p = &model.params;
    assert_eq!(ModulatedSources::STATE_NAMES, ["m1.p", "m2.p", "spring.q"]);
    let t = 0.8;
    let value = p.rate * t;
    for x in seeded_states::<3>(0x5eed_50ce, 20) {
        let [p1, p2, q] = x;
        let hand = [-value, p.k * q, -value - p2 / p.m];
        assert_close(&derivatives(&model, t, &x), &hand, "derivatives");
        assert_close(&outputs(&model, t, &x), &[p1 / p.m, value], "outputs");
        let supplied = -value * p1 / p.m - p.k * q * value;
        assert_close(&[balance(&model, t, &x).input], &[supplied], "input power");
    }
}

#[test]
fn vector_sources_on_bonds_entering_them_act_against_the_arrow() {
    let model = VectorSources::default();
    let p = &model.params;
    let force = vec3(p.fx, p.fy, p.fz);
    let speed = vec3(p.vx, p.vy, p.vz);
    for x in seeded_states::<9>(0x5eed_50ce, 20) {
        // States: m1.p, m2.p, spring.q (declaration order of the storage elements).
        let p1 = vec3(x[0], x[1], x[2]);
        let p2 = vec3(x[3], x[4], x[5]);
        let q = vec3(x[6], x[7], x[8]);
        let dp1 = -force;
        let dp2 = p.k * q;
        let dq = -speed - p2 / p.m;
        let hand: Vec<f64> = dp1
            .iter()
            .chain(dp2.iter())
            .chain(dq.iter())
            .copied()
            .collect();
        assert_close(&derivatives(&model, 0.0, &x), &hand, "derivatives");
        assert_close(&outputs(&model, 0.0, &x), speed.as_slice(), "drive.f");
        let supplied = -force.dot(&(p1 / p.m)) - (p.k * q).dot(&speed);
        assert_close(
            &[balance(&model, 0.0, &x).input],
            &[supplied],
            "input power",
        );
    }
}

#[test]
fn scalar_flow_sources_behind_a_splitter_follow_their_own_arrows() {
    let model = SplitFlowSources::default();
    let p = &model.params;
    for x in seeded_states::<6>(0x5eed_50ce, 20) {
        // States: spring.q, mass.p.
        let q = vec3(x[0], x[1], x[2]);
        let momentum = vec3(x[3], x[4], x[5]);
        // Along x and z the bond enters the source (guide.0 -> dx): the guide's
        // component, a 0-junction, passes minus the source's flow on to `s`.
        let into_s = vec3(-p.vx, p.vy, -p.vz);
        let dq = into_s - momentum / p.m;
        let dp = p.k * q;
        let hand: Vec<f64> = dq.iter().chain(dp.iter()).copied().collect();
        assert_close(&derivatives(&model, 0.0, &x), &hand, "derivatives");
        assert_close(&outputs(&model, 0.0, &x), &[p.vx, p.vy, p.vz], "outputs");
        let supplied = (p.k * q).dot(&into_s);
        assert_close(
            &[balance(&model, 0.0, &x).input],
            &[supplied],
            "input power",
        );
    }
}
