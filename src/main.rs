//! The `photon` command line: arguments, progress and messages over the library.
//! Every error becomes `error: …` on stderr and exit code 2.

#![forbid(unsafe_code)]

mod cli;

use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    let args = cli::Cli::parse();
    match cli::run(args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // The chain of causes, leaving out those the message already quotes.
            let mut message = e.to_string();
            for cause in e.chain().skip(1) {
                let text = cause.to_string();
                if !message.contains(&text) {
                    message = format!("{message}: {text}");
                }
            }
            // The library names a setting by its key; here it is a flag.
            for cause in e.chain() {
                match cause.downcast_ref::<photon::Error>() {
                    Some(p @ photon::Error::Setting(s)) => {
                        message = message.replace(&p.to_string(), &cli::describe_setting_error(s));
                    }
                    Some(photon::Error::PhotonMapSceneMismatch { .. }) => {
                        message = format!("{message}; use --force to use it anyway");
                    }
                    _ => {}
                }
            }
            eprintln!("error: {message}");
            ExitCode::from(2)
        }
    }
}
