//! Subcommands of the `photon` binary, one file each.

mod compare;
mod model;
mod photons;
mod progress;
mod progressive;
mod render;

use anyhow::Result;
use clap::{Parser, Subcommand};
use photon::scene::builtin::BUILTINS;

#[derive(Parser)]
#[command(
    name = "photon",
    version,
    about = "Photon: a photon-mapping global-illumination renderer"
)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene to an image (.png, .exr or .pfm, chosen by the extension).
    Render(Box<render::RenderArgs>),
    /// Print how far one image is from a reference: RMSE, relMSE and mean ratio per channel.
    Compare(compare::CompareArgs),
    /// Photon maps: trace and save them, describe a saved file, export it as a PLY point cloud.
    Photons {
        #[command(subcommand)]
        command: photons::PhotonsCommand,
    },
    /// Merge partial progressive renders (`--integrator ppm --pass-range a..b`) into one image.
    Merge(progressive::MergeArgs),
    /// Write a procedural model (the plant pot) as OBJ or PLY.
    Model(model::ModelArgs),
    /// List the built-in scenes.
    Scenes,
}

pub fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Render(args) => render::run(*args),
        Command::Compare(args) => compare::run(&args),
        Command::Photons { command } => photons::run(command),
        Command::Model(args) => model::run(&args),
        Command::Merge(args) => progressive::merge(&args),
        Command::Scenes => {
            for b in BUILTINS {
                println!("{:<14} {}", b.name, b.description);
            }
            Ok(())
        }
    }
}

/// Worker pool with `threads` threads (0 or `None`: one per core).
pub fn thread_pool(threads: Option<usize>) -> Result<rayon::ThreadPool> {
    use anyhow::Context;
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads.unwrap_or(0))
        .build()
        .context("cannot start worker threads")
}
