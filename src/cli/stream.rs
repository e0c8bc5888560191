//! Streamed text output of the subcommands that write one line per sample (`limit`, `sample`):
//! the work is cut into units, evaluated block by block in parallel and written in order, so
//! memory stays bounded (one block of text, a few MB) whatever the number of lines, with a
//! progress line on stderr once a run takes longer than a couple of seconds.

use std::io::Write;
use std::path::Path;
use std::time::{Duration, Instant};

use rayon::prelude::*;
use tessera::{Error, Result};

/// Lines (samples) evaluated and formatted per block before it is written.
pub const BLOCK_LINES: u64 = 32 * 1024;

/// The `Error::Write` of `path`.
pub fn write_error(path: &str, e: impl std::fmt::Display) -> Error {
    Error::Write {
        path: path.to_string(),
        message: e.to_string(),
    }
}

/// A buffered writer on `path`, or on standard output; and the name used in messages.
pub fn open_output(path: Option<&Path>) -> Result<(Box<dyn Write>, String)> {
    match path {
        Some(path) => {
            let name = path.display().to_string();
            let file = std::fs::File::create(path).map_err(|e| write_error(&name, e))?;
            Ok((Box::new(std::io::BufWriter::new(file)), name))
        }
        None => Ok((
            Box::new(std::io::BufWriter::new(std::io::stdout().lock())),
            "<stdout>".to_string(),
        )),
    }
}

/// Progress of a long run on stderr: nothing for the first [`Progress::QUIET_FOR`], then one
/// line at most every [`Progress::EVERY`] with the fraction done and the time left.
pub struct Progress {
    label: &'static str,
    total: u64,
    done: u64,
    start: Instant,
    last: Option<Instant>,
    quiet: bool,
}

impl Progress {
    /// How long a run stays silent.
    pub const QUIET_FOR: Duration = Duration::from_secs(2);
    /// Interval between progress lines.
    pub const EVERY: Duration = Duration::from_secs(5);

    /// Progress over `total` units of work called `label` (e.g. "samples"); silent if `quiet`.
    pub fn new(label: &'static str, total: u64, quiet: bool) -> Progress {
        Progress {
            label,
            total,
            done: 0,
            start: Instant::now(),
            last: None,
            quiet,
        }
    }

    /// Counts `n` more units done; prints a line when due.
    pub fn advance(&mut self, n: u64) {
        self.done += n;
        let now = Instant::now();
        let elapsed = now - self.start;
        let due = match self.last {
            None => elapsed >= Self::QUIET_FOR,
            Some(t) => now - t >= Self::EVERY,
        };
        if self.quiet || !due || self.total == 0 {
            return;
        }
        self.last = Some(now);
        let frac = (self.done as f64 / self.total as f64).min(1.0);
        let left = if frac > 0.0 {
            elapsed.as_secs_f64() * (1.0 - frac) / frac
        } else {
            f64::NAN
        };
        eprintln!(
            "progress: {} of {} {} ({:.1}%), {:.0} s elapsed, about {:.0} s left",
            self.done,
            self.total,
            self.label,
            100.0 * frac,
            elapsed.as_secs_f64(),
            left
        );
    }

    /// Says the run is complete, if progress was shown.
    pub fn finish(&self) {
        if self.last.is_some() && !self.quiet {
            eprintln!(
                "progress: {} {} done in {:.1} s",
                self.done,
                self.label,
                self.start.elapsed().as_secs_f64()
            );
        }
    }
}

/// Formats `units` in parallel, block by block (each block at most about [`BLOCK_LINES`] lines
/// as `lines` counts them), and writes their text to `w` in order. `format` appends one unit's
/// lines to the string it is given.
pub fn write_ordered<T, I, F>(
    units: I,
    lines: impl Fn(&T) -> u64,
    format: F,
    w: &mut dyn Write,
    name: &str,
    progress: &mut Progress,
) -> Result<()>
where
    T: Send + Sync,
    I: Iterator<Item = T>,
    F: Fn(&T, &mut String) -> Result<()> + Sync,
{
    let mut units = units.peekable();
    let mut block: Vec<T> = Vec::new();
    while units.peek().is_some() {
        block.clear();
        let mut count = 0u64;
        while count < BLOCK_LINES {
            let Some(u) = units.next() else { break };
            count += lines(&u);
            block.push(u);
        }
        let texts: Vec<String> = block
            .par_iter()
            .map(|u| {
                let mut s = String::new();
                format(u, &mut s).map(|()| s)
            })
            .collect::<Result<_>>()?;
        for t in &texts {
            w.write_all(t.as_bytes())
                .map_err(|e| write_error(name, e))?;
        }
        progress.advance(count);
    }
    w.flush().map_err(|e| write_error(name, e))?;
    progress.finish();
    Ok(())
}
