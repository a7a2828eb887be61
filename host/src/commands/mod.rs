//! The commands: [`run`] dispatches a parsed command (for `main` and for the Python module).
//! Each returns what goes to stdout; errors go back to the caller. The commands themselves live
//! in one module per command family.

use crate::cli::{Command, RunOptions};
use crate::error::Result;
use crate::scenes::scene_source::Overrides;

mod cases;
mod fit;
mod map;
mod numerics;
mod recordings;
mod simulate;

pub use cases::cases;
pub use fit::fit;
pub use map::map;
pub use numerics::{accuracy, stability};
pub use recordings::{analyze, compare, decode, record, sil};
pub use simulate::{scenes, simulate};

/// [`run`] with `token` as the command's cancellation ([`crate::cancel`]): cancelled, it ends
/// at its next cancellation point with [`crate::error::HostError::Cancelled`].
pub fn run_cancellable(command: &Command, token: crate::cancel::Cancel) -> Result<String> {
    crate::cancel::with(Some(token), || run(command))
}

/// Runs one parsed command: what it prints on stdout, or its error.
pub fn run(command: &Command) -> Result<String> {
    match command {
        Command::Simulate(a) => simulate(a),
        Command::Cases(a) => cases(a),
        Command::Scenes(a) => scenes(a),
        Command::Accuracy(a) => accuracy(a),
        Command::Stability(a) => stability(a),
        Command::Analyze(a) => analyze(a),
        Command::Sil(a) => sil(a),
        Command::Compare(a) => compare(a),
        Command::Map(a) => map(a),
        Command::Fit(a) => fit(a),
        Command::Decode(a) => decode(a),
        Command::Record(a) => record(a),
    }
}

pub(crate) fn overrides(o: &RunOptions) -> Overrides {
    Overrides {
        dt: o.dt,
        duration: o.duration,
        stats_from: o.stats_from,
    }
}

pub(crate) fn to_json<T: serde::Serialize>(v: &T) -> String {
    // Serializing plain structs of numbers and strings cannot fail; no NaN reaches here
    // (non-finite values are None, printed as null).
    let mut s =
        serde_json::to_string_pretty(v).unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"));
    s.push('\n');
    s
}

pub(crate) fn stderr_is_terminal() -> bool {
    use std::io::IsTerminal;
    std::io::stderr().is_terminal()
}

