//! Unit strings as bgdsl models write them (`"kg"`, `"N·s/m"`, `"m/s²"`, `"kg*m^2/s"`),
//! parsed into exponents of the SI base units and a factor: exactly what an FMI 2.0
//! `<BaseUnit>` holds (section 2.2.2 of the standard: `kg`, `m`, `s`, `A`, `K`, `mol`,
//! `cd`, `rad`, `factor`, `offset`), and what the `bond_graph!` compiler compares to
//! find an output whose declared unit disagrees with the units its expression reads.
//!
//! `#![no_std]`, no allocation: the compiler, the runtime and the FMI export share it.
//!
//! # Grammar
//!
//! ```text
//! unit   := term (op term)*               "1" is a term: dimensionless, "1/s"
//! op     := "·" | "⋅" | "*" | "/"          a "/" divides by the next term only:
//!                                         "N·s/m" = N·s·m⁻¹, "m/s/s" = m·s⁻²
//! term   := prefix? symbol power?
//! power  := superscript digits, optionally "⁻" first ("m²", "s⁻¹"),
//!           or "^" "-"? digits ("m^2", "s^-1")
//! prefix := Y Z E P T G M k h da d c m µ u n p f a z y
//! symbol := SI base units (kg via g, m, s, A, K, mol, cd), rad and sr,
//!           derived units (N J W Pa Hz C V Ω Ohm F S Wb T H), and
//!           min h d (time), deg, rpm, L, bar
//! ```
//!
//! `°C` and `degC` stand alone (kelvin with offset 273.15). Parentheses are not
//! understood: write `kg/m/s` for kg/(m·s).
#![no_std]
#![warn(missing_docs)]

/// The base units, in the order of [`Unit::exponents`] and of FMI's `BaseUnit`.
pub const BASE_UNITS: [&str; 8] = ["kg", "m", "s", "A", "K", "mol", "cd", "rad"];

/// A parsed unit: `value in SI = factor · value + offset`, with the SI unit
/// `kg^e0 · m^e1 · s^e2 · A^e3 · K^e4 · mol^e5 · cd^e6 · rad^e7`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Unit {
    /// Exponents of [`BASE_UNITS`].
    pub exponents: [i8; 8],
    /// The factor to SI: 1e-3 for `mm`, π/180 for `deg`.
    pub factor: f64,
    /// The offset to SI (273.15 for `°C`, 0 otherwise).
    pub offset: f64,
}

/// Why a unit string did not parse.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UnitError {
    /// The string is empty.
    Empty,
    /// A symbol that is no known unit, with or without a prefix (the symbol as written).
    UnknownSymbol(usize, usize),
    /// A `^` or `⁻` without digits, or an exponent out of range, at this byte range.
    BadPower(usize, usize),
    /// Two operators in a row, or one at an end, at this byte offset.
    MissingTerm(usize),
    /// A unit with an offset (`°C`) inside a product.
    OffsetInProduct,
}

impl UnitError {
    /// The message for `text`, the string that failed: "unknown unit `furlong`".
    pub fn describe<'a>(&self, text: &'a str) -> Description<'a> {
        Description { error: *self, text }
    }
}

/// An error message about a unit string (see [`UnitError::describe`]).
pub struct Description<'a> {
    error: UnitError,
    text: &'a str,
}

impl core::fmt::Display for Description<'_> {
    fn fmt(&self, out: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let text = self.text;
        match self.error {
            UnitError::Empty => write!(out, "an empty unit: write \"1\" for a dimensionless value"),
            UnitError::UnknownSymbol(start, end) => write!(
                out,
                "unknown unit `{}` in \"{text}\" (known: SI base and derived units with \
                 prefixes, rad, deg, rpm, min, h, L, bar; products with `·` or `*`, `/`, \
                 powers `m²` or `m^2`, \"1\" for dimensionless)",
                &text[start..end]
            ),
            UnitError::BadPower(start, end) => {
                write!(out, "a bad power `{}` in \"{text}\"", &text[start..end])
            }
            UnitError::MissingTerm(at) => write!(
                out,
                "a unit is missing at byte {at} of \"{text}\": write units between `·`, `*` and `/`"
            ),
            UnitError::OffsetInProduct => {
                write!(
                    out,
                    "\"{text}\": a unit with an offset (°C) cannot be part of a product"
                )
            }
        }
    }
}

const fn unit(exponents: [i8; 8], factor: f64) -> Unit {
    Unit {
        exponents,
        factor,
        offset: 0.0,
    }
}

const PI: f64 = core::f64::consts::PI;

/// Symbols and their value in SI. `g` is 1e-3 kg so that `kg`, `mg` work as prefixes.
const SYMBOLS: &[(&str, Unit)] = &[
    ("1", unit([0; 8], 1.0)),
    ("g", unit([1, 0, 0, 0, 0, 0, 0, 0], 1e-3)),
    ("m", unit([0, 1, 0, 0, 0, 0, 0, 0], 1.0)),
    ("s", unit([0, 0, 1, 0, 0, 0, 0, 0], 1.0)),
    ("A", unit([0, 0, 0, 1, 0, 0, 0, 0], 1.0)),
    ("K", unit([0, 0, 0, 0, 1, 0, 0, 0], 1.0)),
    ("mol", unit([0, 0, 0, 0, 0, 1, 0, 0], 1.0)),
    ("cd", unit([0, 0, 0, 0, 0, 0, 1, 0], 1.0)),
    ("rad", unit([0, 0, 0, 0, 0, 0, 0, 1], 1.0)),
    ("sr", unit([0, 0, 0, 0, 0, 0, 0, 2], 1.0)),
    ("N", unit([1, 1, -2, 0, 0, 0, 0, 0], 1.0)),
    ("J", unit([1, 2, -2, 0, 0, 0, 0, 0], 1.0)),
    ("W", unit([1, 2, -3, 0, 0, 0, 0, 0], 1.0)),
    ("Pa", unit([1, -1, -2, 0, 0, 0, 0, 0], 1.0)),
    ("Hz", unit([0, 0, -1, 0, 0, 0, 0, 0], 1.0)),
    ("C", unit([0, 0, 1, 1, 0, 0, 0, 0], 1.0)),
    ("V", unit([1, 2, -3, -1, 0, 0, 0, 0], 1.0)),
    ("Ω", unit([1, 2, -3, -2, 0, 0, 0, 0], 1.0)),
    ("Ohm", unit([1, 2, -3, -2, 0, 0, 0, 0], 1.0)),
    ("F", unit([-1, -2, 4, 2, 0, 0, 0, 0], 1.0)),
    ("S", unit([-1, -2, 3, 2, 0, 0, 0, 0], 1.0)),
    ("Wb", unit([1, 2, -2, -1, 0, 0, 0, 0], 1.0)),
    ("T", unit([1, 0, -2, -1, 0, 0, 0, 0], 1.0)),
    ("H", unit([1, 2, -2, -2, 0, 0, 0, 0], 1.0)),
    ("min", unit([0, 0, 1, 0, 0, 0, 0, 0], 60.0)),
    ("h", unit([0, 0, 1, 0, 0, 0, 0, 0], 3600.0)),
    ("d", unit([0, 0, 1, 0, 0, 0, 0, 0], 86400.0)),
    ("deg", unit([0, 0, 0, 0, 0, 0, 0, 1], PI / 180.0)),
    ("°", unit([0, 0, 0, 0, 0, 0, 0, 1], PI / 180.0)),
    ("rpm", unit([0, 0, -1, 0, 0, 0, 0, 1], 2.0 * PI / 60.0)),
    ("L", unit([0, 3, 0, 0, 0, 0, 0, 0], 1e-3)),
    ("l", unit([0, 3, 0, 0, 0, 0, 0, 0], 1e-3)),
    ("bar", unit([1, -1, -2, 0, 0, 0, 0, 0], 1e5)),
];

const PREFIXES: &[(&str, f64)] = &[
    ("da", 1e1),
    ("Y", 1e24),
    ("Z", 1e21),
    ("E", 1e18),
    ("P", 1e15),
    ("T", 1e12),
    ("G", 1e9),
    ("M", 1e6),
    ("k", 1e3),
    ("h", 1e2),
    ("d", 1e-1),
    ("c", 1e-2),
    ("m", 1e-3),
    ("µ", 1e-6),
    ("μ", 1e-6),
    ("u", 1e-6),
    ("n", 1e-9),
    ("p", 1e-12),
    ("f", 1e-15),
    ("a", 1e-18),
    ("z", 1e-21),
    ("y", 1e-24),
];

impl Unit {
    /// The dimensionless unit `1`.
    pub const ONE: Unit = unit([0; 8], 1.0);

    /// Whether `self` and `other` measure the same quantity, radians not counted (a
    /// torque in N·m and an energy in J agree, so do `rad/s` and `1/s`: radians are
    /// a ratio, and a compiler that cannot tell them apart must not complain).
    pub fn same_dimension(&self, other: &Unit) -> bool {
        self.exponents[..7] == other.exponents[..7]
    }

    /// Whether `self` and `other` are the same unit: same dimension (radians counted)
    /// and the same factor and offset.
    pub fn same_unit(&self, other: &Unit) -> bool {
        self.exponents == other.exponents
            && (self.factor / other.factor - 1.0).abs() < 1e-12
            && self.offset == other.offset
    }

    /// `self · other`.
    pub fn times(&self, other: &Unit) -> Option<Unit> {
        self.combine(other, 1)
    }

    /// `self / other`.
    pub fn per(&self, other: &Unit) -> Option<Unit> {
        self.combine(other, -1)
    }

    /// `self` raised to `power` (`None` when an exponent leaves `i8`).
    pub fn powi(&self, power: i32) -> Option<Unit> {
        let mut exponents = [0i8; 8];
        for (out, &e) in exponents.iter_mut().zip(&self.exponents) {
            *out = i8::try_from(i32::from(e).checked_mul(power)?).ok()?;
        }
        Some(unit(exponents, powi(self.factor, power)))
    }

    /// The square root, when every exponent is even.
    pub fn sqrt(&self) -> Option<Unit> {
        let mut exponents = [0i8; 8];
        for (out, &e) in exponents.iter_mut().zip(&self.exponents) {
            if e % 2 != 0 {
                return None;
            }
            *out = e / 2;
        }
        // Factors of square roots are rare in units; keep exact ones only.
        (self.factor == 1.0).then_some(unit(exponents, 1.0))
    }

    fn combine(&self, other: &Unit, sign: i8) -> Option<Unit> {
        let mut exponents = [0i8; 8];
        for ((out, &a), &b) in exponents
            .iter_mut()
            .zip(&self.exponents)
            .zip(&other.exponents)
        {
            *out = a.checked_add(b.checked_mul(sign)?)?;
        }
        let factor = if sign > 0 {
            self.factor * other.factor
        } else {
            self.factor / other.factor
        };
        Some(unit(exponents, factor))
    }

    /// The dimension in base units, `kg·m·s⁻²` (`1` for none; the factor is not
    /// shown), for messages.
    pub fn dimension(&self) -> DimensionText {
        DimensionText(self.exponents)
    }
}

/// A unit's dimension written in base units (see [`Unit::dimension`]).
pub struct DimensionText([i8; 8]);

impl core::fmt::Display for DimensionText {
    fn fmt(&self, out: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        const DIGITS: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];
        let mut first = true;
        for (name, &e) in BASE_UNITS.iter().zip(&self.0) {
            if e == 0 {
                continue;
            }
            if !first {
                out.write_str("·")?;
            }
            first = false;
            out.write_str(name)?;
            if e != 1 {
                if e < 0 {
                    out.write_str("⁻")?;
                }
                let mut magnitude = e.unsigned_abs();
                let mut digits = [0u8; 3];
                let mut n = 0;
                while magnitude > 0 {
                    digits[n] = magnitude % 10;
                    magnitude /= 10;
                    n += 1;
                }
                for &d in digits[..n].iter().rev() {
                    write!(out, "{}", DIGITS[usize::from(d)])?;
                }
            }
        }
        if first {
            out.write_str("1")?;
        }
        Ok(())
    }
}

fn powi(x: f64, n: i32) -> f64 {
    let mut result = 1.0;
    for _ in 0..n.unsigned_abs() {
        result *= x;
    }
    if n < 0 {
        1.0 / result
    } else {
        result
    }
}

/// Parses a unit string (see the crate documentation for the grammar).
pub fn parse(text: &str) -> Result<Unit, UnitError> {
    let trimmed = text.trim();
    if trimmed.is_empty() {
        return Err(UnitError::Empty);
    }
    if trimmed == "°C" || trimmed == "degC" {
        return Ok(Unit {
            exponents: [0, 0, 0, 0, 1, 0, 0, 0],
            factor: 1.0,
            offset: 273.15,
        });
    }
    if trimmed == "1" {
        return Ok(Unit::ONE);
    }
    let mut result = Unit::ONE;
    let mut sign = 1i32;
    let mut at = text.len() - text.trim_start().len();
    let end = at + trimmed.len();
    loop {
        let (term, next) = parse_term(text, at, end)?;
        let term = term.powi(sign).ok_or(UnitError::BadPower(at, next))?;
        result = result.times(&term).ok_or(UnitError::BadPower(at, next))?;
        if next == end {
            return Ok(result);
        }
        let rest = &text[next..end];
        let op = rest.chars().next().unwrap_or(' ');
        sign = match op {
            '·' | '⋅' | '*' => 1,
            '/' => -1,
            _ => return Err(UnitError::UnknownSymbol(next, next + op.len_utf8())),
        };
        at = next + op.len_utf8();
        if at == end {
            return Err(UnitError::MissingTerm(at));
        }
    }
}

/// One `prefix? symbol power?` from `start`; returns it and where it ends.
fn parse_term(text: &str, start: usize, end: usize) -> Result<(Unit, usize), UnitError> {
    let rest = &text[start..end];
    let symbol_len = rest
        .char_indices()
        .find(|&(_, c)| matches!(c, '·' | '⋅' | '*' | '/' | '^') || is_superscript(c))
        .map_or(rest.len(), |(i, _)| i);
    if symbol_len == 0 {
        return Err(UnitError::MissingTerm(start));
    }
    let symbol = &rest[..symbol_len];
    let base = lookup(symbol).ok_or(UnitError::UnknownSymbol(start, start + symbol_len))?;
    let after = start + symbol_len;
    let (power, next) = parse_power(text, after, end)?;
    let value = base.powi(power).ok_or(UnitError::BadPower(after, next))?;
    Ok((value, next))
}

/// A symbol with or without prefix: the whole symbol first (`m`, `min`, `Pa`, `cd`).
fn lookup(symbol: &str) -> Option<Unit> {
    let find = |s: &str| SYMBOLS.iter().find(|(name, _)| *name == s).map(|(_, u)| *u);
    if let Some(unit) = find(symbol) {
        return Some(unit);
    }
    PREFIXES.iter().find_map(|&(prefix, factor)| {
        let base = find(symbol.strip_prefix(prefix)?)?;
        // Prefixes go on units with factor 1 and on the gram, not on min, deg, rpm...
        let prefixable = base.factor == 1.0 || symbol.ends_with('g');
        prefixable.then_some(Unit {
            factor: base.factor * factor,
            ..base
        })
    })
}

fn is_superscript(c: char) -> bool {
    superscript_digit(c).is_some() || c == '⁻'
}

fn superscript_digit(c: char) -> Option<i32> {
    "⁰¹²³⁴⁵⁶⁷⁸⁹".chars().position(|d| d == c).map(|d| d as i32)
}

/// `²`, `⁻¹`, `^2`, `^-1` at `start`, or nothing (power 1).
fn parse_power(text: &str, start: usize, end: usize) -> Result<(i32, usize), UnitError> {
    let rest = &text[start..end];
    let mut chars = rest.char_indices().peekable();
    let mut negative = false;
    let mut digits = 0;
    let mut value = 0i32;
    let mut consumed = 0;
    match chars.peek() {
        Some(&(_, '^')) => {
            chars.next();
            consumed = 1;
            if let Some(&(_, '-')) = chars.peek() {
                chars.next();
                negative = true;
                consumed += 1;
            }
            while let Some(&(i, c)) = chars.peek() {
                let Some(d) = c.to_digit(10) else { break };
                value = value * 10 + d as i32;
                digits += 1;
                consumed = i + 1;
                chars.next();
            }
        }
        Some(&(_, c)) if is_superscript(c) => {
            while let Some(&(i, c)) = chars.peek() {
                if c == '⁻' && digits == 0 && !negative {
                    negative = true;
                } else if let Some(d) = superscript_digit(c) {
                    value = value * 10 + d;
                    digits += 1;
                } else {
                    break;
                }
                consumed = i + c.len_utf8();
                chars.next();
            }
        }
        _ => return Ok((1, start)),
    }
    if digits == 0 || digits > 2 {
        return Err(UnitError::BadPower(start, start + consumed.max(1)));
    }
    Ok((if negative { -value } else { value }, start + consumed))
}

#[cfg(test)]
mod should {
    extern crate std;
    use super::*;
    use std::format;

    fn exponents(text: &str) -> [i8; 8] {
        parse(text).unwrap().exponents
    }

    #[test]
    fn read_base_and_derived_units_with_prefixes() {
        assert_eq!(exponents("kg"), [1, 0, 0, 0, 0, 0, 0, 0]);
        assert_eq!(parse("kg").unwrap().factor, 1.0);
        assert_eq!(exponents("N"), [1, 1, -2, 0, 0, 0, 0, 0]);
        assert_eq!(parse("mm").unwrap().factor, 1e-3);
        assert_eq!(parse("kN").unwrap().factor, 1e3);
        assert_eq!(exponents("min"), [0, 0, 1, 0, 0, 0, 0, 0]);
        assert_eq!(parse("min").unwrap().factor, 60.0);
        assert_eq!(exponents("Pa"), exponents("N/m²"));
        assert_eq!(parse("1").unwrap(), Unit::ONE);
        assert_eq!(exponents("1/s"), exponents("Hz"));
    }

    #[test]
    fn read_products_quotients_and_powers() {
        let momentum = [1, 1, -1, 0, 0, 0, 0, 0];
        assert_eq!(exponents("kg·m/s"), momentum);
        assert_eq!(exponents("kg*m/s"), momentum);
        assert_eq!(exponents("N·s"), momentum);
        assert_eq!(exponents("m/s²"), exponents("m/s^2"));
        assert_eq!(exponents("m/s/s"), exponents("m·s⁻²"));
        assert_eq!(exponents("m·s^-2"), [0, 1, -2, 0, 0, 0, 0, 0]);
        assert_eq!(exponents("kg·m²/s"), [1, 2, -1, 0, 0, 0, 0, 0]);
        assert_eq!(exponents("N·m/rad"), [1, 2, -2, 0, 0, 0, 0, -1]);
        // Parentheses are not understood: V/rad/s is V·rad⁻¹·s⁻¹.
        assert_eq!(exponents("V/rad/s"), [1, 2, -4, -1, 0, 0, 0, -1]);
    }

    #[test]
    fn convert_angles_and_speeds() {
        let rpm = parse("rpm").unwrap();
        assert!((rpm.factor - 2.0 * PI / 60.0).abs() < 1e-15);
        assert!(rpm.same_dimension(&parse("rad/s").unwrap()));
        assert!(parse("deg").unwrap().same_dimension(&Unit::ONE));
        assert_eq!(parse("°C").unwrap().offset, 273.15);
    }

    #[test]
    fn reject_what_is_not_a_unit() {
        assert_eq!(parse("furlong"), Err(UnitError::UnknownSymbol(0, 7)));
        assert_eq!(parse("kg·parsec"), Err(UnitError::UnknownSymbol(4, 10)));
        assert_eq!(parse(""), Err(UnitError::Empty));
        assert_eq!(parse("m/"), Err(UnitError::MissingTerm(2)));
        assert_eq!(parse("m^"), Err(UnitError::BadPower(1, 2)));
        assert_eq!(parse("°C·m"), Err(UnitError::UnknownSymbol(0, 3)));
        assert!(parse("kmin").is_err(), "no prefix on a minute");
        let message = format!("{}", UnitError::UnknownSymbol(0, 7).describe("furlong"));
        assert!(message.starts_with("unknown unit `furlong`"), "{message}");
    }

    #[test]
    fn compare_dimensions_and_units() {
        let torque = parse("N·m").unwrap();
        assert!(torque.same_dimension(&parse("J").unwrap()));
        assert!(!torque.same_dimension(&parse("N").unwrap()));
        assert!(!parse("mm").unwrap().same_unit(&parse("m").unwrap()));
        assert!(parse("kg·m/s").unwrap().same_unit(&parse("N·s").unwrap()));
    }

    #[test]
    fn write_dimensions_in_base_units() {
        use std::string::ToString;
        assert_eq!(parse("N").unwrap().dimension().to_string(), "kg·m·s⁻²");
        assert_eq!(Unit::ONE.dimension().to_string(), "1");
        assert_eq!(parse("m^12").unwrap().dimension().to_string(), "m¹²");
    }
}
