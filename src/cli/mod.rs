//! Subcommands of the `tessera` binary: argument structs and their `run` functions.

pub mod animate;
pub mod bench;
pub mod bench_creases;
pub mod bench_gregory;
pub mod compare;
pub mod error;
pub mod glyphs;
pub mod image_out;
pub mod info;
pub mod limit;
pub mod limits;
pub mod logger;
pub mod render;
pub mod sample;
pub mod stream;
