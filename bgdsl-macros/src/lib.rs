//! The `bond_graph!` compiler.
//!
//! A pipeline of plain functions over `proc_macro2` tokens, one module per stage:
//! `syntax` (parse) → `flatten` (submodels) → `resolve` (names, structure, dimensions) → `causality` (SCAP) →
//! `equations` (assignments in computation order; `implicit` tears what cannot be
//! ordered) → `codegen` (Rust; `staged` for a model with unknowns). Modes and events
//! ride along: `event_syntax` parses them, `events` resolves and rewrites them (in
//! `resolve` and `equations`), `event_code` generates their `Model` items. Each stage
//! returns spanned `syn::Error`s, combined so that one compile reports every independent
//! mistake; the macro never panics.
//!
//! Users depend on `bgdsl-runtime`, which re-exports [`bond_graph!`].

mod allow;
mod causality;
mod chunks;
mod codegen;
mod compliance;
mod components;
mod derived;
mod dims;
mod equations;
mod errors;
mod event_code;
mod event_syntax;
mod events;
mod expand;
mod flatten;
mod hoist;
mod implicit;
mod ir;
mod keywords;
mod power;
mod resolve;
mod rewrite;
mod shapes;
mod signals;
mod split;
mod staged;
mod stdlib;
mod syntax;
mod units;
mod value_shape;

/// Compiles a textual bond graph into a simulation model.
///
/// ```
/// use bgdsl_runtime::{bond_graph, Model};
///
/// bond_graph! {
///     /// A mass on a spring with a damper, pushed by a constant force.
///     pub model Oscillator {
///         /// mass
///         param m = 1.0 in "kg";
///         /// stiffness
///         param k = 100.0 in "N/m";
///         /// damping
///         param c = 0.4 in "N·s/m";
///         /// applied force
///         param force = 1.0 in "N";
///
///         Se push = force;
///         I  mass = m, p in "kg·m/s";   // f = p / m; its state's unit
///         C  spring = k, q in "m";      // e = k q
///         R  damper = c;                // e = c f
///         1  v;                         // the common velocity
///
///         push -> v -> { mass, spring, damper };
///
///         init spring.q = 0.01;
///         output x = spring.q;          // a plain state lends its unit: m
///         output speed = v.f in "m/s";
///     }
/// }
///
/// let model = Oscillator::default();
/// assert_eq!(Oscillator::STATE_NAMES, ["mass.p", "spring.q"]);
/// assert_eq!((Oscillator::STATES[0].unit, Oscillator::OUTPUTS[0].unit), ("kg·m/s", "m"));
/// assert_eq!((Oscillator::PARAMETERS[1].name, Oscillator::PARAMETERS[1].unit), ("k", "N/m"));
/// let mut x = [0.0; 2];
/// model.initial_state(&mut x);
/// let mut dx = [0.0; 2];
/// model.derivatives(0.0, &x, &mut dx);
/// assert_eq!(dx, [1.0 - 100.0 * 0.01, 0.0]); // dp/dt = F - k q, dq/dt = p / m
/// ```
///
/// # Grammar
///
/// ```text
/// input     := (model | submodel)+
/// model     := (doc | allow)* vis? "model" Name "{" statement* "}"
/// submodel  := doc* "submodel" Name "(" param_decl ("," param_decl)* ")" "{" statement* "}"
/// param_decl:= name (":" type)? ("=" default)?
/// statement := doc* "param" name (":" type)? "=" expr ("in" "\"unit\"")? ";"
///                                                          parameter, default, unit
///            | (doc | allow)* KIND ("[" n "]")? name law? state_unit? ";"
///                                                          element (n: bond dimension)
///            | allow* endpoint (arrow endpoint)+ ";"         bonds
///            | "init" element "." ("q" | "p") "=" expr ";"   initial state (default 0)
///            | doc* "state" name ":" type "=" expr unit? ";"  kinematic state, initial value
///            | "der" name "=" expr ";"                       its time derivative
///            | doc* "output" name (":" type)? "=" expr unit? ";"  named output
///            | Submodel instance "(" (name "=" expr),* ")" ";"  submodel instance
///            | doc* "mode" name ":" ("bool" | "i64" | "f64") "=" expr ";"
///                                                          discrete mode, initial value
///            | doc* "when" (label ":")? condition "{" action* "}"  event (no `;` needed)
/// condition := expr ("<" | "<=") expr                       falling: lhs − rhs falls through 0
///            | expr (">" | ">=") expr                       rising: lhs − rhs rises through 0
///            | "crossing" "(" expr ")"                      either way
/// action    := "reinit" state "=" expr ";"                 a state: `ball.p`, `spring.q`, a
///                                                          kinematic `state`
///            | mode "=" expr ";"                           switch a mode
///            | "stop" ";"                                  end the run at the event
///            | "if" expr "{" action* "}" ("else" ("{" action* "}" | if_action))?
/// allow     := "#[allow(" lint ("," lint)* ")]"            opt-ins (see Dependent storage)
/// lint      := "derivative_causality" | "algebraic_loops"  (on the model, Rust's lints too)
/// KIND      := "Se" | "Sf" | "MSe" | "MSf" | "C" | "I" | "R" | "TF" | "GY" | "MTF" | "MGY" | "0" | "1" | "Split"
/// name      := identifier | "r#" keyword                  `r#loop`, shown as `loop`
/// type      := "f64" | "Vector3" | "Matrix3" | "[f64; N]" | "[[f64; C]; R]"
/// law       := "=" expr ("," "inverse" "=" expr)?          linear law or source value
///                                                          (inverse: TF/GY only)
///            | "{" form ("," form)* ","? "}"              explicit law
/// form      := ("e" | "f") "=" expr
/// state_unit:= "," ("q" | "p") unit                       C: `, q in "m"`; I: `, p in "kg·m/s"`
/// unit      := "in" "\"unit\""                             e.g. "N·m", "kg*m^2/s", "m/s²", "1"
/// endpoint  := path | "{" path ("," path)* ","? "}"        a group fans out or in
/// path      := name ("." name)* ("." n)?                   `crank.v`: a port of an instance;
///                                                          `s.0`: component 0 of splitter `s`
/// arrow     := "->" | "-[" label "]->"                     half arrow: power left to right
/// expr      := a Rust expression over parameters, `t`, signals `name.e` ..., states,
///              components `v.x` `v[i]` `M[(r, c)]`, `f64` constants and functions
///                                                          (see Expressions)
/// ```
///
/// Every statement ends with `;`; a missing one is reported once, after the statement
/// that lacks it. A model has at least one element. A Rust keyword names something only
/// as a raw identifier (`1 r#loop;`, `r#loop.f`); messages, state, parameter and output
/// names and `GRAPH` show it without `r#`. The modulated kinds (MSe, MSf, MTF, MGY) are
/// their base kinds to the compiler and keep their own name in messages and `GRAPH`.
///
/// ## Multibonds
///
/// Bonds meeting at a junction share one dimension; an element written `I[3]` fixes it;
/// what nothing fixes is scalar. A one-port (Se, Sf, C, I, R) never takes a dimension
/// from the junction it meets: it has its own `[n]`, else the one its law visibly has
/// (`Se push = vec3(..)`, `C k = diag3(..)`, a coefficient parameter declared `Vector3`
/// or `Matrix3`), else it is scalar, and a scalar one-port on a 3-D junction is an error
/// naming the junction, with the fixes (`R[3] damper = c;`, or a projection
/// `MTF proj = n.transpose();` in between).
/// A 3-dimensional bond carries nalgebra vectors of the model's scalar type, and a
/// linear law's coefficient may be a number (it scales) or a matrix (it multiplies):
/// `C[3] joint = diag3(0.0, k, k);`. A TF/MTF with modulus `M` relates `f2 = M f1` and
/// `e1 = Mᵀ e2` (a GY/MGY: `e2 = M f1`, `e1 = Mᵀ f2`). A two-port declared `[n]`, or
/// whose modulus is a number, joins its two bonds into one dimension; otherwise `M` is
/// an n₂×n₁ matrix between a port-1 bond of dimension n₁ and a port-2 bond of dimension
/// n₂: `MTF proj = n.transpose();` (with `param n: Vector3`) projects a 3-D velocity on
/// `n` for a scalar damper, `MTF along = n;` turns a scalar speed into a 3-D velocity.
/// The compiler reads the shape of a modulus made of numbers, typed parameters and
/// states, `vec3`, `diag3`, `skew`, `rot_z`, `identity3`, `box_inertia`,
/// `.transpose()`, sums and products, and reports one that does not fit its bonds; a
/// modulus it cannot read takes the other port's dimension when only one is known, and
/// rustc checks it against `SMatrix<_, n₂, n₁>` at the expression. When causality
/// makes a multibond two-port work backwards, it needs `M⁻¹`: give it with
/// `MTF frame = R.transpose(), inverse = R;` — without it, the compile error says so (a
/// skew-symmetric lever arm has no inverse; a non-square modulus has none at all). A
/// modulus that is a plain number (as the splitters' paragraph below defines it) needs
/// none: run backwards it is divided by, on a multibond as on a scalar bond (`TF lever
/// = ratio;` gives `e2 = e1 / ratio`, `f1 = f2 / ratio`; a GY `f2 = e1 / r`,
/// `f1 = e2 / r`). A given inverse is checked on numbers (`Model::check`: before every run, when an FMU
/// leaves initialisation, and in debug builds at every `f64` evaluation that computes
/// with it). Helpers for laws are in `bgdsl_runtime::multibond`: `vec3`, `diag3`, `skew`, `rot_z`, `box_inertia`.
///
/// Parameters may be vectors and matrices (`param K: [f64; 3] = [0.0, 1e5, 1e5];`,
/// rows first), which laws see as nalgebra values. A kinematic state
/// (`state R: Matrix3 = rot_z(theta0); der R = skew(w.f) * R;`) is integrated like
/// storage; its name is a value in every expression. Vector and matrix outputs give one
/// column per entry: `_x`, `_y`, `_z`, or `_rc` column by column.
///
/// ## Splitters
///
/// `Split[n] s;` joins an n-dimensional multibond (bonded to `s` itself) to its n scalar
/// components (bonded to `s.0` .. `s.{n-1}`), and the components may take different
/// causalities: an anchor driven along x (`Sf drive -> s.0`), held along y and pushed
/// along z (`Se push -> s.2`). The junctions between a splitter and the elements that
/// act on whole vectors (C, I, R, sources, a TF or GY whose modulus may be a matrix) are
/// taken apart into one scalar junction per component, so causality is assigned
/// component by component there; a whole-vector element itself takes one causality for
/// all its components (to let a damper's components differ, write it as scalar dampers
/// behind a second splitter). A TF or GY whose modulus is a plain number acts on each
/// component alike, so it is taken apart too, into n scalar two-ports with the same
/// modulus, and the junctions beyond it with it: `guide -> lever -> anchor` with
/// `TF lever = n;` passes a flow source's speed on along x and an effort source's push
/// along z. A plain number is what the compiler can see is one: literals, `f64`
/// parameters and inputs, components of vector or matrix parameters (`K.x`), `t`, and
/// arithmetic and scalar methods (`sin`, `sqrt`, `powi`, ...) of these; a matrix
/// parameter, a helper call or a signal keeps the two-port whole (a causal conflict
/// through it says so). The taken-apart two-port's `e1`, `f1`, `e2`, `f2` are vectors
/// assembled from its components'.
///
/// ## Submodels
///
/// `submodel Name(params) { statements }` defines a reusable fragment; each instance
/// `Name inst(param = expr, ...)` is inlined with its names prefixed (`inst.part` in
/// messages and state names) and its parameters replaced by the arguments (a plain
/// name or path is passed as a name, so a body can be handed to a point:
/// `Point tip(body = crank, at = vec3(0.1, 0.0, 0.0))`). From outside, `inst.port`
/// names an instance's element or junction. Errors inside an instance point at the
/// instantiation. The standard library, written in this language and always available
/// (a model's own submodel of the same name takes precedence):
///
/// - `RigidBody(m, J, R0, r0, g)`: translational momentum, angular momentum in frame 0
///   with `w = R J⁻¹ Rᵀ h`, orientation `R` and position `r` states, weight; ports `v`
///   (centre-of-mass velocity) and `w` (angular velocity).
/// - `Point(body, at)`: the point at body-frame vector `at`; port `v`.
/// - `OffsetPoint(body, offset)`: the point at frame-0 offset `offset` from the centre
///   of mass (it may move over the body); port `v`.
/// - `Ground()`: a fixed point; port `v`.
/// - `Coupling(a, b, k, c)`: a spring-damper between ports `a` and `b`; its force acts
///   on `b`, its opposite on `a`; `spring.q` is `∫ (a − b)`.
/// - `FrameCoupling(a, b, frame, k, c)`: the same with the laws in a moving frame.
/// - `Switch(a, b, control, r_on, g_off, closed0)`, `Diode(a, b, r_on, g_off, on0)`:
///   a resistor between two nodes switching between `e = r_on f` and `f = g_off e`
///   (mode `closed` / `on`), by a control's or its own voltage's sign.
/// - `Impact(at, body, gap, dir, restitution, v_rest, held)`: restitution when `gap`
///   closes, rest mode `resting` below `v_rest`; `Contact(at, gap, dir, k, c)`: a
///   one-sided spring-damper (mode `touching`).
/// - `CoulombFriction(a, b, fc, forward0)`, `StickSlip(a, b, fc, fs, held, stuck0,
///   forward0)`, `Clutch(a, b, tk, ts, held, locked0, forward0)`: friction between two
///   ports, kinetic or with stiction (`held`: the force that keeps it stuck); see
///   "Events and modes".
///
/// ## Events and modes
///
/// A **mode** is a discrete state: `mode stuck: bool = false;` (or `i64`, `f64`), with
/// its initial value in the parameters. It is stored in the state vector after every
/// continuous state, in declaration order (an instance's modes where the instance is
/// written), with derivative exactly 0, so every integrator holds it constant between
/// events; `STATE_NAMES`, the named state record, `initial_state`, trajectories and
/// CSVs carry it (a `bool` as 0.0 or 1.0), and `Model::MODES` describes it (name, type,
/// doc comment). Laws, outputs, `der`, conditions and actions read a mode by its name as
/// a plain value: a `bool`, an `i64` (integer literals in arithmetic and comparisons
/// with it stay integers: `gear == 2`, `(gear * 2 + 1) % 3`), or, for an `f64` mode, a
/// constant of the scalar type. It
/// never carries a derivative, so `if stuck { .. } else { .. }` switches between two
/// smooth laws, each with its exact Jacobian (`JACOBIAN_SPARSITY` has an empty row for
/// a mode and no column for it).
///
/// An **event** is `when condition { actions }`. Its indicator is g = lhs − rhs (or
/// the argument of `crossing`), computed in `f64` from every signal of the model at (t,
/// x), and it fires when g crosses zero in its direction: `lhs < rhs` (or `<=`) when g
/// falls through zero (from above to at or below), `lhs > rhs` (or `>=`) when g rises
/// through zero, `crossing(x)` either way; `<` and `<=` make the same event. A condition
/// that already holds at the start of a run fires only after it has stopped holding and
/// crosses again. `Model::EVENTS` lists the events (name, direction, doc comment) and
/// `Model::event_indicators` computes g; the runtime locates the crossing and calls
/// `Model::apply_event` (see `bgdsl_runtime::event`).
///
/// The actions: `reinit ball.p = ..;` sets a state (a C's `q`, an I's `p`, a kinematic
/// `state`); `stuck = ..;` switches a mode; `stop;` ends the run at the event;
/// `if .. { .. } else { .. }` chooses. Every value and every `if` condition reads the
/// values just before the event, and the assignments are made together after all are
/// computed (Modelica's semantics): `reinit a.p = b.p; reinit b.p = a.p;` swaps. Two
/// assignments to one state: the later one written wins. Events that fire at the same
/// time (within the runtime's time tolerance) are handled in declaration order, each
/// action applied to the state the previous one left.
///
/// **A discontinuity goes through a mode**, never through `if v > 0.0 { .. }` on a
/// continuous signal: switch a mode at the event where v crosses zero and let the law
/// read the mode, so the right-hand side is smooth inside every step and the solver's
/// error control and Jacobians stay valid. Events the host causes by changing inputs
/// between steps are the host's to handle.
///
/// An event is named by its label, `when impact: x < 0.0 { .. }`, or else `when_k`,
/// the k-th `when` of the model or submodel it is written in (labelled ones counted).
/// Modes and events may be declared in submodels; their names are prefixed like states
/// (`wall.hits`, `wall.when_1`). Labels and modes share the namespace of parameters and
/// elements. In a model with dependent storage or algebraic loops, the event functions
/// solve the unknowns first, as `outputs` does (a failed solve gives NaN indicators and
/// leaves the state unchanged).
///
/// Compile errors, each at the text concerned: `reinit` of something that is no state
/// (a parameter, a signal such as `spring.e`, an element without state, dependent
/// storage, a mode: "assign a mode with `x = ..;`"); a condition that is no comparison
/// or `crossing(..)` (`==`, `&&` and a bare value included); a condition on a vector
/// or a matrix; a mode that is read but never switched (a parameter in disguise); an
/// assignment to an unknown mode (with the nearest name); a `when` with no action;
/// two modes of one name; a mode of another type than `bool`, `i64`, `f64`. Unknown
/// names in conditions and actions are reported like those in laws.
///
/// ## Units
///
/// A parameter, input, output or kinematic state takes its unit after its value, `in
/// "N·m"`; a C or I element gives its state's after its law, `C spring = k, q in "m";`
/// (the element's doc comment documents the state). An output that is a plain state or
/// parameter (`output x = spring.q;`) takes that one's unit; nothing else is inferred,
/// and what the model does not say stays unit-less. Units and docs reach
/// `Model::STATES` and `Model::OUTPUTS` (one entry per number: every component of a
/// vector has the unit), the FMU's `modelDescription.xml` and the `models` program.
///
/// Unit strings are SI with prefixes: base and derived units, `rad`, `deg`, `rpm`,
/// `min`, `h`, `L`, `bar`; products with `·` or `*`, quotients with `/`, powers `m²`
/// or `m^2`, `1` for dimensionless (the grammar is in the `bgdsl-units` crate). The
/// compiler **warns**, at the unit's text, about a unit it cannot read and about an
/// output whose unit disagrees with the declared units its expression reads
/// (`output x = mass.p in "m"` where `mass.p` is in kg·m/s; `output F = k * spring.q
/// in "W"`; `spring.q + mass.p`; a plain state in "m" declared "mm", which nothing
/// converts). The warning is a `#[deprecated]` note (so `#![deny(warnings)]` makes it
/// an error); the checks change none of the generated evaluation code.
///
/// ## Elements and their laws
///
/// | kind | `= expr` means | explicit form | own variables |
/// |---|---|---|---|
/// | `Se` | the effort it sets on its bond | – | – |
/// | `Sf` | the flow it sets on its bond | – | – |
/// | `C` | a stiffness k (not a compliance): `e = k q` | `{ e = φ(q) }` | `q` (displacement) |
/// | `I` | inertia m: `f = p / m` | `{ f = φ(p) }` | `p` (momentum) |
/// | `R` | resistance r: `e = r f` | `{ e = φ(f) }` and/or `{ f = ψ(e) }` | `f` or `e` |
/// | `TF` | modulus n: `e1 = n e2`, `f2 = n f1` | – | – |
/// | `GY` | modulus r: `e1 = r f2`, `e2 = r f1` | – | – |
/// | `0`, `1` | junctions: common effort, common flow | – | – |
///
/// A source sets its bond's effort (Se, MSe) or flow (Sf, MSf) counted in the half
/// arrow's direction, whichever way the arrow points: `Sf drive = w; drive -> j;`
/// brings `w` into `j`, while `j -> drive;` takes `w` out of it (a bond entering a
/// source makes it a sink). The same holds for multibond sources and sources on a
/// splitter's components. A C's linear law is a stiffness: a shaft of stiffness
/// `k_shaft` is `C shaft = k_shaft;`, not `1.0 / k_shaft` (20-sim's and BondLib's
/// compliance). The compiler warns about `C shaft = 1.0 / x;` when `x` is a stiffness:
/// a parameter in N/m or N·m/rad, or, with no unit, named like one (`k`, `k_shaft`,
/// `K01`, `stiffness`); a capacitor's `1.0 / capacitance` is its stiffness and is right.
///
/// A linear law is inverted when causality needs it (an R that must compute its flow
/// uses `f = e / r`). An explicit law is used only in the form given: an R whose
/// causality needs the other form is a compile error that says which form to add.
/// One-ports take exactly one bond; TF and GY take one bond in (port 1) and one out
/// (port 2); junctions take two or more.
///
/// ## Expressions
///
/// Laws and outputs are Rust expressions in the model's scalar type. They may use
/// parameters by name, `t` (time), the element's own variables, and any signal of the
/// graph: `name.e`, `name.f` of a one-port (port variables: power positive into C, I
/// and R; a source's are its bond's, along the half arrow), `name.q` / `name.p` of a storage element, `name.e` of a
/// 0-junction, `name.f` of a 1-junction, `name.e1`/`f1`/`e2`/`f2` of a TF or GY, and
/// `label.e` / `label.f` of a labelled bond. Methods of [`Scalar`] (`sin`, `exp`,
/// `powi`, `abs`, ...) are available. Float literals (and integer literals used as
/// operands of arithmetic or comparison) become scalar constants: write `0.5 * q`,
/// `q.powi(3)`, `if f > 0.0 { ... } else { ... }`.
///
/// Parameter defaults and initial conditions are `f64` expressions in the parameters
/// declared before them.
///
/// ### Parameter expressions
///
/// A sub-expression that reads only parameters and constants (`f64` constants such as
/// `core::f64::consts::PI` or a user's `UPPER_CASE` constant, calls of the user's
/// `f64` functions and of methods on such values: `box_inertia(m, a, b, c)`, `(k /
/// m).sqrt()`) is an `f64` expression computed once: the model keeps its value in a
/// private cache that `new` and `Model::set_parameter_values` recompute (parameters
/// written directly into `params` are detected and read fresh). One that also reads `t`
/// or an input is computed in `f64` once per evaluation (`v0 * (2.0 *
/// core::f64::consts::PI * freq * t).sin()`). Both enter the law as constants of the
/// scalar type (`bgdsl_runtime::lift`). The cache holds numbers, vectors and matrices
/// whose shape the compiler can tell (parameters, arithmetic, the `multibond`
/// helpers); any other constant expression (a user's function returning a vector, a
/// block) is computed per evaluation, still in `f64`.
///
/// ### Components
///
/// `.x` `.y` `.z` (`.w`) and `[i]` read a vector's components, `[(r, c)]`, `[r][c]`
/// and `.m11` .. (from 1) a matrix's entries, on every value alike: parameters, storage
/// and kinematic states, signals (`vel.f.x`, `mass.p[2]`, `K.y`). A component a value
/// does not have (`.z` on a number, `[3]` on a 3-vector) is a compile error at it.
///
/// ### Names
///
/// A bare lowercase name that the expression does not bind itself (`let`, closure
/// parameters, patterns) must be a parameter, element, bond label or state of the
/// model, `t`, or the element's own variable; otherwise it is an "unknown name" error
/// at the name, with the nearest model name as a did-you-mean, reported with the
/// model's other mistakes (in laws, outputs, `der`, initial values and parameter
/// defaults). A name in call position (`my_function(k)`), a path with `::`, method and
/// field names, and names starting with an upper-case letter (constants, unit structs,
/// enum variants) are left to rustc.
///
/// ## What is generated
///
/// For `pub model Foo`: `FooParams` (one `f64` field per parameter; `Default` from the
/// declared values; serde `Serialize`/`Deserialize`, unknown fields rejected), `Foo`
/// (holds the parameters; `Foo::GRAPH` describes the causal graph), `FooState<T>` and
/// `FooOutputs<T>` (named views of the state and output vectors), and an
/// implementation of `bgdsl_runtime::Model` whose derivative and output functions are
/// straight-line code generic over the scalar type.
///
/// ## Causality
///
/// Assigned at compile time by the sequential causality assignment procedure: sources,
/// then storage elements one at a time in integral causality, then resistors, each
/// followed by propagation through junctions, TF and GY. A causal conflict, a storage
/// element forced into derivative causality, an algebraic loop and a law in the wrong
/// form are compile errors at the element concerned (derivative causality and loops
/// unless allowed: see below), with notes at the elements that
/// caused them. A conflict names the junction where it happens, both parties and the
/// path between them (gyrators included), and says whether two bonds both set the
/// junction's common variable or none can.
///
/// ## Dependent storage and algebraic loops
///
/// Two things SCAP cannot complete are errors by default and allowed where the model
/// says so, with Rust's lint vocabulary:
///
/// - `#[allow(derivative_causality)]`: a C or I whose integral causality conflicts takes
///   derivative causality instead: *dependent storage*, for a rigid connection (two
///   inertias through a gear, a slider driven through a rigid arm) or storage driven by
///   a source. It has no state (`STATE_NAMES` leaves it out; `init` on it is an error);
///   it receives its co-energy variable (an I its flow, a C its effort) and returns the
///   time derivative of its energy variable E: p = m f for an I, q = k⁻¹ e for a C.
///   Its law must be linear — a number, vector or matrix coefficient, which may depend
///   on states, parameters and `t` (`MTF`-style modulation); an explicit law there is
///   an error. E must be a function of the states and time only: reading another
///   dependent element's output or an unknown of an algebraic loop is an error (a
///   higher-index problem). A conflict that remains with derivative causality allowed
///   is a *redundant constraint*, reported with the connections that over-determine
///   the motion.
/// - `#[allow(algebraic_loops)]`: equations that compute each other at the same instant
///   (two dampers in series) are solved at every evaluation.
///
/// Written before `model` an allowance covers the whole model; before an element, that
/// element; before a bond statement, the bonds it makes. Derivative causality is allowed
/// for a storage element if the model, the element or one of its bonds allows it; a
/// loop is allowed if the model or any element or bond on it does. An unknown lint name
/// is an error naming the one meant; an allowance that nothing uses is an error ("remove
/// it"), so a stale opt-in hides nothing. Without allowances the generated code is
/// exactly what it was.
///
/// The generated code solves one vector z of K unknowns (K fixed at compile time): the
/// state derivatives that dependent storage's d/dt E reads where they depend on it in
/// turn (for a mechanism, its independent momenta's derivatives: the mass matrix in
/// disguise), and one torn signal per algebraic loop. d/dt E is exact: E is evaluated on
/// `Tangent` numbers carrying the state derivatives. Newton runs in `f64` with the exact
/// Jacobian (one evaluation on `DualN<K>`) from the previous solution, one step when the
/// compiler sees the system is linear in z; a final implicit-function step on the
/// caller's scalar carries derivatives through the solve, so a stiff solver's Jacobian
/// stays exact. A failed solve fills the derivatives with NaN and is reported by
/// `Model::evaluation_error` (`UnsolvedLoop`, `SingularConstraint`) with the elements
/// concerned. `DEPENDENT_STORAGE`, `ALGEBRAIC_LOOPS` and `GRAPH` (derivative causality,
/// `loops`) describe what was allowed; the power account keeps dependent storage's
/// energy.
///
/// [`Scalar`]: https://docs.rs/bgdsl-runtime/latest/bgdsl_runtime/trait.Scalar.html
#[proc_macro]
pub fn bond_graph(input: proc_macro::TokenStream) -> proc_macro::TokenStream {
    expand::expand(input.into()).into()
}

#[cfg(test)]
#[path = "tests/expand_all.rs"]
mod expand_all;

#[cfg(test)]
#[path = "tests/events.rs"]
mod events_tests;
