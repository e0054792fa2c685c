//! Writing `modelDescription.xml` (FMI 2.0 schema `fmi2ModelDescription.xsd`).
//!
//! The document is built as a string; every attribute value goes through [`escape`].
//! Element order follows the schema: `ModelExchange`, `CoSimulation`,
//! `UnitDefinitions`, `LogCategories`, `ModelVariables`, `ModelStructure`.

use std::collections::BTreeSet;
use std::fmt::Write as _;

use crate::description::ModelDescription;
use crate::logger::Category;
use crate::variables::{Role, Variable};

/// The text of `modelDescription.xml` for `description` in an FMU whose binary is
/// `<identifier>.so` (the `modelIdentifier` of both interfaces).
pub fn model_description_xml(description: &ModelDescription, identifier: &str) -> String {
    let mut x = String::new();
    let d = description;
    x.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    x.push_str("<fmiModelDescription\n");
    attr(&mut x, 2, "fmiVersion", "2.0");
    attr(&mut x, 2, "modelName", d.model_name);
    attr(&mut x, 2, "guid", &d.guid);
    attr(&mut x, 2, "description", &d.description);
    let tool = concat!("bgdsl-fmi-core ", env!("CARGO_PKG_VERSION"));
    attr(&mut x, 2, "generationTool", tool);
    attr(&mut x, 2, "variableNamingConvention", d.naming.as_str());
    let events = d.variables.sizes().events.to_string();
    attr(&mut x, 2, "numberOfEventIndicators", &events);
    x.push_str(">\n");

    // Capabilities. Both interfaces are served by the same binary.
    x.push_str("  <ModelExchange\n");
    attr(&mut x, 4, "modelIdentifier", identifier);
    // With events, the FMU needs fmi2CompletedIntegratorStep: each accepted step's end
    // is the reference its indicators' crossings are measured from, as in the
    // runtime (an indicator exactly 0 at the last event takes its sign from the
    // next step's end).
    let not_needed = if d.variables.sizes().events == 0 {
        "true"
    } else {
        "false"
    };
    attr(&mut x, 4, "completedIntegratorStepNotNeeded", not_needed);
    common_capabilities(&mut x);
    x.push_str("  />\n");
    x.push_str("  <CoSimulation\n");
    attr(&mut x, 4, "modelIdentifier", identifier);
    attr(&mut x, 4, "canHandleVariableCommunicationStepSize", "true");
    attr(&mut x, 4, "canInterpolateInputs", "false");
    attr(&mut x, 4, "maxOutputDerivativeOrder", "0");
    attr(&mut x, 4, "canRunAsynchronuously", "false");
    common_capabilities(&mut x);
    x.push_str("  />\n");

    let units: BTreeSet<&str> = d
        .variables
        .all()
        .iter()
        .map(|v| v.unit.as_str())
        .filter(|u| !u.is_empty())
        .collect();
    if !units.is_empty() {
        x.push_str("  <UnitDefinitions>\n");
        for unit in units {
            unit_definition(&mut x, unit);
        }
        x.push_str("  </UnitDefinitions>\n");
    }

    x.push_str("  <LogCategories>\n");
    for category in Category::ALL {
        let _ = writeln!(
            x,
            "    <Category name=\"{}\" description=\"{}\"/>",
            category.name(),
            escape(category.description())
        );
    }
    x.push_str("  </LogCategories>\n");

    x.push_str("  <ModelVariables>\n");
    for v in d.variables.all() {
        scalar_variable(&mut x, d, v);
    }
    x.push_str("  </ModelVariables>\n");

    model_structure(&mut x, d);
    x.push_str("</fmiModelDescription>\n");
    x
}

/// One `<Unit>`, with its `<BaseUnit>` (the exponents of the SI base units, factor and
/// offset, FMI 2.0 section 2.2.2) when the unit string parses; a unit it cannot read is
/// declared by name alone.
fn unit_definition(x: &mut String, unit: &str) {
    let Ok(parsed) = bgdsl_runtime::units::parse(unit) else {
        let _ = writeln!(x, "    <Unit name=\"{}\"/>", escape(unit));
        return;
    };
    let _ = write!(x, "    <Unit name=\"{}\">\n      <BaseUnit", escape(unit));
    for (name, exponent) in bgdsl_runtime::units::BASE_UNITS
        .iter()
        .zip(parsed.exponents)
    {
        if exponent != 0 {
            let _ = write!(x, " {name}=\"{exponent}\"");
        }
    }
    if parsed.factor != 1.0 {
        let _ = write!(x, " factor=\"{}\"", xml_double(parsed.factor));
    }
    if parsed.offset != 0.0 {
        let _ = write!(x, " offset=\"{}\"", xml_double(parsed.offset));
    }
    x.push_str("/>\n    </Unit>\n");
}

/// The capability flags both interfaces share.
fn common_capabilities(x: &mut String) {
    attr(x, 4, "canNotUseMemoryManagementFunctions", "true");
    attr(x, 4, "canGetAndSetFMUstate", "false");
    attr(x, 4, "canSerializeFMUstate", "false");
    attr(x, 4, "providesDirectionalDerivative", "false");
}

/// The 1-based `ScalarVariable` index of a variable: its value reference plus one.
fn index(v: &Variable) -> u64 {
    u64::from(v.value_reference) + 1
}

fn scalar_variable(x: &mut String, d: &ModelDescription, v: &Variable) {
    let continuous = d.variables.sizes().continuous();
    let (causality, variability, initial) = match v.role {
        Role::State(i) if i >= continuous => ("local", "discrete", Some("exact")),
        Role::State(_) => ("local", "continuous", Some("exact")),
        Role::Derivative(_) => ("local", "continuous", Some("calculated")),
        Role::Output(_) => ("output", "continuous", Some("calculated")),
        Role::Parameter(_) => ("parameter", "tunable", Some("exact")),
        Role::Input(_) => ("input", "continuous", None),
    };
    let _ = write!(
        x,
        "    <!-- index {}: {} -->\n    <ScalarVariable name=\"{}\" valueReference=\"{}\"",
        index(v),
        v.role.kind(),
        escape(&v.name),
        v.value_reference
    );
    if !v.description.is_empty() {
        let _ = write!(x, " description=\"{}\"", escape(&v.description));
    }
    let _ = write!(
        x,
        " causality=\"{causality}\" variability=\"{variability}\""
    );
    if let Some(initial) = initial {
        let _ = write!(x, " initial=\"{initial}\"");
    }
    x.push_str(">\n      <Real");
    if !v.unit.is_empty() {
        let _ = write!(x, " unit=\"{}\"", escape(&v.unit));
    }
    if let Role::Derivative(i) = v.role {
        let state = d.variables.value_reference(Role::State(i));
        let _ = write!(x, " derivative=\"{}\"", u64::from(state) + 1);
    }
    if let Some(start) = v.start {
        let _ = write!(x, " start=\"{}\"", xml_double(start));
    }
    x.push_str("/>\n    </ScalarVariable>\n");
}

/// `ModelStructure`: the outputs, the state derivatives, and what initialisation
/// computes (outputs and derivatives, `initial="calculated"`; the states are
/// `initial="exact"`, so not unknowns). No `dependencies` attributes: every unknown may
/// depend on every known.
fn model_structure(x: &mut String, d: &ModelDescription) {
    let all = d.variables.all();
    let of = |keep: fn(Role) -> bool| -> Vec<u64> {
        all.iter().filter(|v| keep(v.role)).map(index).collect()
    };
    let outputs = of(|r| matches!(r, Role::Output(_)));
    let derivatives = of(|r| matches!(r, Role::Derivative(_)));
    let initial = of(|r| matches!(r, Role::Output(_) | Role::Derivative(_)));
    x.push_str("  <ModelStructure>\n");
    for (element, list) in [
        ("Outputs", outputs),
        ("Derivatives", derivatives),
        ("InitialUnknowns", initial),
    ] {
        if list.is_empty() {
            continue;
        }
        let _ = writeln!(x, "    <{element}>");
        for i in list {
            let _ = writeln!(x, "      <Unknown index=\"{i}\"/>");
        }
        let _ = writeln!(x, "    </{element}>");
    }
    x.push_str("  </ModelStructure>\n");
}

/// Writes `name="value"` on its own line, indented.
fn attr(x: &mut String, indent: usize, name: &str, value: &str) {
    let _ = writeln!(x, "{:indent$}{name}=\"{}\"", "", escape(value));
}

/// A number as `xs:double`: the shortest text that reads back as the same `f64`
/// (`1.0`, `0.0005`, `1e-5`), `INF`, `-INF` or `NaN`.
pub fn xml_double(value: f64) -> String {
    if value.is_nan() {
        "NaN".to_string()
    } else if value.is_infinite() {
        if value > 0.0 { "INF" } else { "-INF" }.to_string()
    } else {
        format!("{value:?}")
    }
}

/// `text` made safe inside a double-quoted attribute or element content: markup
/// characters as entities, tab and line breaks as character references (an attribute
/// value would otherwise normalise them to spaces), and characters XML 1.0 forbids
/// (other control characters, U+FFFE, U+FFFF) replaced by U+FFFD.
pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            '\t' => out.push_str("&#9;"),
            '\n' => out.push_str("&#10;"),
            '\r' => out.push_str("&#13;"),
            c if (c as u32) < 0x20 || c == '\u{FFFE}' || c == '\u{FFFF}' => out.push('\u{FFFD}'),
            c => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod should {
    use super::*;

    #[test]
    fn escape_markup_and_line_breaks() {
        assert_eq!(
            escape("a<b & \"c\" 'd'>\n\u{1}"),
            "a&lt;b &amp; &quot;c&quot; &apos;d&apos;&gt;&#10;\u{FFFD}"
        );
        assert_eq!(escape("N·m/rad"), "N·m/rad");
    }

    #[test]
    fn write_numbers_that_read_back_exactly() {
        for value in [1.0, 0.1, 1e-5, 2.5e-300, 1e16, -0.0, f64::MAX] {
            assert_eq!(xml_double(value).parse::<f64>().unwrap(), value);
        }
        assert_eq!(xml_double(f64::INFINITY), "INF");
        assert_eq!(xml_double(f64::NAN), "NaN");
    }
}
