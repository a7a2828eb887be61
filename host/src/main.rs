//! `stickslip`: the desktop tool of the stick-slip model (see `stickslip --help`).


use std::io::Write;
use std::process::ExitCode;

use clap::Parser;

use stickslip::cli::parse::OutOfRange;
use stickslip::cli::{Cli, Command, RunOptions, SimulateArgs};
use stickslip::commands;
use stickslip::scenes::run;

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(c) => c,
        Err(e) => {
            use clap::error::ErrorKind;
            if matches!(e.kind(), ErrorKind::DisplayHelp | ErrorKind::DisplayVersion) {
                let _ = e.print();
                return ExitCode::SUCCESS;
            }
            // A value out of its option's range: the parser's own line (`--OPTION VALUE: rule`).
            if let Some(r) = std::error::Error::source(&e).and_then(|s| s.downcast_ref::<OutOfRange>()) {
                eprintln!("error: {r}");
                return ExitCode::from(2);
            }
            // One line: clap's message up to its first blank line (it starts with "error: "),
            // without the usage block.
            let text = e.render().to_string();
            let msg: Vec<&str> = text
                .lines()
                .skip_while(|l| l.trim().is_empty())
                .take_while(|l| !l.trim().is_empty())
                .map(str::trim)
                .collect();
            let msg = if msg.is_empty() {
                "error: bad command line".to_string()
            } else {
                msg.join(" ")
            };
            eprintln!("{msg} (see --help)");
            return ExitCode::from(2);
        }
    };
    let command = cli.command.unwrap_or_else(|| {
        Command::Simulate(SimulateArgs {
            scene: stickslip::cli::DEFAULT_SCENE.into(),
            csv: None,
            json: false,
            grid: false,
            events: false,
            run: RunOptions {
                dt: None,
                duration: None,
                stats_from: None,
                precision: run::Precision::F64,
            },
        })
    });
    let result = match &command {
        Command::Simulate(a) => commands::simulate(a),
        Command::Cases(a) => commands::cases(a),
        Command::Scenes(a) => commands::scenes(a),
        Command::Accuracy(a) => commands::accuracy(a),
        Command::Stability(a) => commands::stability(a),
        Command::Analyze(a) => commands::analyze(a),
        Command::Sil(a) => commands::sil(a),
        Command::Compare(a) => commands::compare(a),
        Command::Map(a) => commands::map(a),
        Command::Fit(a) => commands::fit(a),
        Command::Decode(a) => commands::decode(a),
        Command::Record(a) => commands::record(a),
    };
    match result {
        Ok(out) => {
            let mut stdout = std::io::stdout().lock();
            match stdout
                .write_all(out.as_bytes())
                .and_then(|_| stdout.flush())
            {
                Ok(()) => ExitCode::SUCCESS,
                // A closed pipe (`| head`) is not an error worth a message.
                Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => ExitCode::SUCCESS,
                Err(e) => {
                    eprintln!("error: cannot write to stdout: {e}");
                    ExitCode::from(1)
                }
            }
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(e.exit_code())
        }
    }
}
