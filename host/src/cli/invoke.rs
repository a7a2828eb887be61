//! A command line from its argument strings to a [`Command`], and what an argument error says:
//! `main` and the Python module (host/python) both parse through here, so a notebook gets the
//! same one-line message as the shell.

use clap::error::ErrorKind;
use clap::Parser;

use super::parse::OutOfRange;
use super::{Cli, Command, RunOptions, SimulateArgs, DEFAULT_SCENE};
use crate::scenes::run::Precision;

/// The long flags of `command` (a subcommand path such as `["map"]` or `["map", "merge"]`)
/// that take no value (switches such as `--json`), without their `--`; None for a command
/// that does not exist. For the Python module, which tells a switch from a flag with a value.
pub fn switches(command: &[&str]) -> Option<Vec<String>> {
    use clap::CommandFactory;
    let mut c = Cli::command();
    for name in command {
        c = c.find_subcommand(name)?.clone();
    }
    Some(
        c.get_arguments()
            .filter(|a| !a.get_action().takes_values())
            .filter_map(|a| a.get_long().map(str::to_string))
            .collect(),
    )
}

/// What the arguments ask for.
pub enum Parsed {
    /// A command to run (no subcommand: `simulate` of the default scene).
    Run(Command),
    /// `--help` or `--version`: the text to print, and the exit is a success.
    Help(clap::Error),
}

/// Parses `argv` (the program's name first, as `std::env::args`). An argument error is the one
/// line the tool prints (it starts with `error: `); its exit code is 2.
pub fn parse<I, T>(argv: I) -> Result<Parsed, String>
where
    I: IntoIterator<Item = T>,
    T: Into<std::ffi::OsString> + Clone,
{
    match Cli::try_parse_from(argv) {
        Ok(c) => Ok(Parsed::Run(c.command.unwrap_or_else(default_command))),
        Err(e) if matches!(e.kind(), ErrorKind::DisplayHelp | ErrorKind::DisplayVersion) => Ok(Parsed::Help(e)),
        Err(e) => Err(argument_error(&e)),
    }
}

/// The command run when none is given: `simulate` of the default scene.
pub fn default_command() -> Command {
    Command::Simulate(SimulateArgs {
        scene: DEFAULT_SCENE.into(),
        csv: None,
        json: false,
        grid: false,
        events: false,
        run: RunOptions { dt: None, duration: None, stats_from: None, precision: Precision::F64 },
    })
}

/// One line for an argument error: a value out of its option's range gives the parser's own
/// line (`--OPTION VALUE: rule`); any other, clap's message up to its first blank line (it
/// starts with "error: "), without the usage block.
fn argument_error(e: &clap::Error) -> String {
    if let Some(r) = std::error::Error::source(e).and_then(|s| s.downcast_ref::<OutOfRange>()) {
        return format!("error: {r}");
    }
    let text = e.render().to_string();
    let msg: Vec<&str> = text
        .lines()
        .skip_while(|l| l.trim().is_empty())
        .take_while(|l| !l.trim().is_empty())
        .map(str::trim)
        .collect();
    if msg.is_empty() {
        "error: bad command line (see --help)".to_string()
    } else {
        format!("{} (see --help)", msg.join(" "))
    }
}

#[cfg(test)]
mod switch_tests {
    use super::switches;

    #[test]
    fn switches_are_the_flags_that_take_no_value() {
        let map = switches(&["map"]).expect("map exists");
        assert!(map.contains(&"json".to_string()) && map.contains(&"step-stick".to_string()), "{map:?}");
        assert!(!map.iter().any(|f| f == "sweep" || f == "jobs"), "{map:?}");
        assert!(switches(&["map", "merge"]).is_some());
        assert_eq!(switches(&["no-such-command"]), None);
    }
}
