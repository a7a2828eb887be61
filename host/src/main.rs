//! `stickslip`: the desktop tool of the stick-slip model (see `stickslip --help`).


use std::io::Write;
use std::process::ExitCode;

use stickslip::cli::invoke::{self, Parsed};
use stickslip::commands;

fn main() -> ExitCode {
    let command = match invoke::parse(std::env::args_os()) {
        Ok(Parsed::Run(c)) => c,
        Ok(Parsed::Help(h)) => {
            let _ = h.print();
            return ExitCode::SUCCESS;
        }
        Err(line) => {
            eprintln!("{line}");
            return ExitCode::from(2);
        }
    };
    let result = commands::run(&command);
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
