//! Units: what the model declares for its states and outputs, and the checks the
//! compiler can make cheaply.
//!
//! Every unit string the model writes (`param m = 1.0 in "kg";`, `output x = spring.q
//! in "m";`, `C spring = k, q in "m";`, `state r: Vector3 = r0 in "m";`) is parsed
//! with `bgdsl-units`. An unknown unit, and an output whose declared unit disagrees
//! with the units its expression reads (`output x = mass.p in "m"` where `mass.p` is in
//! kg·m/s), is a **warning** at the user's text: a stable proc macro cannot emit one
//! directly, so the expansion uses a `#[deprecated(note = "...")]` item spanned there,
//! which rustc reports as a warning (an error under `#![deny(warnings)]`). The checks
//! run at compile time only and change none of the generated evaluation code.
//!
//! An output that is a plain state or parameter (`output x = spring.q;`) without a
//! unit of its own takes that one's declared unit. Nothing else is inferred: a state
//! or output whose unit the model does not say stays unit-less.

use std::collections::BTreeMap;

use bgdsl_units::Unit;
use proc_macro2::{Span, TokenStream};
use quote::{format_ident, quote_spanned};
use syn::spanned::Spanned;
use syn::{BinOp, Expr, Lit, UnOp};

use crate::equations::Equations;
use crate::ir::{ElementKind, Graph};

/// The unit and documentation of one state or output (before it is split into
/// components: each component gets the same).
pub struct Described {
    /// The unit as declared, empty when none is known.
    pub unit: String,
    /// Its documentation, possibly empty.
    pub doc: String,
}

/// What the units stage produces for code generation.
pub struct Units {
    /// One entry per state of `Equations::states`.
    pub states: Vec<Described>,
    /// One entry per output of `Graph::outputs`.
    pub outputs: Vec<Described>,
    /// The warnings, as items to splice into the expansion.
    pub warnings: TokenStream,
}

/// Reads and checks every unit of the model.
pub fn check(graph: &Graph, equations: &Equations) -> Units {
    let mut warnings = Warnings::default();
    let mut scope = Scope::default();
    for param in &graph.params {
        if let Some(unit) = warnings.parse(param.unit.as_ref()) {
            scope.names.insert(param.name.to_string(), unit);
        }
    }
    for state in &graph.kinematics {
        if let Some(unit) = warnings.parse(state.unit.as_ref()) {
            scope.names.insert(state.name.to_string(), unit);
        }
    }
    for note in &graph.storage {
        if let Some(unit) = warnings.parse(note.unit.as_ref()) {
            let element = graph.element(note.element);
            let var = if element.kind == ElementKind::C {
                "q"
            } else {
                "p"
            };
            scope.storage.insert(element.name.to_string(), (var, unit));
        }
    }
    scope
        .names
        .insert("t".to_string(), (String::from("s"), seconds()));
    for (span, message) in crate::compliance::suspicious(graph) {
        warnings.push(span, message);
    }

    let states = equations
        .states
        .iter()
        .map(|state| match (state.element, state.kinematic) {
            (Some(id), _) => {
                let note = graph.storage_note(id);
                let element = graph.element(id);
                let var = if element.kind == ElementKind::C {
                    "q"
                } else {
                    "p"
                };
                let default_doc = format!(
                    "{} of {}",
                    if var == "q" {
                        "displacement q"
                    } else {
                        "momentum p"
                    },
                    graph.describe(id).replace('`', "")
                );
                Described {
                    unit: note
                        .and_then(|n| n.unit.as_ref())
                        .map(syn::LitStr::value)
                        .unwrap_or_default(),
                    doc: note.and_then(|n| n.doc.clone()).unwrap_or(default_doc),
                }
            }
            (None, Some(k)) => {
                let kinematic = &graph.kinematics[k];
                Described {
                    unit: kinematic
                        .unit
                        .as_ref()
                        .map(syn::LitStr::value)
                        .unwrap_or_default(),
                    doc: kinematic.doc.clone().unwrap_or_default(),
                }
            }
            (None, None) => Described {
                unit: String::new(),
                doc: state
                    .mode
                    .and_then(|m| graph.modes[m].doc.clone())
                    .unwrap_or_default(),
            },
        })
        .collect();

    let outputs = graph
        .outputs
        .iter()
        .map(|output| {
            let name = crate::flatten::display(&output.name.to_string());
            let doc = crate::codegen::doc_text(&output.attrs).unwrap_or_default();
            let source = scope.source(&output.expr);
            let mut issues = Vec::new();
            let inferred = scope.infer(&output.expr, &mut issues);
            for (span, message) in issues {
                warnings.push(span, format!("in the output `{name}`: {message}"));
            }
            let Some(literal) = &output.unit else {
                // A plain state or parameter lends the output its unit.
                let unit = source.map(|(text, _)| text).unwrap_or_default();
                return Described { unit, doc };
            };
            let declared_text = literal.value();
            if let Some(declared) = warnings.parse(Some(literal)) {
                let (_, declared) = declared;
                match (&source, inferred) {
                    (Some((text, unit)), _) if !unit.same_dimension(&declared) => warnings.push(
                        literal.span(),
                        format!(
                            "the output `{name}` is declared in \"{declared_text}\" ({}) but its \
                             expression is in \"{text}\" ({})",
                            declared.dimension(),
                            unit.dimension()
                        ),
                    ),
                    (Some((text, unit)), _) if !unit.same_unit(&declared) => warnings.push(
                        literal.span(),
                        format!(
                            "the output `{name}` is declared in \"{declared_text}\" but its \
                             expression is in \"{text}\", and nothing converts it"
                        ),
                    ),
                    (None, Dim::Known(unit)) if !unit.same_dimension(&declared) => warnings.push(
                        literal.span(),
                        format!(
                            "the output `{name}` is declared in \"{declared_text}\" ({}) but the \
                             units its expression reads give {}",
                            declared.dimension(),
                            unit.dimension()
                        ),
                    ),
                    _ => {}
                }
            }
            Described {
                unit: declared_text,
                doc,
            }
        })
        .collect();

    Units {
        states,
        outputs,
        warnings: warnings.tokens,
    }
}

fn seconds() -> Unit {
    Unit {
        exponents: [0, 0, 1, 0, 0, 0, 0, 0],
        factor: 1.0,
        offset: 0.0,
    }
}

/// The warnings of one model, as `#[deprecated]` items spanned at the user's text.
#[derive(Default)]
struct Warnings {
    tokens: TokenStream,
    count: usize,
}

impl Warnings {
    fn push(&mut self, span: Span, message: String) {
        let item = format_ident!("unit_warning_{}", self.count, span = span);
        self.count += 1;
        let note = format!("bond_graph!: {message}");
        self.tokens.extend(quote_spanned! {span=>
            const _: () = {
                #[deprecated(note = #note)]
                #[allow(non_camel_case_types)]
                struct #item;
                let _ = #item;
            };
        });
    }

    /// The unit of a declaration, warning at the literal when it does not parse.
    fn parse(&mut self, literal: Option<&syn::LitStr>) -> Option<(String, Unit)> {
        let literal = literal?;
        let text = literal.value();
        match bgdsl_units::parse(&text) {
            Ok(unit) => Some((text, unit)),
            Err(error) => {
                self.push(literal.span(), error.describe(&text).to_string());
                None
            }
        }
    }
}

/// The declared units an expression can read.
#[derive(Default)]
struct Scope {
    /// Parameters, inputs, kinematic states and `t`: name → (unit text, unit).
    names: BTreeMap<String, (String, Unit)>,
    /// Storage elements with a declared state unit: name → (state variable, unit).
    storage: BTreeMap<String, (&'static str, (String, Unit))>,
}

/// What is known of an expression's unit.
#[derive(Clone, Copy)]
enum Dim {
    /// Nothing (a call, a port variable, a name without a declared unit).
    Unknown,
    /// A number written in the text: dimensionless as a factor, anything as a term.
    Literal,
    /// A unit.
    Known(Unit),
}

impl Scope {
    /// The declared unit of an expression that is one name or state: `k`, `r`,
    /// `spring.q`, `K.x` (a component of a vector parameter).
    fn source(&self, expr: &Expr) -> Option<(String, Unit)> {
        match expr {
            Expr::Path(path) => {
                let name = path.path.get_ident()?.to_string();
                self.names.get(&name).cloned()
            }
            Expr::Field(field) => {
                let Expr::Path(base) = &*field.base else {
                    return None;
                };
                let base = base.path.get_ident()?.to_string();
                let member = match &field.member {
                    syn::Member::Named(ident) => ident.to_string(),
                    syn::Member::Unnamed(_) => return None,
                };
                if let Some((var, unit)) = self.storage.get(&base) {
                    return (member == *var).then(|| unit.clone());
                }
                self.names.get(&base).cloned()
            }
            Expr::Paren(inner) => self.source(&inner.expr),
            Expr::Group(inner) => self.source(&inner.expr),
            _ => None,
        }
    }

    /// The unit of `expr` from the declared units it reads; sums of different
    /// dimensions are reported into `issues`.
    fn infer(&self, expr: &Expr, issues: &mut Vec<(Span, String)>) -> Dim {
        if let Some((_, unit)) = self.source(expr) {
            return Dim::Known(unit);
        }
        match expr {
            Expr::Lit(lit) if matches!(lit.lit, Lit::Float(_) | Lit::Int(_)) => Dim::Literal,
            Expr::Paren(inner) => self.infer(&inner.expr, issues),
            Expr::Group(inner) => self.infer(&inner.expr, issues),
            Expr::Unary(unary) if matches!(unary.op, UnOp::Neg(_)) => {
                self.infer(&unary.expr, issues)
            }
            Expr::Binary(binary) => {
                let left = self.infer(&binary.left, issues);
                let right = self.infer(&binary.right, issues);
                match binary.op {
                    BinOp::Mul(_) => product(left, right, Unit::times),
                    BinOp::Div(_) => product(left, right, Unit::per),
                    BinOp::Add(_) | BinOp::Sub(_) => match (left, right) {
                        (Dim::Known(a), Dim::Known(b)) if !a.same_dimension(&b) => {
                            issues.push((
                                binary.op.span(),
                                format!(
                                    "`{}` adds {} to {}",
                                    quote::ToTokens::to_token_stream(binary)
                                        .to_string()
                                        .replace(" . ", "."),
                                    a.dimension(),
                                    b.dimension()
                                ),
                            ));
                            Dim::Unknown
                        }
                        (Dim::Known(a), _) | (_, Dim::Known(a)) => Dim::Known(a),
                        (Dim::Literal, Dim::Literal) => Dim::Literal,
                        _ => Dim::Unknown,
                    },
                    _ => Dim::Unknown,
                }
            }
            Expr::MethodCall(call) => {
                let receiver = self.infer(&call.receiver, issues);
                let Dim::Known(unit) = receiver else {
                    return Dim::Unknown;
                };
                match (call.method.to_string().as_str(), call.args.first()) {
                    ("abs" | "norm" | "transpose" | "clone", None) => receiver,
                    ("sqrt", None) => unit.sqrt().map_or(Dim::Unknown, Dim::Known),
                    ("powi", Some(Expr::Lit(lit))) => match &lit.lit {
                        Lit::Int(n) => n
                            .base10_parse::<i32>()
                            .ok()
                            .and_then(|n| unit.powi(n))
                            .map_or(Dim::Unknown, Dim::Known),
                        _ => Dim::Unknown,
                    },
                    _ => Dim::Unknown,
                }
            }
            _ => Dim::Unknown,
        }
    }
}

fn product(left: Dim, right: Dim, combine: fn(&Unit, &Unit) -> Option<Unit>) -> Dim {
    let as_unit = |d: Dim| match d {
        Dim::Known(unit) => Some(unit),
        Dim::Literal => Some(Unit::ONE),
        Dim::Unknown => None,
    };
    match (left, right) {
        (Dim::Literal, Dim::Literal) => Dim::Literal,
        (Dim::Unknown, _) | (_, Dim::Unknown) => Dim::Unknown,
        _ => as_unit(left)
            .zip(as_unit(right))
            .and_then(|(a, b)| combine(&a, &b))
            .map_or(Dim::Unknown, Dim::Known),
    }
}

#[cfg(test)]
mod should {
    /// The expansion of `text` as a string.
    fn expand(text: &str) -> String {
        crate::expand::expand(text.parse().unwrap()).to_string()
    }

    /// The generated `derivatives` and `outputs` functions' text.
    fn evaluation(expansion: &str) -> &str {
        let start = expansion.find("fn derivatives").unwrap();
        let end = expansion.find("fn power_balance").unwrap();
        &expansion[start..end]
    }

    const WITH_UNITS: &str = r#"
        pub model Oscillator {
            param m = 1.0 in "kg";
            param k = 100.0 in "N/m";
            I mass = m, p in "kg·m/s";
            C spring = k, q in "m";
            1 v;
            v -> { mass, spring };
            output x = spring.q in "mm";
            output speed = mass.p / m in "m/s";
        }
    "#;

    #[test]
    fn leave_the_evaluation_code_as_it_was() {
        let without = WITH_UNITS
            .replace(r#", p in "kg·m/s""#, "")
            .replace(r#", q in "m""#, "")
            .replace(r#" in "mm""#, "")
            .replace(r#" in "m/s""#, "");
        let with = expand(WITH_UNITS);
        let without = expand(&without);
        assert!(
            with.contains("unit_warning_0"),
            "the mm output is warned about"
        );
        assert!(!without.contains("unit_warning"));
        assert_eq!(evaluation(&with), evaluation(&without));
    }

    #[test]
    fn describe_every_state_and_output() {
        let with = expand(WITH_UNITS);
        for entry in [
            r#"name : "mass.p" , unit : "kg·m/s""#,
            r#"name : "spring.q" , unit : "m""#,
            r#"name : "x" , unit : "mm""#,
            r#"name : "speed" , unit : "m/s""#,
        ] {
            assert!(with.contains(entry), "{entry} missing");
        }
    }

    #[test]
    fn lend_a_plain_state_its_unit_and_guess_nothing_else() {
        let with = expand(
            r#"
            pub model M {
                param m = 1.0 in "kg";
                I mass = m, p in "kg·m/s";
                C spring = 1.0;
                1 v;
                v -> { mass, spring };
                output p = mass.p;
                output q = spring.q;
                output speed = mass.p / m;
            }
        "#,
        );
        assert!(with.contains(r#"name : "p" , unit : "kg·m/s""#));
        assert!(with.contains(r#"name : "q" , unit : """#));
        assert!(with.contains(r#"name : "speed" , unit : """#));
    }
}
