//! Output of the scene and numerics commands: number formatting for every command
//! ([`format`]), Markdown tables and JSON of a run and of the six cases ([`report`]), their figures ([`plots`]), and the numerics reports' figures
//! ([`numerics_plots`]); one figure style for every figure of the tool ([`style`]). (`recorded`,
//! `map` and `fit` keep their own output beside their computation, in that style.)

pub mod format;
pub mod numerics_plots;
pub mod plots;
pub mod report;
pub mod style;

/// Fails now, before a long computation, where a file an option names for output cannot be
/// written (a missing directory, no permission): the file is opened for writing, created empty
/// if it did not exist; an existing one is left as it is until its output is written.
pub fn check_writable(path: &std::path::Path, what: &str) -> crate::error::Result<()> {
    std::fs::OpenOptions::new()
        .append(true)
        .create(true)
        .open(path)
        .map(|_| ())
        .map_err(|e| crate::error::HostError::Output(format!("{}: cannot write the {what}: {e}", path.display())))
}
