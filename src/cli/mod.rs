//! Subcommands of the `photon` binary, one file each.

mod compare;
mod model;
mod photons;
mod progress;
mod progressive;
mod render;
mod validate;

use anyhow::Result;
use clap::{Parser, Subcommand};
use photon::description::builtin::BUILTINS;
use photon::description::{RenderSpec, load_scene};
use photon::scene::Scene;

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
    /// List the built-in scenes, or write one (or any scene file) as a TOML scene.
    Scenes(ScenesArgs),
    /// Render the validation scenes with every integrator and compare them with their
    /// references: time, relMSE, mean ratios and the worst region, as a table.
    Validate(validate::ValidateArgs),
}

pub fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Render(args) => render::run(*args),
        Command::Compare(args) => compare::run(&args),
        Command::Photons { command } => photons::run(command),
        Command::Model(args) => model::run(&args),
        Command::Merge(args) => progressive::merge(&args),
        Command::Scenes(args) => scenes(&args),
        Command::Validate(args) => validate::run_suite(&args),
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

#[derive(clap::Args)]
pub struct ScenesArgs {
    /// Write this scene (a built-in name or a scene file) as a .toml scene file.
    #[arg(long, value_name = "SCENE", requires = "output")]
    export: Option<String>,
    /// The .toml file to write with --export.
    #[arg(short, long)]
    output: Option<std::path::PathBuf>,
}

fn scenes(a: &ScenesArgs) -> Result<()> {
    let (Some(name), Some(out)) = (&a.export, &a.output) else {
        for b in BUILTINS {
            println!("{:<14} {}", b.name, b.description);
        }
        println!("\nor a scene file: SCENE.toml (docs/scene-format.md), SCENE.gltf or SCENE.glb");
        return Ok(());
    };
    if out.extension().and_then(|e| e.to_str()) != Some("toml") {
        anyhow::bail!("'{}': --export writes a .toml file", out.display());
    }
    let loaded = photon::description::load(name)?;
    print_warnings(&loaded.warnings);
    let dir = out.parent().filter(|d| !d.as_os_str().is_empty());
    let dir = std::path::absolute(dir.unwrap_or(std::path::Path::new(".")))?;
    let mut desc = loaded.desc;
    desc.base_dir = if desc.base_dir.as_os_str().is_empty() {
        // Built-ins name no files; a scene file's names are relative to its directory.
        dir.clone()
    } else {
        std::path::absolute(&desc.base_dir)?
    };
    let text = photon::description::toml_write::to_toml(&desc, &dir)?;
    photon::io::image::write_atomically(out, |tmp| {
        std::fs::write(tmp, &text).map_err(|source| photon::Error::Write {
            path: out.clone(),
            source,
        })
    })?;
    eprintln!("photon: wrote scene '{}' to {}", desc.name, out.display());
    Ok(())
}

fn print_warnings(warnings: &[String]) {
    for w in warnings {
        eprintln!("warning: {w}");
    }
}

/// Load a scene by built-in name or file, printing what the loader could not map. Also
/// returns the seconds it took (reading files, building the BVH).
pub fn scene(name_or_path: &str) -> Result<(Scene, RenderSpec, f64)> {
    let start = std::time::Instant::now();
    let (scene, loaded) = load_scene(name_or_path)?;
    print_warnings(&loaded.warnings);
    Ok((scene, loaded.desc.render, start.elapsed().as_secs_f64()))
}
