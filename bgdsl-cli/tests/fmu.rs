//! `fmu` of a program's own models: it packs the shared library of the catalogue's
//! package (`lib<package>.so`, `-` as `_`), and without it fails as a missing
//! prerequisite (exit status 69) that names the library, the command that builds it and
//! where it looked, creating nothing. (CI's `.ci/starter` packs a real one and runs it
//! in FMPy, and tries a library built from other model code.)

use std::path::PathBuf;
use std::sync::LazyLock;

use bgdsl_cli::cli::{execute, Cli, Command};
use bgdsl_cli::Catalogue;
use bgdsl_runtime::bond_graph;

bond_graph! {
    /// A capacitor discharging through a resistor.
    pub model Discharge {
        /// resistance
        param r = 1000.0 in "Ω";
        /// capacitance
        param c = 1.0e-6 in "F";
        C cap = 1.0 / c, q in "C";
        R res = r;
        0 node;
        node -> { cap, res };
        init cap.q = 1.0e-6;
        /// Voltage across the capacitor, V.
        output voltage = cap.e in "V";
    }
}

/// A program of a package that nobody built.
static CATALOGUE: LazyLock<Catalogue> =
    LazyLock::new(|| Catalogue::new("no-such-fmi-package").model::<Discharge>());

#[test]
fn fmu_without_the_packages_library_names_it_and_the_build_command() {
    if std::env::var_os(bgdsl_fmi_core::LIBRARY_ENV).is_some() {
        eprintln!("\n!!! SKIPPED: {} is set\n", bgdsl_fmi_core::LIBRARY_ENV);
        return;
    }
    let out = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("fmu-{}", std::process::id()))
        .join("discharge.fmu");
    let cli = Cli {
        command: Some(Command::Fmu {
            model: "discharge".to_owned(),
            out: Some(out.clone()),
        }),
    };
    let failure = execute(cli, &CATALOGUE).unwrap_err();
    assert_eq!(failure.exit_code(), 69, "{failure}");
    let message = failure.to_string();
    let file = format!(
        "{}no_such_fmi_package{}",
        std::env::consts::DLL_PREFIX,
        std::env::consts::DLL_SUFFIX
    );
    assert!(
        message.starts_with(&format!("the FMI shared library {file} was not found")),
        "{message}"
    );
    assert!(
        message.contains("`cargo build -p no-such-fmi-package --release`"),
        "{message}"
    );
    // Where it looked: beside this test program first.
    let exe = std::env::current_exe().unwrap();
    let beside = exe.with_file_name(&file);
    assert!(message.contains(&beside.display().to_string()), "{message}");
    assert!(!out.parent().unwrap().exists(), "nothing is created");
}

#[test]
fn fmu_of_an_unknown_model_is_a_usage_error_listing_the_models() {
    let cli = Cli {
        command: Some(Command::Fmu {
            model: "pump".to_owned(),
            out: None,
        }),
    };
    let failure = execute(cli, &CATALOGUE).unwrap_err();
    assert_eq!(failure.exit_code(), 2, "{failure}");
    assert!(failure.to_string().contains("discharge"), "{failure}");
}
