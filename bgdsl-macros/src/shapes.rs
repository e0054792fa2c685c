//! The shape of an expression (a number, an n-vector, an r×c matrix), as far as the
//! compiler can tell from the shapes of the names it reads: parameters, states,
//! signals, and the helpers of `bgdsl_runtime::multibond`. `None` means unknown (a
//! user's function, a block, a branch); callers then fall back to what needs no shape.

use syn::{BinOp, Expr, Ident, Member, UnOp};

use crate::ir::Shape;

/// Where the shapes of names come from.
pub trait ShapeEnv {
    /// The shape of a bare name (a parameter, a kinematic state, `t`), if known.
    fn name(&self, name: &Ident) -> Option<Shape>;
    /// The shape of the signal `base.member` (`spring.q`, `v.f`), if `base` is an
    /// element or a labelled bond.
    fn signal(&self, base: &Ident, member: &Ident) -> Option<Shape>;
}

/// Methods of a number that give a number.
const SCALAR_METHODS: &[&str] = &[
    "abs",
    "acos",
    "acosh",
    "asin",
    "asinh",
    "atan",
    "atan2",
    "atanh",
    "cbrt",
    "ceil",
    "cos",
    "cosh",
    "exp",
    "exp2",
    "exp_m1",
    "floor",
    "hypot",
    "ln",
    "ln_1p",
    "log",
    "log10",
    "log2",
    "max",
    "min",
    "mul_add",
    "powf",
    "powi",
    "recip",
    "round",
    "signum",
    "sin",
    "sinh",
    "sqrt",
    "tan",
    "tanh",
    "to_degrees",
    "to_radians",
    "trunc",
    "clamp",
    "to_f64",
    "fract",
];

/// Methods of a vector or matrix that give a number.
const REDUCING_METHODS: &[&str] = &[
    "norm",
    "norm_squared",
    "dot",
    "determinant",
    "trace",
    "sum",
    "max",
    "min",
    "amax",
    "amin",
    "magnitude",
    "magnitude_squared",
];

/// Methods of a vector or matrix that keep its shape.
const SHAPE_KEEPING_METHODS: &[&str] = &[
    "abs",
    "component_mul",
    "component_div",
    "normalize",
    "scale",
    "unscale",
    "clone",
    "cross",
];

/// The component a field names: `x`, `y`, `z`, `w` of a vector, `m11` .. `m66` of a
/// matrix (rows and columns from 1).
pub enum Component {
    /// A vector entry, from 0.
    Vector(usize),
    /// A matrix entry (row, column), from 0.
    Matrix(usize, usize),
}

/// The component a field name denotes, if it is one.
pub fn component(member: &str) -> Option<Component> {
    match member {
        "x" => Some(Component::Vector(0)),
        "y" => Some(Component::Vector(1)),
        "z" => Some(Component::Vector(2)),
        "w" => Some(Component::Vector(3)),
        _ => {
            let digits = member.strip_prefix('m')?.as_bytes();
            match digits {
                [r @ b'1'..=b'6', c @ b'1'..=b'6'] => Some(Component::Matrix(
                    usize::from(r - b'1'),
                    usize::from(c - b'1'),
                )),
                _ => None,
            }
        }
    }
}

/// The shape of `expr`, if the compiler can tell.
pub fn shape(expr: &Expr, env: &dyn ShapeEnv) -> Option<Shape> {
    use Shape::*;
    match expr {
        Expr::Lit(_) => Some(Scalar),
        Expr::Paren(inner) => shape(&inner.expr, env),
        Expr::Group(inner) => shape(&inner.expr, env),
        Expr::Path(path) => match path.path.get_ident() {
            Some(ident) if path.qself.is_none() => env.name(ident),
            // `core::f64::consts::PI` and the like.
            _ => {
                let segments: Vec<String> = path
                    .path
                    .segments
                    .iter()
                    .map(|s| s.ident.to_string())
                    .collect();
                (segments.len() >= 2 && segments[segments.len() - 2] == "consts").then_some(Scalar)
            }
        },
        Expr::Unary(unary) if matches!(unary.op, UnOp::Neg(_)) => shape(&unary.expr, env),
        Expr::Binary(binary) => {
            let (left, right) = (shape(&binary.left, env)?, shape(&binary.right, env)?);
            match binary.op {
                BinOp::Add(_) | BinOp::Sub(_) => (left == right).then_some(left),
                BinOp::Mul(_) => product(left, right),
                BinOp::Div(_) => (right == Scalar).then_some(left),
                BinOp::Rem(_) => (left == Scalar && right == Scalar).then_some(Scalar),
                _ => None,
            }
        }
        Expr::Field(field) => {
            if let (Expr::Path(base), Member::Named(member)) = (&*field.base, &field.member) {
                if let Some(base) = base.path.get_ident() {
                    if let Some(shape) = env.signal(base, member) {
                        return Some(shape);
                    }
                }
            }
            match &field.member {
                Member::Named(member) => match component(&member.to_string())? {
                    Component::Vector(_) | Component::Matrix(..) => Some(Scalar),
                },
                Member::Unnamed(_) => None,
            }
        }
        Expr::Index(_) => {
            // A component of a vector or matrix (`K[0]`, `R[(0, 1)]`): a number.
            Some(Scalar)
        }
        Expr::MethodCall(call) => {
            let method = call.method.to_string();
            let receiver = shape(&call.receiver, env)?;
            match receiver {
                Scalar if SCALAR_METHODS.contains(&method.as_str()) => Some(Scalar),
                Vector(_) | Matrix(..) if REDUCING_METHODS.contains(&method.as_str()) => {
                    Some(Scalar)
                }
                Vector(_) | Matrix(..) if SHAPE_KEEPING_METHODS.contains(&method.as_str()) => {
                    Some(receiver)
                }
                Matrix(r, c) if method == "transpose" => Some(Matrix(c, r)),
                Vector(n) if method == "transpose" => Some(Matrix(1, n)),
                Scalar if method == "transpose" => Some(Scalar),
                _ => None,
            }
        }
        Expr::Call(call) => {
            let Expr::Path(func) = &*call.func else {
                return None;
            };
            let last = func.path.segments.last()?.ident.to_string();
            match last.as_str() {
                "vec3" | "box_inertia" => Some(Vector(3)),
                "diag3" | "skew" | "rot_z" | "identity3" => Some(Matrix(3, 3)),
                _ => None,
            }
        }
        _ => None,
    }
}

/// The shape of a product `a * b`, if it is defined.
fn product(a: Shape, b: Shape) -> Option<Shape> {
    use Shape::*;
    match (a, b) {
        (Scalar, other) | (other, Scalar) => Some(other),
        (Matrix(r, k), Vector(n)) if k == n => Some(Shape::of_dimension(r)),
        (Matrix(r, k), Matrix(k2, c)) if k == k2 => Some(Matrix(r, c)),
        // An outer product, n×1 times 1×c.
        (Vector(n), Matrix(1, c)) => Some(Matrix(n, c)),
        _ => None,
    }
}

#[cfg(test)]
mod should {
    use super::*;

    struct Env;
    impl ShapeEnv for Env {
        fn name(&self, name: &Ident) -> Option<Shape> {
            match name.to_string().as_str() {
                "k" | "m" | "t" => Some(Shape::Scalar),
                "l" => Some(Shape::Vector(3)),
                "R" => Some(Shape::Matrix(3, 3)),
                _ => None,
            }
        }
        fn signal(&self, _: &Ident, member: &Ident) -> Option<Shape> {
            (member == "f").then_some(Shape::Vector(3))
        }
    }

    fn of(text: &str) -> Option<Shape> {
        shape(&syn::parse_str(text).unwrap(), &Env)
    }

    #[test]
    fn follow_arithmetic_helpers_and_components() {
        assert_eq!(of("(k / m).sqrt() * 2.0"), Some(Shape::Scalar));
        assert_eq!(of("R * l"), Some(Shape::Vector(3)));
        assert_eq!(of("R.transpose() * R"), Some(Shape::Matrix(3, 3)));
        assert_eq!(of("box_inertia(m, l.x, l.y, l.z)"), Some(Shape::Vector(3)));
        assert_eq!(of("-core::f64::consts::PI * k"), Some(Shape::Scalar));
        assert_eq!(of("v.f"), Some(Shape::Vector(3)));
        assert_eq!(of("v.f.x + R.m12"), Some(Shape::Scalar));
    }

    #[test]
    fn say_unknown_for_what_they_cannot_tell() {
        assert_eq!(of("my_function(k)"), None);
        assert_eq!(of("l + k"), None);
        assert_eq!(of("if k > 0.0 { k } else { m }"), None);
        assert_eq!(of("MY_CONSTANT"), None);
    }
}
