//! `scenes` and `scenes show`.

use clap::{Args, Subcommand};

#[derive(Debug, Args)]
pub struct ScenesArgs {
    #[command(subcommand)]
    pub action: Option<ScenesAction>,
}

#[derive(Debug, Subcommand)]
pub enum ScenesAction {
    /// Print a scene as a complete TOML scene file (every key, with unit and meaning), which
    /// `simulate FILE` accepts unchanged
    Show {
        /// Built-in scene name, or a scene file to print in full
        #[arg(value_name = "NAME|FILE")]
        name: String,
    },
}
