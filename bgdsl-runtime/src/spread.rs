//! Marker types that spread a large generated model over codegen units.
//!
//! rustc puts a method into the codegen unit of the module that defines its self type.
//! A chunked model (`bgdsl-macros/src/chunks.rs`) implements each chunk of its
//! evaluation as a trait method on one of these types, `m<k % 16>::Slot` for chunk
//! `k`, so its chunks land in up to 16 codegen units that LLVM optimises in parallel,
//! instead of all in the model's module (one unit, one core). The placement follows the
//! type wherever the model is declared, in a module or in a function body.

/// The number of slot modules: cargo's default codegen units for a release build.
pub const SLOTS: usize = 16;

macro_rules! slots {
    ($($m:ident)*) => {$(
        /// One codegen unit's slot (see the [module documentation](super)).
        pub mod $m {
            /// The self type of the chunks placed in this slot's codegen unit.
            #[derive(Clone, Copy, Debug)]
            pub struct Slot;
        }
    )*};
}

slots!(m0 m1 m2 m3 m4 m5 m6 m7 m8 m9 m10 m11 m12 m13 m14 m15);
