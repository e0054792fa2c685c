//! Part of the units stage: a C whose linear law looks like a compliance.
//!
//! A C's linear law is a stiffness, `e = k q`; 20-sim and BondLib take a compliance
//! instead, so `C shaft = 1.0 / k_shaft;` written from their habits compiles and gives
//! a shaft k² times too soft. `1.0 / x` is right for a capacitor (`1.0 / capacitance`
//! in F) or a heat capacity (J/K), so the law is flagged only when `x` is a stiffness:
//! a parameter declared in N/m or N·m/rad, or, with no unit, named like one (`k`,
//! `k_shaft`, `k1`, `K01`, `stiffness`).

use proc_macro2::Span;
use syn::spanned::Spanned;
use syn::{BinOp, Expr, Lit};

use crate::ir::{ElementKind, Graph, Law};

/// The C elements whose linear law is `1 / x` with `x` a stiffness: where to warn, and
/// what to say.
pub fn suspicious(graph: &Graph) -> Vec<(Span, String)> {
    let stiffness_units: Vec<bgdsl_units::Unit> = ["N/m", "N·m/rad"]
        .iter()
        .filter_map(|text| bgdsl_units::parse(text).ok())
        .collect();
    let mut found = Vec::new();
    for id in graph.element_ids() {
        let element = graph.element(id);
        let (ElementKind::C, Law::Linear(law)) = (element.kind, &element.law) else {
            continue;
        };
        let Some(divisor) = reciprocal_of(law) else {
            continue;
        };
        let Some(param) = graph.params.iter().find(|p| divisor.is_ident(&p.name)) else {
            continue;
        };
        let is_stiffness = match &param.unit {
            Some(unit) => bgdsl_units::parse(&unit.value())
                .is_ok_and(|unit| stiffness_units.iter().any(|s| s.same_dimension(&unit))),
            None => named_like_a_stiffness(&param.name.to_string()),
        };
        if is_stiffness {
            let name = crate::flatten::display(&element.name.to_string());
            let k = crate::flatten::display(&param.name.to_string());
            found.push((
                law.span(),
                format!(
                    "a C's law is a stiffness k (`e = k q`); `1 / {k}` looks like a compliance \
                     1/k: write `C {name} = {k};` (a capacitor's `1.0 / capacitance` is right: \
                     it is a stiffness)"
                ),
            ));
        }
    }
    found
}

/// `x` in `1 / x` or `1.0 / x` (in parentheses or not), `x` a plain name.
fn reciprocal_of(expr: &Expr) -> Option<&syn::Path> {
    match expr {
        Expr::Paren(inner) => reciprocal_of(&inner.expr),
        Expr::Group(inner) => reciprocal_of(&inner.expr),
        Expr::Binary(binary) if matches!(binary.op, BinOp::Div(_)) => {
            let one = match &*binary.left {
                Expr::Lit(lit) => match &lit.lit {
                    Lit::Float(f) => f.base10_parse::<f64>().is_ok_and(|v| v == 1.0),
                    Lit::Int(i) => i.base10_parse::<u64>().is_ok_and(|v| v == 1),
                    _ => false,
                },
                _ => false,
            };
            match (&*binary.right, one) {
                (Expr::Path(path), true) if path.path.get_ident().is_some() => Some(&path.path),
                _ => None,
            }
        }
        _ => None,
    }
}

/// `k`, `k_shaft`, `k1`, `K01`, `kShaft`, `stiffness`, `shaft_stiffness`: the names
/// a stiffness goes by (the part after the last submodel prefix).
fn named_like_a_stiffness(name: &str) -> bool {
    let name = name
        .rsplit(crate::flatten::SEPARATOR)
        .next()
        .unwrap_or(name);
    let mut chars = name.chars();
    let starts_like_k = match (chars.next(), chars.next()) {
        (Some('k' | 'K'), None) => true,
        (Some('k' | 'K'), Some(c)) => c == '_' || c.is_ascii_digit() || c.is_ascii_uppercase(),
        _ => false,
    };
    starts_like_k || name.to_ascii_lowercase().contains("stiff")
}

#[cfg(test)]
mod should {
    use super::*;

    fn warnings(text: &str) -> Vec<String> {
        let file: crate::syntax::File = syn::parse_str(text).unwrap();
        let graph = crate::resolve::resolve(file.models.into_iter().next().unwrap()).unwrap();
        suspicious(&graph).into_iter().map(|(_, m)| m).collect()
    }

    #[test]
    fn flag_the_reciprocal_of_a_stiffness() {
        for law in ["1.0 / k_shaft", "1 / k_shaft", "(1.0 / k_shaft)"] {
            let found = warnings(&format!(
                "model M {{ param k_shaft = 4e5; C shaft = {law}; Se s = 1.0; s -> shaft; }}"
            ));
            assert_eq!(found.len(), 1, "{law}");
            assert!(
                found[0].contains("write `C shaft = k_shaft;`"),
                "{}",
                found[0]
            );
        }
        let found = warnings(
            "model M { param k = 4e5 in \"N·m/rad\"; C shaft = 1.0 / k; Se s = 1.0; s -> shaft; }",
        );
        assert_eq!(found.len(), 1);
        let found = warnings(
            "model M { param grip = 4e5 in \"N/m\"; C spring = 1.0 / grip; Se s = 1.0; s -> spring; }",
        );
        assert_eq!(found.len(), 1);
    }

    #[test]
    fn leave_capacitors_and_other_stiffness_laws_alone() {
        for (param, law) in [
            ("capacitance = 1e-5 in \"F\"", "1.0 / capacitance"),
            ("capacity = 5e5 in \"J/K\"", "1.0 / capacity"),
            ("compliance = 1e-3", "1.0 / compliance"),
            ("k = 4e5 in \"F\"", "1.0 / k"),
            ("k_shaft = 4e5", "k_shaft"),
            ("k_shaft = 4e5", "2.0 / k_shaft"),
            ("kappa = 4e5", "1.0 / kappa"),
        ] {
            let found = warnings(&format!(
                "model M {{ param {param}; C c = {law}; Se s = 1.0; s -> c; }}"
            ));
            assert!(found.is_empty(), "{law}: {found:?}");
        }
    }
}
