//! `sercon script`: placeholder until the controller model's script runner lands.

use clap::Args;

/// Arguments of `sercon script`.
#[derive(Debug, Args)]
pub struct ScriptArgs {
    /// The script file.
    pub file: std::path::PathBuf,
}

/// Runs a script.
pub fn run(_args: ScriptArgs) -> anyhow::Result<()> {
    anyhow::bail!("sercon script is not built yet")
}
