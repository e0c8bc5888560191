//! Subcommands of the `tessera` binary: argument structs and their `run` functions.

pub mod info;
pub mod limit;
