//! The tool's error: one line for the user, and the exit code it maps to.

use std::fmt;

/// What went wrong, already phrased for the user (without the leading `error: `).
#[derive(Debug)]
pub enum HostError {
    /// Bad input: a scene name, a scene file, an option value. Exit code 2.
    Input(String),
    /// An output could not be written (CSV, SVG). Exit code 1.
    Output(String),
    /// A bound of a report's `--check` failed. Exit code 3.
    Check(String),
    /// The connection to the board (the debug probe) was lost while recording. Exit code 4.
    Link(String),
    /// The command was cancelled from outside ([`crate::cancel`]: the Python module's Ctrl-C).
    /// Exit code 130, as for a process that SIGINT ended.
    Cancelled,
}

impl HostError {
    pub fn exit_code(&self) -> u8 {
        match self {
            HostError::Input(_) => 2,
            HostError::Output(_) => 1,
            HostError::Check(_) => 3,
            HostError::Link(_) => 4,
            HostError::Cancelled => 130,
        }
    }
}

impl fmt::Display for HostError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let msg = match self {
            HostError::Input(m) | HostError::Output(m) | HostError::Check(m) | HostError::Link(m) => m,
            HostError::Cancelled => "cancelled",
        };
        // Always one line: fold any line breaks a library put in its message.
        let mut first = true;
        for part in msg.lines().map(str::trim).filter(|l| !l.is_empty()) {
            if !first {
                f.write_str(" ")?;
            }
            f.write_str(part)?;
            first = false;
        }
        Ok(())
    }
}

pub type Result<T> = std::result::Result<T, HostError>;
