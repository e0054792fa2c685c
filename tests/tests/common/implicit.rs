//! Helpers for the models that solve something at each evaluation (dependent storage,
//! algebraic loops): an energy account integrated along a run, a closed-form
//! comparison, and the Jacobian checks (automatic differentiation through the solve
//! against central differences, the declared sparsity a superset of the true one).

use bgdsl_runtime::{JacobianEvaluator, Model, ModelError, Scalar, SparsityPattern};

/// Names for the states of a [`WithWork`] model: enough for the textbook models.
const WORK_NAMES: [&str; 16] = [
    "x0", "x1", "x2", "x3", "x4", "x5", "x6", "x7", "x8", "x9", "x10", "x11", "x12", "x13", "x14",
    "x15",
];

/// A model with two more states: the energy its sources have supplied and the energy
/// its resistors have dissipated since the start, integrated from its own
/// `power_balance` by the same solver (so the account closes to the solver's
/// tolerance, not to a quadrature's). States: the model's, then `supplied`,
/// `dissipated` (named `x<i>`).
pub struct WithWork<'m, M>(pub &'m M);

impl<M: Model> Model for WithWork<'_, M> {
    type Params = M::Params;
    const NAME: &'static str = M::NAME;
    const STATE_NAMES: &'static [&'static str] = WORK_NAMES.split_at(M::N_STATES + 2).0;
    const OUTPUT_NAMES: &'static [&'static str] = M::OUTPUT_NAMES;

    fn params(&self) -> &M::Params {
        self.0.params()
    }

    fn initial_state(&self, x0: &mut [f64]) {
        let n = M::N_STATES;
        self.0.initial_state(&mut x0[..n]);
        x0[n] = 0.0;
        x0[n + 1] = 0.0;
    }

    fn derivatives<T: Scalar>(&self, t: f64, x: &[T], dx: &mut [T]) {
        let n = M::N_STATES;
        self.0.derivatives(t, &x[..n], &mut dx[..n]);
        let balance = self
            .0
            .power_balance(t, &x[..n])
            .expect("generated models keep an account");
        dx[n] = balance.input;
        dx[n + 1] = balance.dissipated;
    }

    fn outputs<T: Scalar>(&self, t: f64, x: &[T], y: &mut [T]) {
        self.0.outputs(t, &x[..M::N_STATES], y);
    }

    fn evaluation_error(&self) -> Option<ModelError> {
        self.0.evaluation_error()
    }
}

/// The largest absolute value in `values`.
fn max_abs(values: impl IntoIterator<Item = f64>) -> f64 {
    values.into_iter().fold(0.0, |m, v| m.max(v.abs()))
}

/// Checks a column against a closed form: the largest error over the samples,
/// relative to the largest value of the closed form, is at most `tol`. Returns the
/// relative error (printed, for the record).
pub fn assert_matches(
    what: &str,
    times: &[f64],
    computed: &[f64],
    exact: impl Fn(f64) -> f64,
    tol: f64,
) -> f64 {
    assert_eq!(times.len(), computed.len(), "{what}: lengths");
    let expected: Vec<f64> = times.iter().map(|&t| exact(t)).collect();
    let scale = max_abs(expected.iter().copied()).max(f64::MIN_POSITIVE);
    let error = max_abs(computed.iter().zip(&expected).map(|(c, e)| c - e));
    let relative = error / scale;
    assert!(
        relative <= tol,
        "{what}: max error {error:e} exceeds {tol:e} x amplitude {scale:e} (relative {relative:e})"
    );
    eprintln!("{what}: max error {relative:e} of the amplitude");
    relative
}

/// Runs `model` wrapped in [`WithWork`] from its declared initial state over
/// `[0, t_end]` and checks, at each of `n` samples, that the stored energy changed by
/// what the sources supplied less what the resistors dissipated, within `tol` of the
/// largest of the stored energy, the supplied and the dissipated energy. Returns the
/// largest relative defect.
pub fn assert_energy_closes<M: Model>(
    model: &M,
    solver: bgdsl_runtime::Solver,
    t_end: f64,
    n: usize,
    tol: f64,
) -> f64 {
    let wrapped = WithWork(model);
    let states = M::N_STATES;
    let mut x0 = vec![0.0; states + 2];
    wrapped.initial_state(&mut x0);
    let (traj, _) = super::run(&wrapped, solver, &x0, t_end, n);
    let stored = |row: usize| {
        let x: Vec<f64> = (0..states).map(|j| traj.state(row, j).unwrap()).collect();
        model.power_balance(traj.times()[row], &x).unwrap().stored
    };
    let stored0 = stored(0);
    let mut scale: f64 = 0.0;
    let mut worst: f64 = 0.0;
    for row in 0..traj.len() {
        let supplied = traj.state(row, states).unwrap();
        let dissipated = traj.state(row, states + 1).unwrap();
        let now = stored(row);
        scale = scale
            .max(now.abs())
            .max(supplied.abs())
            .max(dissipated.abs());
        worst = worst.max((now - stored0 - supplied + dissipated).abs());
    }
    assert!(scale > 0.0, "{}: nothing happens", M::NAME);
    let relative = worst / scale;
    assert!(
        relative <= tol,
        "{}: stored − stored(0) − supplied + dissipated reaches {worst:e}, {relative:e} of \
         the energies' scale {scale:e} (tolerance {tol:e})",
        M::NAME
    );
    eprintln!(
        "{}: the energy account closes to {relative:e} of its scale",
        M::NAME
    );
    relative
}

/// d(stored)/dt = input − dissipated at `x`, exactly: the stored energy's derivative
/// along the model's own dx/dt by a dual number (through the model's solve), against
/// the power the sources supply and the resistors absorb, to `tol` of their scale.
pub fn assert_power_balances<M: Model>(model: &M, t: f64, x: &[f64], tol: f64) {
    use bgdsl_runtime::Dual;
    let mut dx = vec![0.0; x.len()];
    model.derivatives(t, x, &mut dx);
    let along: Vec<Dual> = x.iter().zip(&dx).map(|(&v, &d)| Dual::new(v, d)).collect();
    let balance = model.power_balance(t, &along).expect("an account");
    let rate = balance.stored.eps;
    let (input, dissipated) = (balance.input.to_f64(), balance.dissipated.to_f64());
    let scale = (input.abs() + dissipated.abs() + rate.abs()).max(1e-300);
    assert!(
        (rate - (input - dissipated)).abs() <= tol * scale,
        "{} at t = {t}, x = {x:?}: dE/dt {rate} vs input {input} − dissipated {dissipated}",
        M::NAME
    );
    assert!(dissipated >= 0.0, "{}: resistors absorb power", M::NAME);
}

/// The finite-difference step for a state at `x` with typical magnitude `scale`
/// (as in `jacobians.rs`): `ε^(1/3) · max(|x|, scale)` balances truncation and
/// round-off at about `ε^(2/3) ≈ 4e-11` of the function's scale.
fn step(x: f64, scale: f64) -> f64 {
    f64::EPSILON.cbrt() * x.abs().max(scale)
}

/// At each `(t, x)` of `samples`: the Jacobian by automatic differentiation (dual
/// numbers through the model's per-evaluation solve) equals a central-difference one
/// to `1e-7` of the largest entry of its row; every entry that is non-zero lies in the
/// declared `JACOBIAN_SPARSITY` (a superset of the true pattern is allowed, a subset
/// is a bug); and the compressed evaluation (one derivative per colour of the declared
/// pattern) equals the dense one inside the pattern.
pub fn assert_jacobian_exact<M: Model>(model: &M, samples: &[(f64, Vec<f64>)], scales: &[f64]) {
    let n = M::N_STATES;
    assert_eq!(scales.len(), n, "{}: one scale per state", M::NAME);
    let declared = M::JACOBIAN_SPARSITY.expect("generated models declare a pattern");
    let pattern = SparsityPattern::from_rows(declared).expect("a valid pattern");
    let mut dense = JacobianEvaluator::with_pattern(SparsityPattern::dense(n));
    let mut compressed = JacobianEvaluator::new(model);
    let (mut jd, mut jc) = (vec![0.0; n * n], vec![0.0; n * n]);
    let (mut above, mut below) = (vec![0.0; n], vec![0.0; n]);
    for (t, x) in samples {
        let at = format!("{} at t = {t}, x = {x:?}", M::NAME);
        dense.evaluate(model, *t, x, &mut jd);
        compressed.evaluate(model, *t, x, &mut jc);
        let mut xs = x.clone();
        for j in 0..n {
            let h = step(x[j], scales[j]);
            xs[j] = x[j] + h;
            let up = xs[j];
            model.derivatives(*t, &xs, &mut above);
            xs[j] = x[j] - h;
            let down = xs[j];
            model.derivatives(*t, &xs, &mut below);
            xs[j] = x[j];
            for i in 0..n {
                let fd = (above[i] - below[i]) / (up - down);
                let row_scale = max_abs(jd[i * n..(i + 1) * n].iter().copied()).max(1e-300);
                let ad = jd[i * n + j];
                assert!(
                    ad.is_finite() && (ad - fd).abs() <= 1e-7 * row_scale,
                    "{at}: ∂({})'/∂{}: AD {ad} vs central difference {fd} (row scale {row_scale})",
                    M::STATE_NAMES[i],
                    M::STATE_NAMES[j],
                );
                if ad != 0.0 {
                    assert!(
                        pattern.contains(i, j),
                        "{at}: ∂({})'/∂{} = {ad} but the declared pattern leaves it out",
                        M::STATE_NAMES[i],
                        M::STATE_NAMES[j],
                    );
                }
                if pattern.contains(i, j) {
                    assert!(
                        (jc[i * n + j] - ad).abs() <= 1e-14 * row_scale,
                        "{at}: ({i}, {j}): compressed {} vs dense {ad}",
                        jc[i * n + j]
                    );
                }
            }
        }
    }
}

/// The metadata and the drawing agree on what a model solves: each element is in
/// derivative causality in `M::GRAPH` exactly when `M::DEPENDENT_STORAGE` names it, and
/// is drawn in red then; it is outlined in orange exactly when it is a member of one of
/// `M::GRAPH`'s loops, whose names are those of `M::ALGEBRAIC_LOOPS`; a bond is red
/// exactly when it touches dependent storage. Returns the DOT text (for a parse check).
pub fn assert_drawing_marks<M: Model>(graph: &bgdsl_runtime::CausalGraph) -> String {
    use bgdsl_runtime::ElementCausality;
    let dot = graph.to_dot();
    let node_line = |index: usize| {
        let start = format!("e{index} [");
        dot.lines()
            .map(str::trim)
            .find(|l| l.starts_with(&start))
            .unwrap_or_else(|| panic!("{}: no node e{index} in\n{dot}", M::NAME))
    };
    let dependent: Vec<bool> = graph
        .elements
        .iter()
        .map(|e| e.causality == ElementCausality::Derivative)
        .collect();
    for (index, element) in graph.elements.iter().enumerate() {
        let listed = M::DEPENDENT_STORAGE.contains(&element.name);
        assert_eq!(
            dependent[index],
            listed,
            "{}: {} in derivative causality vs listed in DEPENDENT_STORAGE",
            M::NAME,
            element.name
        );
        let line = node_line(index);
        assert_eq!(
            line.contains("fontcolor=\"red\""),
            listed,
            "{}: {line}",
            M::NAME
        );
        let on_loop = graph.loops.iter().any(|members| members.contains(&index));
        assert_eq!(
            line.contains("color=\"orange\""),
            on_loop,
            "{}: {line}",
            M::NAME
        );
    }
    assert_eq!(
        graph.loops.len(),
        M::ALGEBRAIC_LOOPS.len(),
        "{}: loops",
        M::NAME
    );
    for (members, names) in graph.loops.iter().zip(M::ALGEBRAIC_LOOPS) {
        let mut drawn: Vec<&str> = members.iter().map(|&i| graph.elements[i].name).collect();
        let mut listed = names.to_vec();
        drawn.sort_unstable();
        listed.sort_unstable();
        assert_eq!(drawn, listed, "{}: a loop's members", M::NAME);
    }
    for bond in graph.bonds {
        let start = format!("e{} -> e{} [", bond.from, bond.to);
        let line = dot
            .lines()
            .map(str::trim)
            .find(|l| l.starts_with(&start))
            .unwrap_or_else(|| panic!("{}: no bond {start}", M::NAME));
        let touches = dependent[bond.from] || dependent[bond.to];
        assert_eq!(line.contains("color=\"red"), touches, "{}: {line}", M::NAME);
    }
    let marked = !M::DEPENDENT_STORAGE.is_empty() || !M::ALGEBRAIC_LOOPS.is_empty();
    assert_eq!(dot.contains("legend ["), marked, "{}: the legend", M::NAME);
    dot
}

/// Runs Graphviz's `dot -Tsvg` on `source` when it is installed (says so on stderr
/// when not): the drawing must parse without a warning.
pub fn assert_graphviz_parses(source: &str) {
    use std::io::Write as _;
    use std::process::{Command, Stdio};
    if Command::new("dot").arg("-V").output().is_err() {
        let _ = writeln!(
            std::io::stderr(),
            "SKIPPED the Graphviz parse: `dot` is not on PATH"
        );
        return;
    }
    let mut child = Command::new("dot")
        .arg("-Tsvg")
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn dot");
    child
        .stdin
        .take()
        .unwrap()
        .write_all(source.as_bytes())
        .unwrap();
    let output = child.wait_with_output().expect("run dot");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        output.status.success() && stderr.trim().is_empty(),
        "dot: {stderr}\n{source}"
    );
}
