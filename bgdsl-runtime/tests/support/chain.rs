//! A hand-written stiff model for the Jacobian tests and benchmarks: a chain of masses
//! coupled by stiff spring-dampers (mass 0.1 kg, k = 1e5 N/m, c = 20 N·s/m, as in the
//! quick return mechanism), with a slightly hardening spring law so the Jacobian
//! depends on the state.
//!
//! Spring `i` joins mass `i − 1` (the wall for `i = 0`) to mass `i`; the last mass is
//! pulled by `F(t) = F₀ sin(ω t)`. States interleave `x[2i] = qᵢ` (the elongation of
//! spring `i`) and `x[2i + 1] = pᵢ` (the momentum of mass `i`):
//!
//! ```text
//! q̇ᵢ = vᵢ − vᵢ₋₁                      vᵢ = pᵢ / m, v₋₁ = 0
//! ṗᵢ = Tᵢ₊₁ − Tᵢ (+ F(t) on the last)  Tᵢ = k qᵢ + k₃ qᵢ³ + c (vᵢ − vᵢ₋₁), T_N = 0
//! ```
//!
//! So row `2i` reads columns `2i − 1, 2i + 1` and row `2i + 1` reads `2i − 1 … 2i + 3`
//! (clipped at the ends): the exact pattern, declared as a `static` built at compile
//! time.
#![allow(dead_code)]

use bgdsl_runtime::{Model, Scalar};

/// Masses in the chain.
pub const N_MASSES: usize = 60;
/// States: an elongation and a momentum per mass.
pub const N_STATES: usize = 2 * N_MASSES;

/// The columns row `r` depends on, written into `out` (at most 5); returns how many.
const fn row_columns(r: usize, out: &mut [usize; 5]) -> usize {
    let i = r / 2;
    let mut len = 0;
    if r.is_multiple_of(2) {
        if i > 0 {
            out[len] = 2 * i - 1;
            len += 1;
        }
        out[len] = 2 * i + 1;
        len += 1;
    } else {
        if i > 0 {
            out[len] = 2 * i - 1;
            len += 1;
        }
        out[len] = 2 * i;
        out[len + 1] = 2 * i + 1;
        len += 2;
        if i + 1 < N_MASSES {
            out[len] = 2 * i + 2;
            out[len + 1] = 2 * i + 3;
            len += 2;
        }
    }
    len
}

const NNZ: usize = {
    let mut total = 0;
    let mut r = 0;
    while r < N_STATES {
        total += row_columns(r, &mut [0; 5]);
        r += 1;
    }
    total
};

static COLUMNS: [usize; NNZ] = {
    let mut flat = [0; NNZ];
    let mut at = 0;
    let mut r = 0;
    while r < N_STATES {
        let mut row = [0; 5];
        let len = row_columns(r, &mut row);
        let mut k = 0;
        while k < len {
            flat[at] = row[k];
            at += 1;
            k += 1;
        }
        r += 1;
    }
    flat
};

static ROWS: [&[usize]; N_STATES] = {
    let mut rows: [&[usize]; N_STATES] = [&[]; N_STATES];
    let mut start = 0;
    let mut r = 0;
    while r < N_STATES {
        let len = row_columns(r, &mut [0; 5]);
        let (_, rest) = COLUMNS.split_at(start);
        let (row, _) = rest.split_at(len);
        rows[r] = row;
        start += len;
        r += 1;
    }
    rows
};

/// State names `q0, p0, q1, p1, …`.
static NAMES: [&str; N_STATES] = [
    "q0", "p0", "q1", "p1", "q2", "p2", "q3", "p3", "q4", "p4", "q5", "p5", "q6", "p6", "q7", "p7",
    "q8", "p8", "q9", "p9", "q10", "p10", "q11", "p11", "q12", "p12", "q13", "p13", "q14", "p14",
    "q15", "p15", "q16", "p16", "q17", "p17", "q18", "p18", "q19", "p19", "q20", "p20", "q21",
    "p21", "q22", "p22", "q23", "p23", "q24", "p24", "q25", "p25", "q26", "p26", "q27", "p27",
    "q28", "p28", "q29", "p29", "q30", "p30", "q31", "p31", "q32", "p32", "q33", "p33", "q34",
    "p34", "q35", "p35", "q36", "p36", "q37", "p37", "q38", "p38", "q39", "p39", "q40", "p40",
    "q41", "p41", "q42", "p42", "q43", "p43", "q44", "p44", "q45", "p45", "q46", "p46", "q47",
    "p47", "q48", "p48", "q49", "p49", "q50", "p50", "q51", "p51", "q52", "p52", "q53", "p53",
    "q54", "p54", "q55", "p55", "q56", "p56", "q57", "p57", "q58", "p58", "q59", "p59",
];

/// The chain's parameters.
#[derive(Clone, Debug)]
pub struct ChainParams {
    /// Each mass, kg.
    pub m: f64,
    /// Linear stiffness of each spring, N/m.
    pub k: f64,
    /// Cubic stiffness of each spring, N/m³.
    pub k3: f64,
    /// Damping of each spring, N·s/m.
    pub c: f64,
    /// Amplitude of the force on the last mass, N.
    pub force: f64,
    /// Its angular frequency, rad/s.
    pub omega: f64,
}

impl Default for ChainParams {
    fn default() -> Self {
        ChainParams {
            m: 0.1,
            k: 1.0e5,
            k3: 1.0e9,
            c: 20.0,
            force: 10.0,
            omega: 50.0,
        }
    }
}

/// The chain of masses (see the module documentation).
#[derive(Clone, Debug, Default)]
pub struct Chain {
    /// The parameters.
    pub params: ChainParams,
}

impl Model for Chain {
    type Params = ChainParams;
    const NAME: &'static str = "chain";
    const STATE_NAMES: &'static [&'static str] = &NAMES;
    const OUTPUT_NAMES: &'static [&'static str] = &[];
    const JACOBIAN_SPARSITY: Option<&'static [&'static [usize]]> = Some(&ROWS);

    fn params(&self) -> &ChainParams {
        &self.params
    }

    fn initial_state(&self, x0: &mut [f64]) {
        x0.fill(0.0);
    }

    fn derivatives<T: Scalar>(&self, t: f64, x: &[T], dx: &mut [T]) {
        assert_eq!(x.len(), N_STATES, "state vector length");
        assert_eq!(dx.len(), N_STATES, "derivative vector length");
        let p = &self.params;
        let (inv_m, k, k3, c) = (
            T::from_f64(1.0 / p.m),
            T::from_f64(p.k),
            T::from_f64(p.k3),
            T::from_f64(p.c),
        );
        // Walk the springs from the wall: spring `i`'s tension acts on masses i − 1, i.
        let mut v_prev = T::from_f64(0.0);
        let mut tension_prev = T::from_f64(0.0);
        for i in 0..N_MASSES {
            let q = x[2 * i];
            let v = x[2 * i + 1] * inv_m;
            let rate = v - v_prev;
            let tension = k * q + k3 * q.powi(3) + c * rate;
            dx[2 * i] = rate;
            if i > 0 {
                dx[2 * i - 1] = tension - tension_prev;
            }
            v_prev = v;
            tension_prev = tension;
        }
        dx[N_STATES - 1] = T::from_f64(p.force * (p.omega * t).sin()) - tension_prev;
    }

    fn outputs<T: Scalar>(&self, _t: f64, _x: &[T], _y: &mut [T]) {}
}
