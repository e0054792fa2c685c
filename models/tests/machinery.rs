//! Tests of the program's machinery (`bgdsl-cli`: columns, parameters, sweeps, scenario
//! resolution) on the models of this catalogue: units, vector groups and messages of
//! the quick return and its friends. They were unit tests of these modules when they
//! lived in `models`.

mod columns {
    use std::path::Path;

    use models::catalog::{column_unit, find, resolve_columns, units_path, Column};

    #[test]
    fn give_every_column_its_declared_unit() {
        let model = &*find("quick_return").unwrap().model;
        assert_eq!(column_unit(model, "t"), ("s", "time"));
        assert_eq!(column_unit(model, "Tc_z").0, "N·m");
        assert_eq!(column_unit(model, "p5_x").0, "kg·m/s");
        assert_eq!(column_unit(model, "crank.rotation.p_z").0, "kg·m²/s");
        assert_eq!(
            column_unit(model, "j01.spring.q_x").0,
            "",
            "a coupling's unit is not known"
        );
        assert_eq!(
            units_path(Path::new("out/quick_return.partial.csv")),
            Path::new("out/quick_return.partial.units.csv")
        );
    }

    #[test]
    fn resolves_names_and_vector_groups() {
        let model = &*find("quick_return").unwrap().model;
        let tc = resolve_columns(model, "Tc").unwrap();
        let names: Vec<&str> = tc.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(names, ["Tc_x", "Tc_y", "Tc_z"]);
        assert_eq!(resolve_columns(model, "R1").unwrap().len(), 9);
        assert_eq!(resolve_columns(model, "P_in").unwrap().len(), 1);
        assert!(resolve_columns(model, "nothing").is_none());
        let state = model.state_names()[0];
        assert_eq!(
            resolve_columns(model, state).unwrap(),
            [(state.to_owned(), Column::State(0))]
        );
    }
}

mod params {
    use models::catalog::{find, format_number, format_significant, parse_value, set_parameter};
    use serde_yaml::Value;

    #[test]
    fn overrides_a_parameter_of_the_right_shape() {
        let entry = find("quick_return").unwrap();
        let mut params = entry.model.default_parameters();
        set_parameter(
            entry,
            &mut params,
            "l1",
            parse_value("[0.3, 0.02, 0.01]").unwrap(),
        )
        .unwrap();
        set_parameter(entry, &mut params, "K01", parse_value("2e5").unwrap()).unwrap();
        set_parameter(entry, &mut params, "m1", parse_value("1").unwrap()).unwrap();
        let p: models::quick_return::QuickReturnParams =
            serde_yaml::from_value(Value::Mapping(params)).unwrap();
        assert_eq!(p.l1, [0.3, 0.02, 0.01]);
        assert_eq!(p.K01, 2e5);
        assert_eq!(p.m1, 1.0);
    }

    #[test]
    fn rejects_unknown_names_and_wrong_shapes() {
        let entry = find("quick_return").unwrap();
        let mut params = entry.model.default_parameters();
        let unknown = set_parameter(entry, &mut params, "mass", Value::from(1.0)).unwrap_err();
        assert!(unknown
            .message
            .starts_with("unknown parameter `mass`; the parameters of quick_return are: m1, m2,"));
        let short =
            set_parameter(entry, &mut params, "l1", parse_value("[1, 2]").unwrap()).unwrap_err();
        assert_eq!(
            short.message,
            "parameter `l1` must be a list of 3 numbers, like [0.2, 0.01, 0.01] in m, found \
             [1, 2] (a list of 2)"
        );
        let text =
            set_parameter(entry, &mut params, "m1", parse_value("heavy").unwrap()).unwrap_err();
        assert_eq!(
            text.message,
            "parameter `m1` must be a number in kg, found a string \"heavy\""
        );
    }

    #[test]
    fn formats_table_values() {
        assert_eq!(format_significant(49.3641234), "49.3641");
        assert_eq!(format_significant(2.0), "2.00000");
        assert_eq!(format_significant(255.883), "255.883");
        assert_eq!(format_significant(1e-5), "1.00000e-5");
        assert_eq!(format_significant(-0.5), "-0.500000");
        assert_eq!(format_significant(0.0), "0");
    }

    #[test]
    fn formats_numbers_shortest() {
        assert_eq!(format_number(1e5), "100000");
        assert_eq!(format_number(1e-14), "1e-14");
        assert_eq!(format_number(0.5), "0.5");
    }
}

mod sweep {
    use models::catalog::{find, metric_unit};

    #[test]
    fn take_metric_units_from_the_model() {
        let quick = &*find("quick_return").unwrap().model;
        assert_eq!(metric_unit(quick, &["Tc_x", "Tc_y", "Tc_z"]), Some("N·m"));
        assert_eq!(metric_unit(quick, &["F_O1_y"]), Some("N"));
        assert_eq!(metric_unit(quick, &["crank_angle", "Tc_x"]), None);
        let servo = &*find("dc_motor").unwrap().model;
        assert_eq!(metric_unit(servo, &["shaft_torque"]), Some("N·m"));
    }
}

mod resolve {
    use std::path::PathBuf;

    use bgdsl_runtime::Solver;
    use models::catalog::{flagship_solver, shared, Plots, RunPlan};
    use models::quick_return::results::sample_times as spec_times;
    use models::scenario::{parse, resolve, Diagnostics, Job, Overrides, Plan, Scenario};
    use serde_yaml::Value;

    fn plan_of(text: &str, overrides: &Overrides) -> Result<Plan, Diagnostics> {
        let loaded = parse("s.yaml".into(), text.to_owned())?;
        resolve(
            shared(),
            Some(&loaded.source),
            &loaded.scenario,
            overrides,
            "s",
        )
    }

    fn run_plan(plan: Plan) -> RunPlan {
        match plan.job {
            Job::Run(run) => run,
            Job::Sweep(_) | Job::Study(_) => panic!("not a run"),
        }
    }

    #[test]
    fn a_bare_model_runs_the_spec_flagship() {
        let scenario = Scenario {
            model: "quick_return".into(),
            ..Scenario::default()
        };
        let plan = run_plan(
            resolve(
                shared(),
                None,
                &scenario,
                &Overrides::default(),
                "quick_return",
            )
            .unwrap(),
        );
        assert_eq!(plan.times, spec_times(), "exactly k / 1000");
        assert_eq!(plan.solver, flagship_solver());
        assert_eq!(plan.out_dir, PathBuf::from("out/quick_return"));
        assert_eq!(plan.plots, Plots::All);
        assert!(plan.record.is_none() && plan.initial.is_empty());
    }

    #[test]
    fn samples_end_on_the_end_time() {
        let plan = run_plan(
            plan_of(
                "model: oscillator\ntime: {end: 1.0}\noutput: {interval: 0.3}\n",
                &Overrides::default(),
            )
            .unwrap(),
        );
        assert_eq!(plan.times, [0.0, 0.3, 0.6, 0.8999999999999999, 1.0]);
        let plan = run_plan(
            plan_of(
                "model: oscillator\ntime: {start: 1, end: 2}\noutput: {count: 3}\n",
                &Overrides::default(),
            )
            .unwrap(),
        );
        assert_eq!(plan.times, [1.0, 1.5, 2.0]);
    }

    #[test]
    fn flags_override_the_file() {
        let overrides = Overrides {
            set: vec!["m=2".into(), "m=3".into()],
            solver: Some("dopri5".into()),
            rtol: Some(1e-9),
            t_end: Some(2.0),
            no_plots: true,
            ..Overrides::default()
        };
        let plan = run_plan(
            plan_of(
                "model: oscillator\nparameters:\n  m: 5\n  k: 50\nsolver:\n  rtol: 1e-3\n  atol: 1e-12\n",
                &overrides,
            )
            .unwrap(),
        );
        assert_eq!(plan.params.get("m").and_then(Value::as_f64), Some(3.0));
        assert_eq!(plan.params.get("k").and_then(Value::as_f64), Some(50.0));
        let Solver::DormandPrince(o) = plan.solver else {
            panic!()
        };
        assert_eq!((o.rtol, o.atol), (1e-9, 1e-12));
        assert_eq!(*plan.times.last().unwrap(), 2.0);
        assert_eq!(plan.plots, Plots::None);
        assert_eq!(
            plan.out_dir,
            PathBuf::from("out/s-m=3,solver=dopri5,rtol=1e-9,t_end=2"),
            "the flags name the folder"
        );
        let chosen = Overrides {
            out: Some("mine".into()),
            ..overrides
        };
        let plan = run_plan(plan_of("model: oscillator\n", &chosen).unwrap());
        assert_eq!(plan.out_dir, PathBuf::from("mine"), "--out wins");
    }

    #[test]
    fn reports_every_independent_error_at_its_line() {
        let text = "model: oscillator\nparameters:\n  m: 0\ninitial:\n  spring.x: 1\nsolver:\n  \
                    method: rk4\n  rtol: 1e-6\noutput:\n  record: [x, y]\n";
        let d = plan_of(text, &Overrides::default()).unwrap_err();
        let lines: Vec<String> = d.0.iter().map(ToString::to_string).collect();
        assert_eq!(lines.len(), 4, "{lines:#?}");
        assert!(lines[0].starts_with("s.yaml:3:3: parameter `m` (mass, kg) must be > 0"));
        assert!(lines[1].starts_with(
            "s.yaml:5:3: unknown state `spring.x`; the states of oscillator are: mass.p, spring.q"
        ));
        assert!(
            lines[2].starts_with("s.yaml:8:3: rtol does not apply to the fixed-step solver rk4")
        );
        assert!(
            lines[3].starts_with("s.yaml:10:3: unknown state or output `y`"),
            "{}",
            lines[3]
        );
    }

    #[test]
    fn an_empty_parameters_block_is_allowed() {
        assert!(plan_of(
            "model: oscillator\nparameters:\n  # none\n",
            &Overrides::default()
        )
        .is_ok());
    }

    fn lines(d: &Diagnostics) -> Vec<String> {
        d.0.iter().map(ToString::to_string).collect()
    }

    /// Before, the first unknown key stopped the reading (hiding the second, and every
    /// value check); a NaN hid the negative mass; the order was that of the checks.
    #[test]
    fn reports_every_error_in_one_go_in_line_order() {
        let text = "model: quick_return\n\
                    output:\n  record: [Tc]\n  every: 2\n\
                    solver:\n  rtol: 0.5\n  tolerance: 1e-6\n\
                    time:\n  end: soon\n\
                    parameters:\n  m1: .nan\n  m2: -1\n  g: 1e400\n\
                    colour: red\n";
        let d = plan_of(text, &Overrides::default()).unwrap_err();
        let lines = lines(&d);
        let expected = [
            "s.yaml:4:3: output: unknown field `every`, expected one of `interval`, `count`, `record`",
            "s.yaml:6:3: rtol must be in [1e-14, 0.1], found 0.5",
            "s.yaml:7:3: solver: unknown field `tolerance`, expected one of `method`",
            "s.yaml:9:3: time.end: invalid type: string \"soon\", expected f64",
            "s.yaml:11:3: parameter `m1` (crank mass (Table 1), kg) must be finite, found NaN",
            "s.yaml:12:3: parameter `m2` (",
            "s.yaml:13:3: parameter `g`: the number 1e400 overflows",
            "s.yaml:14:1: unknown field `colour`, expected one of `model`",
        ];
        assert_eq!(lines.len(), expected.len(), "{lines:#?}");
        for (line, start) in lines.iter().zip(expected) {
            assert!(
                line.starts_with(start),
                "{line:?} should start with {start:?}"
            );
        }
        assert!(lines[5].contains("must be > 0, found -1"), "{}", lines[5]);
    }

    #[test]
    fn a_number_too_large_says_it_overflows() {
        let overrides = Overrides {
            set: vec!["g=1e400".into()],
            ..Overrides::default()
        };
        let d = plan_of("model: quick_return\n", &overrides).unwrap_err();
        assert_eq!(
            lines(&d),
            [
                "--set g=1e400: parameter `g`: the number 1e400 overflows: the largest finite \
              number is about 1.7976931348623157e308"
            ]
        );
        let d = plan_of(
            "model: oscillator\ntime:\n  end: -1e999\n",
            &Overrides::default(),
        )
        .unwrap_err();
        assert_eq!(
            lines(&d),
            [
                "s.yaml:3:3: time.end: the number -1e999 overflows: the largest finite number is \
              about 1.7976931348623157e308"
            ]
        );
    }

    #[test]
    fn a_file_without_a_model_still_reports_its_other_shape_errors() {
        let d = plan_of("time:\n  ends: 2\n", &Overrides::default()).unwrap_err();
        assert_eq!(
            lines(&d),
            [
                "s.yaml:1:1: missing field `model`",
                "s.yaml:2:3: time: unknown field `ends`, expected `start` or `end`"
            ]
        );
    }

    const SWEEP: &str = "model: oscillator\nsweep:\n  parameters:\n    - name: k\n";

    /// Before, a reversed range swept downwards, a repeated value ran twice, one step was
    /// refused, and `--set` of a swept parameter was silently ignored.
    #[test]
    fn a_sweep_range_must_make_sense() {
        let cases = [
            (
                "      from: 10\n      to: 1\n      steps: 3\n",
                "s.yaml:6:7: `to` (1) is below `from` (10); a sweep goes up: swap them",
            ),
            (
                "      from: 2\n      to: 2\n      steps: 3\n",
                "s.yaml:7:7: `from` and `to` are both 2, so the 3 steps would all be the same run",
            ),
            (
                "      from: 1\n      to: 2\n      steps: 0\n",
                "s.yaml:7:7: `steps` (the number of values, ends included) must be >= 1, found 0",
            ),
            (
                "      from: .nan\n      to: 2\n      steps: 3\n",
                "s.yaml:5:7: `from` must be a finite number, found NaN",
            ),
            (
                "      values: [1, 2, 1]\n",
                "s.yaml:5:7: 1 is listed twice; each value is one run, list it once",
            ),
            (
                "      values: [1, .inf]\n",
                "s.yaml:5:7: every value must be finite, found inf",
            ),
        ];
        for (axis, expected) in cases {
            let text = format!("{SWEEP}{axis}  peaks: [x]\n");
            let d = plan_of(&text, &Overrides::default()).unwrap_err();
            assert_eq!(lines(&d).len(), 1, "{text}\n{d}");
            assert!(lines(&d)[0].starts_with(expected), "{text}\n{d}");
        }
        // One step from a value to itself is one run.
        let text = format!("{SWEEP}      from: 2\n      to: 2\n      steps: 1\n  peaks: [x]\n");
        let Job::Sweep(sweep) = plan_of(&text, &Overrides::default()).unwrap().job else {
            panic!("a sweep");
        };
        assert_eq!(sweep.axes[0].values, [2.0]);
    }

    #[test]
    fn setting_a_swept_parameter_is_an_error_naming_the_sweep() {
        let text = format!("{SWEEP}      values: [1, 2]\n  peaks: [x]\n");
        let overrides = Overrides {
            set: vec!["k=5".into()],
            ..Overrides::default()
        };
        let d = plan_of(&text, &overrides).unwrap_err();
        assert_eq!(
            lines(&d),
            [
                "--set k=5: `k` is swept by the scenario (sweep.parameters[0]), so a value set \
              here would be ignored; drop the --set, or the sweep's axis"
            ]
        );
        let text = format!("model: oscillator\nparameters:\n  k: 5\n{}", &text[18..]);
        let d = plan_of(&text, &Overrides::default()).unwrap_err();
        assert!(
            lines(&d)[0].starts_with("s.yaml:3:3: `k` is swept (sweep.parameters[0])"),
            "{d}"
        );
    }

    /// Before, these ran, drew nothing and showed an empty "Figures" heading.
    #[test]
    fn a_figure_that_would_draw_nothing_is_an_error() {
        let d = plan_of(
            "model: oscillator\noutput:\n  record: [x]\nplots: [x, speed]\n",
            &Overrides::default(),
        )
        .unwrap_err();
        assert_eq!(
            lines(&d),
            [
                "s.yaml:4:1: figure `speed` would draw nothing: `speed` is not recorded; add it \
              to `output.record`"
            ]
        );
        let d = plan_of(
            "model: oscillator\noutput:\n  record: [mass.p]\n",
            &Overrides::default(),
        )
        .unwrap_err();
        assert!(
            lines(&d)[0].starts_with(
                "s.yaml:3:3: `record` names no output, so `plots: all` would draw nothing"
            ),
            "{d}"
        );
        let d = plan_of("model: quick_return\nplots: []\n", &Overrides::default()).unwrap_err();
        assert_eq!(
            lines(&d),
            ["s.yaml:2:1: `plots` lists no figure; write `plots: none` to draw none"]
        );
        // Without figures, recording only a state is fine.
        let no_plots = Overrides {
            no_plots: true,
            ..Overrides::default()
        };
        assert!(plan_of(
            "model: oscillator\noutput:\n  record: [mass.p]\n",
            &no_plots
        )
        .is_ok());
    }

    #[test]
    fn text_keys_take_numbers_as_written() {
        let plan = run_plan(
            plan_of(
                "model: oscillator\ndescription: 2024\n",
                &Overrides::default(),
            )
            .unwrap(),
        );
        assert_eq!(plan.title, "2024");
    }
}
