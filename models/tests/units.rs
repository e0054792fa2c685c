//! Units end to end: `models params` shows the units and docs of states and outputs,
//! a run writes the units of its CSV's columns in a side file (the CSV's header stays
//! plain names), and the trajectory figures' y axes carry the unit.

mod common;

use std::fs;

use common::{assert_success, run, scratch, Csv};
use models::quick_return::results::{header as spec_header, COLUMNS};

/// The whitespace-separated cells of the line of `text` that starts with `name `
/// (after its indentation).
fn row<'a>(text: &'a str, name: &str) -> Vec<&'a str> {
    text.lines()
        .map(str::trim_start)
        .find(|l| l.split_whitespace().next() == Some(name))
        .unwrap_or_else(|| panic!("no row {name} in\n{text}"))
        .split_whitespace()
        .collect()
}

#[test]
fn params_shows_the_units_and_docs_of_states_and_outputs() {
    let out = run(&["params", "oscillator", "--states", "--outputs"]);
    assert_success(&out);
    let text = &out.stdout;
    // name, initial value, unit, meaning
    assert_eq!(row(text, "spring.q")[..3], ["spring.q", "0.05", "m"]);
    assert_eq!(row(text, "mass.p")[..3], ["mass.p", "0", "kg·m/s"]);
    // name, unit, meaning
    assert_eq!(
        row(text, "spring_force")[..3],
        ["spring_force", "N", "Force"]
    );
    assert_eq!(row(text, "energy")[..2], ["energy", "J"]);

    let out = run(&["params", "quick_return", "--states", "--outputs"]);
    assert_success(&out);
    assert_eq!(row(&out.stdout, "Tc_z")[1], "N·m");
    assert_eq!(row(&out.stdout, "crank.rotation.p_z")[2], "kg·m²/s");
    // A coupling's deflection has no declared unit: the meaning follows the value.
    assert_eq!(row(&out.stdout, "j01.spring.q_x")[2], "deflection:");
}

#[test]
fn a_run_writes_the_units_of_its_columns_beside_the_csv() {
    let dir = scratch("units_trajectory");
    let out = run(&[
        "run",
        "dc_motor",
        "--t-end",
        "0.2",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_success(&out);
    // The summary's table of columns ends each row with the unit.
    assert_eq!(row(&out.stdout, "motor_speed").last(), Some(&"rad/s"));
    assert_eq!(row(&out.stdout, "energy").last(), Some(&"J"));
    let csv = Csv::read(&dir.join("dc_motor.csv"));
    let units = fs::read_to_string(dir.join("dc_motor.units.csv")).unwrap();
    let lines: Vec<&str> = units.lines().collect();
    assert_eq!(lines[0], "column,unit,description");
    let columns: Vec<&str> = lines[1..]
        .iter()
        .map(|l| l.split(',').next().unwrap())
        .collect();
    assert_eq!(columns, csv.header, "one row per column, in order");
    assert_eq!(lines[1], "t,s,time");
    let unit_of = |name: &str| {
        lines
            .iter()
            .find(|l| l.starts_with(&format!("{name},")))
            .unwrap()
            .split(',')
            .nth(1)
            .unwrap()
            .to_owned()
    };
    assert_eq!(unit_of("coil.p"), "Wb");
    assert_eq!(unit_of("motor_speed"), "rad/s");
    assert_eq!(unit_of("shaft_torque"), "N·m");

    // The figure's y axis names the unit.
    let svg = fs::read_to_string(dir.join("motor_speed.svg")).unwrap();
    assert!(svg.contains("motor_speed (rad/s)"), "no unit on the y axis");
}

#[test]
fn the_quick_return_keeps_its_spec_header_and_lists_units_aside() {
    let dir = scratch("units_quick_return");
    let out = run(&[
        "run",
        "quick_return",
        "--t-end",
        "0.02",
        "--no-plots",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_success(&out);
    let csv = fs::read_to_string(dir.join("quick_return.csv")).unwrap();
    assert_eq!(csv.lines().next().unwrap(), spec_header());
    let units = fs::read_to_string(dir.join("quick_return.units.csv")).unwrap();
    assert_eq!(units.lines().count(), 1 + COLUMNS.len());
    for (line, expected) in units
        .lines()
        .skip(1)
        .zip(["t,s,time", "crank_angle,rad,Crank angle about Z0: atan2 of R1 plus the crank's whole turns (unwrapped)"])
    {
        assert_eq!(line, expected);
    }
    let tc_z = units.lines().find(|l| l.starts_with("Tc_z,")).unwrap();
    assert!(tc_z.starts_with("Tc_z,N·m,"), "{tc_z}");
    // Every column of the spec file has a unit (the rotation matrices' is 1).
    for line in units.lines().skip(1) {
        assert!(!line.split(',').nth(1).unwrap().is_empty(), "{line}");
    }
}
