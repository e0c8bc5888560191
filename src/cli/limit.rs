//! `tessera limit`.

use clap::Args;

/// Arguments of `tessera limit`.
#[derive(Args)]
pub struct LimitArgs {
    /// Control mesh (OBJ with OpenSubdiv tags).
    pub mesh: std::path::PathBuf,
}

/// Runs the subcommand.
pub fn run(_args: LimitArgs) -> tessera::Result<()> {
    Err(tessera::Error::Invalid("`tessera limit` is being written".into()))
}
