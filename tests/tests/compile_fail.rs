//! The compile-fail catalogue: every mistake a `bond_graph!` block can contain, one
//! small case each, with the compiler's output pinned in a `.stderr` snapshot next to it.
//!
//! Regenerate the snapshots with `TRYBUILD=overwrite cargo test -p bgdsl-tests --test
//! compile_fail`, then read every changed `.stderr`: the error must sit on the user's
//! text, say how to mend it, and never be a panic of the macro itself.

#[test]
fn ui() {
    let cases = trybuild::TestCases::new();
    // Statements that do not parse.
    cases.compile_fail("ui/syntax/*.rs");
    // Names, bonds, ports, laws and initial conditions that do not fit together.
    cases.compile_fail("ui/structure/*.rs");
    // Sequential causality assignment: conflicts, derivative causality, algebraic
    // loops, a resistor law in the wrong form.
    cases.compile_fail("ui/causality/*.rs");
    // Expressions in laws and outputs: unknown signals, own variables, type errors.
    cases.compile_fail("ui/laws/*.rs");
    // Several independent mistakes, all reported by one compile.
    cases.compile_fail("ui/multiple/*.rs");
    // A broken model next to user code that names it: only the model's own errors.
    cases.compile_fail("ui/stub/*.rs");
    // Multibonds: dimensions, modulated transformers, kinematic states.
    cases.compile_fail("ui/multibond/*.rs");
    // Submodels: errors inside an instance point at the instantiation.
    cases.compile_fail("ui/submodel/*.rs");
    // Splitters: ports, components and the causality a whole-vector element allows.
    cases.compile_fail("ui/splitter/*.rs");
    // The opt-ins for dependent storage and algebraic loops: the help lines without
    // them, allowances nothing uses, what dependent storage cannot have.
    cases.compile_fail("ui/implicit/*.rs");
    // Events and modes: what a `reinit` or a mode assignment cannot change, conditions
    // that are not comparisons, modes never switched, malformed `when` blocks.
    cases.compile_fail("ui/events/*.rs");
    // Unusual but valid models: no outputs, no states.
    cases.pass("ui/pass/*.rs");
}

/// Units: an unknown unit string, and an output whose declared unit disagrees with the
/// units its expression reads, are warnings at the text (errors under
/// `#![deny(warnings)]`, which pins their messages here); a state unit on the wrong
/// variable is an error.
#[test]
fn units() {
    let cases = trybuild::TestCases::new();
    cases.compile_fail("ui/units/*.rs");
    cases.pass("ui/units/pass/*.rs");
}
