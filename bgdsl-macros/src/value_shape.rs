//! The shape of a law's value, where the macro can tell it from the text alone: number
//! literals, parameters and kinematic states (their shapes are declared), the multibond
//! helpers (`vec3`, `diag3`, `skew`, `rot_z`, `identity3`, `box_inertia`),
//! `.transpose()`, and sums and products of those. Anything else (a signal, a user
//! function, a method the macro does not know) is unknown, and rustc checks it.

use syn::{BinOp, Expr, UnOp};

use crate::ir::{Graph, Shape};

/// A value's shape: a number, or an r×c matrix (a vector is n×1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ValueShape {
    /// A number: it scales whatever it acts on.
    Number,
    /// An r×c matrix.
    Matrix(usize, usize),
}

impl ValueShape {
    /// The shape of a declared parameter or state.
    pub fn of_declared(shape: Shape) -> Self {
        match shape {
            Shape::Scalar => ValueShape::Number,
            Shape::Vector(n) => ValueShape::Matrix(n, 1),
            Shape::Matrix(r, c) => ValueShape::Matrix(r, c),
        }
    }

    fn transpose(self) -> Self {
        match self {
            ValueShape::Number => ValueShape::Number,
            ValueShape::Matrix(r, c) => ValueShape::Matrix(c, r),
        }
    }

    /// "a number", "a 3×1 matrix (a 3-vector)", "a 1×3 matrix".
    pub fn describe(self) -> String {
        match self {
            ValueShape::Number => "a number".to_string(),
            ValueShape::Matrix(n, 1) => format!("a {n}×1 matrix (a {n}-vector)"),
            ValueShape::Matrix(r, c) => format!("a {r}×{c} matrix"),
        }
    }
}

/// The shape of `expr`, if the text alone says it.
pub fn infer(expr: &Expr, graph: &Graph) -> Option<ValueShape> {
    use ValueShape::{Matrix, Number};
    match expr {
        Expr::Lit(lit) => match lit.lit {
            syn::Lit::Float(_) | syn::Lit::Int(_) => Some(Number),
            _ => None,
        },
        Expr::Paren(inner) => infer(&inner.expr, graph),
        Expr::Group(inner) => infer(&inner.expr, graph),
        Expr::Unary(unary) if matches!(unary.op, UnOp::Neg(_)) => infer(&unary.expr, graph),
        Expr::Path(path) => {
            let name = path.path.get_ident()?;
            if name == "t" {
                return Some(Number);
            }
            let declared = graph
                .params
                .iter()
                .find(|p| p.name == *name)
                .map(|p| p.shape)
                .or_else(|| {
                    graph
                        .kinematics
                        .iter()
                        .find(|k| k.name == *name)
                        .map(|k| k.shape)
                })?;
            Some(ValueShape::of_declared(declared))
        }
        Expr::Call(call) => {
            let Expr::Path(function) = &*call.func else {
                return None;
            };
            let last = function.path.segments.last()?.ident.to_string();
            match last.as_str() {
                "vec3" | "box_inertia" => Some(Matrix(3, 1)),
                "diag3" | "skew" | "rot_z" | "identity3" => Some(Matrix(3, 3)),
                _ => None,
            }
        }
        Expr::MethodCall(call) if call.method == "transpose" && call.args.is_empty() => {
            infer(&call.receiver, graph).map(ValueShape::transpose)
        }
        Expr::Binary(binary) => {
            let (left, right) = (infer(&binary.left, graph)?, infer(&binary.right, graph)?);
            match (binary.op, left, right) {
                (BinOp::Mul(_), Number, other) | (BinOp::Mul(_), other, Number) => Some(other),
                (BinOp::Mul(_), Matrix(r, k), Matrix(k2, c)) if k == k2 => Some(Matrix(r, c)),
                (BinOp::Div(_), other, Number) => Some(other),
                (BinOp::Add(_) | BinOp::Sub(_), a, b) if a == b => Some(a),
                _ => None,
            }
        }
        _ => None,
    }
}

#[cfg(test)]
mod should {
    use super::ValueShape::{self, Matrix, Number};

    fn shape(params: &str, expr: &str) -> Option<ValueShape> {
        let text = format!("model M {{ {params} Se s = 1.0; C c = 1.0; s -> c; }}");
        let file: crate::syntax::File = syn::parse_str(&text).unwrap();
        let graph = crate::resolve::resolve(file.models.into_iter().next().unwrap()).unwrap();
        super::infer(&syn::parse_str(expr).unwrap(), &graph)
    }

    #[test]
    fn read_declared_parameters_helpers_and_transposes() {
        let n = "param n: Vector3 = [0.0, 0.0, 1.0];";
        assert_eq!(shape(n, "n.transpose()"), Some(Matrix(1, 3)));
        assert_eq!(shape(n, "-2.0 * n"), Some(Matrix(3, 1)));
        assert_eq!(shape(n, "skew(n) * n"), Some(Matrix(3, 1)));
        assert_eq!(
            shape(n, "n.transpose() * diag3(1.0, 2.0, 3.0)"),
            Some(Matrix(1, 3))
        );
        assert_eq!(shape("param k = 2.0;", "k / 2.0"), Some(Number));
        assert_eq!(
            shape(
                "param a: [[f64; 2]; 3] = [[0.0, 1.0], [2.0, 3.0], [4.0, 5.0]];",
                "a"
            ),
            Some(Matrix(3, 2))
        );
    }

    #[test]
    fn leave_what_the_text_does_not_say_unknown() {
        assert_eq!(shape("", "my_matrix(t)"), None);
        assert_eq!(shape("", "s.e"), None);
        assert_eq!(shape("", "vec3(1.0, 0.0, 0.0) + 2.0"), None);
        assert_eq!(
            shape("param n: Vector3 = [0.0, 0.0, 1.0];", "n * n"),
            None,
            "a 3×1 times a 3×1 is no product"
        );
    }
}
