//! Component access, the same on every value an expression reads (parameters, storage
//! states, kinematic states, signals): `.x` `.y` `.z` (`.w`) and `[i]` on a vector,
//! `[(r, c)]`, `[r][c]` and `.m12` (rows and columns from 1) on a matrix. Checked
//! against the value's shape where the compiler knows it: `.z` on a number or past a
//! vector's end is a compile error at the component; `[r][c]` on a matrix becomes
//! nalgebra's `[(r, c)]`.

use syn::spanned::Spanned;
use syn::visit_mut::VisitMut;
use syn::{Expr, ExprLit, Lit, Member};

use crate::errors::Errors;
use crate::ir::Shape;
use crate::shapes::{component, shape, Component, ShapeEnv};

/// Checks and normalises the component accesses in `expr`.
pub fn normalise(expr: &mut Expr, env: &dyn ShapeEnv, errors: &mut Errors) {
    Components { env, errors }.visit_expr_mut(expr);
}

/// Checks and normalises the component accesses in the model's initial values, `f64`
/// expressions in the parameters. (Parameter defaults see earlier parameters as plain
/// arrays, not nalgebra values, and are left as they are.)
pub fn normalise_initial_values(graph: &mut crate::ir::Graph, errors: &mut Errors) {
    let shapes: Vec<(String, Shape)> = graph
        .params
        .iter()
        .map(|p| (p.name.to_string(), p.shape))
        .collect();
    let mut check = |expr: &mut Expr| {
        let env = ParamShapes {
            shapes: &shapes,
            locals: crate::rewrite::local_names(expr),
        };
        normalise(expr, &env, errors);
    };
    for init in &mut graph.inits {
        check(&mut init.value);
    }
    for state in &mut graph.kinematics {
        check(&mut state.init);
    }
}

/// The shapes of the parameters, shadowed by an expression's local bindings.
struct ParamShapes<'a> {
    shapes: &'a [(String, Shape)],
    locals: std::collections::BTreeSet<String>,
}

impl ShapeEnv for ParamShapes<'_> {
    fn name(&self, name: &syn::Ident) -> Option<Shape> {
        let name = name.to_string();
        if self.locals.contains(&name) {
            return None;
        }
        self.shapes
            .iter()
            .find(|(known, _)| *known == name)
            .map(|&(_, shape)| shape)
    }

    fn signal(&self, _: &syn::Ident, _: &syn::Ident) -> Option<Shape> {
        None
    }
}

struct Components<'a> {
    env: &'a dyn ShapeEnv,
    errors: &'a mut Errors,
}

/// How messages name the value an access reads: `vel.f`, `K`, or "this value".
fn describe(expr: &Expr) -> String {
    match expr {
        Expr::Path(path) => match path.path.get_ident() {
            Some(ident) => format!("`{}`", crate::flatten::display(&ident.to_string())),
            None => "this value".to_string(),
        },
        Expr::Field(field) => match (&*field.base, &field.member) {
            (Expr::Path(base), Member::Named(member)) if base.path.get_ident().is_some() => {
                let base = base.path.get_ident().map(ToString::to_string);
                format!(
                    "`{}.{member}`",
                    crate::flatten::display(&base.unwrap_or_default())
                )
            }
            _ => "this value".to_string(),
        },
        Expr::Paren(inner) => describe(&inner.expr),
        _ => "this value".to_string(),
    }
}

fn what(shape: Shape) -> String {
    match shape {
        Shape::Scalar => "a number".to_string(),
        Shape::Vector(n) => format!("a {n}-vector"),
        Shape::Matrix(r, c) => format!("a {r}×{c} matrix"),
    }
}

/// How to read the components of a value of `shape`.
fn how_to_read(shape: Shape) -> String {
    match shape {
        Shape::Scalar => "only vectors and matrices have components (a parameter is a vector when \
             declared `param K: [f64; 3]`, a bond when an element on it is declared with a \
             dimension, e.g. `C[3] spring`)"
            .to_string(),
        Shape::Vector(n) => {
            let names = ["x", "y", "z", "w"];
            let fields = names[..n.min(4)]
                .iter()
                .map(|c| format!(".{c}"))
                .collect::<Vec<_>>()
                .join(", ");
            if n <= 4 {
                format!(
                    "read its components as {fields} or [0] to [{}]",
                    n.saturating_sub(1)
                )
            } else {
                format!("read its components as [0] to [{}]", n.saturating_sub(1))
            }
        }
        Shape::Matrix(r, c) => format!(
            "read an entry as [(row, column)] with row < {r} and column < {c} (from 0), or \
             .m11 to .m{r}{c} (from 1)"
        ),
    }
}

fn literal_index(expr: &Expr) -> Option<usize> {
    match expr {
        Expr::Lit(ExprLit {
            lit: Lit::Int(int), ..
        }) => int.base10_parse().ok(),
        _ => None,
    }
}

impl VisitMut for Components<'_> {
    fn visit_expr_mut(&mut self, expr: &mut Expr) {
        match expr {
            Expr::Field(field) => {
                self.visit_expr_mut(&mut field.base);
                let Member::Named(member) = &field.member else {
                    return;
                };
                let Some(component) = component(&member.to_string()) else {
                    return;
                };
                let Some(base_shape) = shape(&field.base, self.env) else {
                    return;
                };
                let fits = match (component, base_shape) {
                    (Component::Vector(i), Shape::Vector(n)) => i < n,
                    (Component::Matrix(i, j), Shape::Matrix(r, c)) => i < r && j < c,
                    _ => false,
                };
                if !fits {
                    self.errors.at(
                        member.span(),
                        format!(
                            "{} is {}: it has no component `.{member}`; {}",
                            describe(&field.base),
                            what(base_shape),
                            how_to_read(base_shape)
                        ),
                    );
                }
            }
            Expr::Index(index) => {
                self.visit_expr_mut(&mut index.index);
                let span = index.span();
                let whole = quote::ToTokens::to_token_stream(&*index);
                // `m[r][c]` on a matrix: nalgebra's `m[(r, c)]`.
                if let Expr::Index(inner) = &mut *index.expr {
                    self.visit_expr_mut(&mut inner.expr);
                    self.visit_expr_mut(&mut inner.index);
                    if let Some(Shape::Matrix(r, c)) = shape(&inner.expr, self.env) {
                        let (row, column) = (&inner.index, &index.index);
                        if let (Some(i), Some(j)) = (literal_index(row), literal_index(column)) {
                            if i >= r || j >= c {
                                self.errors.push(syn::Error::new_spanned(
                                    &whole,
                                    format!(
                                        "{} is a {r}×{c} matrix: it has no entry [{i}][{j}]; {}",
                                        describe(&inner.expr),
                                        how_to_read(Shape::Matrix(r, c))
                                    ),
                                ));
                            }
                        }
                        let base = &inner.expr;
                        *expr =
                            Expr::Verbatim(quote::quote_spanned!(span=> #base[(#row, #column)]));
                    }
                    return;
                }
                self.visit_expr_mut(&mut index.expr);
                let Some(base_shape) = shape(&index.expr, self.env) else {
                    return;
                };
                let entry = match &*index.index {
                    Expr::Tuple(pair) if pair.elems.len() == 2 => {
                        let mut elems = pair.elems.iter();
                        match (
                            elems.next().and_then(literal_index),
                            elems.next().and_then(literal_index),
                        ) {
                            (Some(i), Some(j)) => Some((i, Some(j))),
                            _ => return,
                        }
                    }
                    other => literal_index(other).map(|i| (i, None)),
                };
                let Some(entry) = entry else { return };
                let fits = match (entry, base_shape) {
                    ((i, None), Shape::Vector(n)) => i < n,
                    ((i, None), Shape::Matrix(r, c)) => i < r * c,
                    ((i, Some(j)), Shape::Matrix(r, c)) => i < r && j < c,
                    _ => false,
                };
                if !fits {
                    let written = match entry {
                        (i, None) => format!("[{i}]"),
                        (i, Some(j)) => format!("[({i}, {j})]"),
                    };
                    self.errors.at(
                        index.index.span(),
                        format!(
                            "{} is {}: it has no component {written}; {}",
                            describe(&index.expr),
                            what(base_shape),
                            how_to_read(base_shape)
                        ),
                    );
                }
            }
            Expr::Macro(_) => {}
            _ => syn::visit_mut::visit_expr_mut(self, expr),
        }
    }
}
