//! The shape of a two-port's modulus or a one-port's law, in the terms the dimension
//! stage speaks (a number, or an r×c matrix), where the text alone says it: the
//! expression shapes of [`crate::shapes`] over what the model declares (parameters,
//! kinematic states, `t`). Anything else (a signal, a user function, a method the
//! macro does not know) is unknown, and rustc checks it.

use syn::{Expr, Ident};

use crate::ir::{Graph, Shape};
use crate::shapes::ShapeEnv;

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

    /// "a number", "a 3×1 matrix (a 3-vector)", "a 1×3 matrix".
    pub fn describe(self) -> String {
        match self {
            ValueShape::Number => "a number".to_string(),
            ValueShape::Matrix(n, 1) => format!("a {n}×1 matrix (a {n}-vector)"),
            ValueShape::Matrix(r, c) => format!("a {r}×{c} matrix"),
        }
    }
}

/// The shape of `expr`, if the text alone says it: [`crate::shapes::shape`] over the
/// names whose shapes are declared (parameters, kinematic states, `t`). Signals have
/// no dimension yet when this runs, so they are unknown.
pub fn infer(expr: &Expr, graph: &Graph) -> Option<ValueShape> {
    crate::shapes::shape(expr, &Declared(graph)).map(ValueShape::of_declared)
}

/// The shapes a model declares: its parameters', its kinematic states' and `t`'s.
pub struct Declared<'a>(pub &'a Graph);

impl ShapeEnv for Declared<'_> {
    fn name(&self, name: &Ident) -> Option<Shape> {
        if name == "t" {
            return Some(Shape::Scalar);
        }
        let graph = self.0;
        graph
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
            })
    }

    fn signal(&self, _: &Ident, _: &Ident) -> Option<Shape> {
        None
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
