//! `sercon capture`: placeholder until the capture decoder lands.

use clap::Subcommand;

/// Subcommands of `sercon capture`.
#[derive(Debug, Subcommand)]
pub enum CaptureCommand {
    /// Decode every telegram of a capture file.
    Decode {
        /// The capture file.
        file: std::path::PathBuf,
    },
}

/// Runs a capture subcommand.
pub fn run(_cmd: CaptureCommand) -> anyhow::Result<()> {
    anyhow::bail!("sercon capture is not built yet")
}
