//! Running the `sercon` binary in the ring tests.

use std::process::{Command, Output};

/// Runs `sercon args…` from the crate's folder and waits for it.
pub fn sercon(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_sercon"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("sercon runs")
}
