//! Subcommands of the `tessera` binary: argument structs and their `run` functions.

pub mod error;
pub mod info;
pub mod limit;
