// Legitimate Rust inside expressions is not mistaken for unknown names: local `let`
// bindings, closure parameters, match and `if let` patterns, method names, paths, calls
// to the user's functions and the user's UPPER_CASE constants, a user's enum passed
// to a function of a state (not a number: passed through as it is).
use bgdsl_runtime::{bond_graph, Scalar};

const LIMIT: f64 = 2.0;

fn softened<T: Scalar>(x: T) -> T {
    x / (T::from_f64(1.0) + x.abs())
}

fn half(x: f64) -> f64 {
    0.5 * x
}

#[derive(Clone, Copy)]
enum Mode {
    Linear,
    Cubic,
}

fn shaped<T: Scalar>(mode: Mode, x: T) -> T {
    match mode {
        Mode::Linear => x,
        Mode::Cubic => x.powi(3),
    }
}

bond_graph! {
    model Rusty {
        param k = 100.0;
        Se push = { let scale = half(k); scale * (core::f64::consts::PI * t).sin() };
        I mass = 1.0;
        C spring { e = match Some(q) { Some(stretch) => k * softened(stretch), None => q } };
        R damper { e = (|rate: Scalar| rate * LIMIT)(f) };
        1 v;
        push -> v -> { mass, spring, damper };
        output x = if let Some(value) = Some(spring.q) { value.max(-LIMIT) } else { spring.q };
        output s = bgdsl_runtime::multibond::vec3(spring.q, 0.0, 0.0).x;
        output cubic = shaped(Mode::Cubic, spring.q) + shaped(Mode::Linear, mass.p);
    }
}

fn main() {}
