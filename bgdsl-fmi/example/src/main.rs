//! Packs the room's FMU: `bgdsl-fmi-example [OUT]` writes `OUT` (default `room.fmu`)
//! with the shared library built beside this program, and prints its path.

use std::path::PathBuf;
use std::process::ExitCode;

fn main() -> ExitCode {
    let out = std::env::args_os()
        .nth(1)
        .map_or_else(|| PathBuf::from("room.fmu"), PathBuf::from);
    match room_fmu::find_library().and_then(|library| room_fmu::write_fmu(&library, &out)) {
        Ok(written) => {
            println!("{}", written.display());
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
