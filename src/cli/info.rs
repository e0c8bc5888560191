//! `tessera info`.

use clap::Args;

/// Arguments of `tessera info`.
#[derive(Args)]
pub struct InfoArgs {
    /// Control mesh (OBJ with OpenSubdiv tags).
    pub mesh: std::path::PathBuf,
}

/// Runs the subcommand.
pub fn run(_args: InfoArgs) -> tessera::Result<()> {
    Err(tessera::Error::Invalid("`tessera info` is being written".into()))
}
