//! The render settings' flags, made from the library's one table of settings
//! (`photon::settings::SETTINGS`): name, help, default, value type and group.

use clap::builder::PossibleValuesParser;
use clap::{Arg, ArgAction, ArgMatches, Command};
use photon::settings::{RenderOptions, SETTINGS, Setting};

/// Every render setting as a flag of `photon render` (and `photon job create`).
#[derive(Clone, Debug, Default)]
pub struct SettingFlags(pub RenderOptions);

fn flag(s: &'static Setting) -> Arg {
    let arg = Arg::new(s.name)
        .long(s.name.replace('_', "-"))
        .help(format!("{} [default: {}]", s.help.trim(), s.default_text()))
        .help_heading(s.group.heading());
    if s.is_switch {
        return arg.action(ArgAction::SetTrue);
    }
    let arg = arg.value_name(s.metavar).action(ArgAction::Set);
    if s.choices.is_empty() {
        arg.value_parser(move |text: &str| {
            RenderOptions::default()
                .set_text(s.name, text)
                .map(|()| text.to_owned())
                .map_err(|e| e.problem)
        })
    } else {
        arg.value_parser(PossibleValuesParser::new(s.choices))
    }
}

impl clap::FromArgMatches for SettingFlags {
    fn from_arg_matches(matches: &ArgMatches) -> Result<Self, clap::Error> {
        let mut options = RenderOptions::default();
        for s in SETTINGS {
            let set = if s.is_switch {
                if !matches.get_flag(s.name) {
                    continue;
                }
                options.set_json(s.name, serde_json::Value::Bool(true))
            } else {
                let Some(text) = matches.get_one::<String>(s.name) else {
                    continue;
                };
                options.set_text(s.name, text)
            };
            set.map_err(|e| {
                clap::Error::raw(
                    clap::error::ErrorKind::InvalidValue,
                    format!("--{}: {}\n", s.name.replace('_', "-"), e.problem),
                )
            })?;
        }
        Ok(Self(options))
    }

    fn update_from_arg_matches(&mut self, matches: &ArgMatches) -> Result<(), clap::Error> {
        *self = Self::from_arg_matches(matches)?;
        Ok(())
    }
}

impl clap::Args for SettingFlags {
    fn augment_args(cmd: Command) -> Command {
        SETTINGS.iter().fold(cmd, |cmd, s| cmd.arg(flag(s)))
    }

    fn augment_args_for_update(cmd: Command) -> Command {
        Self::augment_args(cmd)
    }
}

/// A setting error as the command line names it: `--radius 0: must be a positive number`.
pub fn describe(e: &photon::error::SettingError) -> String {
    if e.name.is_empty() {
        return e.problem.clone();
    }
    let flag = format!("--{}", e.name.replace('_', "-"));
    match &e.value {
        Some(v) => format!("{flag} {v}: {}", e.problem),
        None => format!("{flag}: {}", e.problem),
    }
}
