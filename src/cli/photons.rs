//! `photon photons trace | info | export`.

use super::progress;
use anyhow::{Result, bail};
use clap::{Subcommand, ValueEnum};
use photon::io::phm;
use photon::io::ply::{self, PlyColor, PlyEncoding, PlyFilter};
use photon::photon::{MapKind, PhotonConfig, PhotonMaps, trace_photons};
use std::path::{Path, PathBuf};
use std::time::Instant;

#[derive(Subcommand)]
pub enum PhotonsCommand {
    /// Trace photons through a scene and save the caustic and global maps.
    Trace(TraceArgs),
    /// Describe a saved photon-map file.
    Info {
        /// A .phm file written by `photon photons trace`.
        file: PathBuf,
    },
    /// Write a photon map as a PLY point cloud (MeshLab, Blender, CloudCompare).
    Export(ExportArgs),
}

#[derive(clap::Args)]
pub struct TraceArgs {
    /// Built-in scene name (see `photon scenes`) or scene file (.toml, .gltf, .glb).
    scene: String,
    /// Output photon-map file (.phm).
    #[arg(short, long)]
    output: PathBuf,
    /// Photons emitted (per channel with --per-channel).
    #[arg(long, default_value_t = 1_000_000)]
    photons: u64,
    /// Only the first N paths store into the global map (caustics get all --photons).
    #[arg(long)]
    global_photons: Option<u64>,
    /// Maximum number of surface hits per photon path.
    #[arg(long, default_value_t = 64)]
    max_depth: u32,
    /// Fixed absorption probability at each hit (the original project's k_a, e.g. 0.1)
    /// instead of Russian roulette on the surface's albedo.
    #[arg(long)]
    absorption: Option<f32>,
    /// Three single-channel traces (red, green, blue), as the original project did.
    #[arg(long)]
    per_channel: bool,
    /// Spectral photons: three wavelengths each, one after a dispersive glass (stored with
    /// the RGB colour of their power).
    #[arg(long, conflicts_with = "per_channel")]
    spectral: bool,
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Worker threads [default: one per core]; the maps do not depend on it.
    #[arg(long)]
    threads: Option<usize>,
    /// No progress bar.
    #[arg(short, long)]
    quiet: bool,
}

#[derive(Clone, Copy, ValueEnum)]
enum MapChoice {
    Caustic,
    Global,
    All,
}

#[derive(Clone, Copy, ValueEnum)]
enum ChannelChoice {
    R,
    G,
    B,
}

#[derive(Clone, Copy, ValueEnum)]
enum ColorChoice {
    Direction,
    Power,
    Depth,
}

#[derive(clap::Args)]
pub struct ExportArgs {
    /// A .phm file written by `photon photons trace`.
    file: PathBuf,
    /// Output point cloud (.ply).
    #[arg(short, long)]
    output: PathBuf,
    #[arg(long, value_enum, default_value = "all")]
    map: MapChoice,
    /// Only photons of this depth (1 = straight from a light).
    #[arg(long)]
    depth: Option<u8>,
    /// Only photons carrying this channel; their `power` is that channel's.
    #[arg(long, value_enum)]
    channel: Option<ChannelChoice>,
    #[arg(long, value_enum, default_value = "direction")]
    color: ColorChoice,
    /// ASCII PLY instead of binary.
    #[arg(long)]
    ascii: bool,
}

pub fn run(command: PhotonsCommand) -> Result<()> {
    match command {
        PhotonsCommand::Trace(a) => trace(&a),
        PhotonsCommand::Info { file } => info(&file),
        PhotonsCommand::Export(a) => export(&a),
    }
}

fn check_extension(path: &Path, ext: &str) -> Result<()> {
    if path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .as_deref()
        != Some(ext)
    {
        bail!("'{}': expected a .{ext} file name", path.display());
    }
    Ok(())
}

fn trace(a: &TraceArgs) -> Result<()> {
    check_extension(&a.output, "phm")?;
    let (scene, _, _) = super::scene(&a.scene)?;
    if scene.has_media() {
        return Err(photon::error::Error::InvalidScene(
            photon::photon::SAVED_MAPS_AND_MEDIA.into(),
        )
        .into());
    }
    let config = PhotonConfig {
        photons: a.photons,
        global_photons: a.global_photons,
        max_depth: a.max_depth,
        absorption: a.absorption,
        per_channel: a.per_channel,
        spectral: a.spectral,
        seed: a.seed,
    };
    config.validate()?;
    photon::io::atomic::check_writable_path(&a.output)?;
    let pool = super::thread_pool(a.threads)?;
    let bar = progress::bar("tracing photons", a.quiet);
    let start = Instant::now();
    let maps = pool.install(|| trace_photons(&scene, &config, &progress::callback(&bar)))?;
    let secs = start.elapsed().as_secs_f64();
    bar.finish_and_clear();
    phm::save(&maps, &a.output)?;
    let stored = maps.caustic.len() + maps.global.len();
    eprintln!(
        "photon: traced {} photons through {} in {secs:.2} s on {} threads ({:.2} M emitted/s): {} caustic + {} global stored ({:.2} M stored/s) → {}",
        maps.stats.emitted,
        scene.name,
        pool.current_num_threads(),
        maps.stats.emitted as f64 / secs / 1e6,
        maps.caustic.len(),
        maps.global.len(),
        stored as f64 / secs / 1e6,
        a.output.display()
    );
    Ok(())
}

fn info(file: &Path) -> Result<()> {
    let maps = phm::load(file)?;
    let bytes = std::fs::metadata(file).map(|m| m.len()).unwrap_or(0);
    print_info(file, bytes, &maps);
    Ok(())
}

fn print_info(file: &Path, bytes: u64, maps: &PhotonMaps) {
    let c = &maps.config;
    let stored = maps.caustic.len() + maps.global.len();
    outln!(
        "file:        {} ({:.1} MB, format {}, {} bytes per photon)",
        file.display(),
        bytes as f64 / 1e6,
        phm::FORMAT_VERSION,
        std::mem::size_of::<photon::photon::Photon>()
    );
    outln!(
        "scene:       {} (content hash {:016x})",
        maps.scene_name,
        maps.scene_hash
    );
    outln!(
        "traced:      {} photons emitted{}, max depth {}, {}, seed {}",
        maps.stats.emitted,
        if c.per_channel {
            format!(" ({} per channel, red, green, blue)", c.photons)
        } else {
            " (RGB)".into()
        },
        c.max_depth,
        match c.absorption {
            Some(p) => format!("absorption probability {p}"),
            None => "Russian roulette on albedo".into(),
        },
        c.seed
    );
    for map in [&maps.caustic, &maps.global] {
        let p = map.total_power();
        let direct = map.photons().iter().filter(|p| p.is_direct()).count();
        let b = map.bounds();
        outln!(
            "{:<8} map: {} photons{}; power ({:.5}, {:.5}, {:.5}) W",
            map.kind.name(),
            map.len(),
            if map.kind == MapKind::Global {
                format!(" ({direct} direct, depth 1)")
            } else {
                String::new()
            },
            p.x,
            p.y,
            p.z
        );
        if !map.is_empty() {
            outln!(
                "             bounds ({:.4}, {:.4}, {:.4}) to ({:.4}, {:.4}, {:.4})",
                b.min.x,
                b.min.y,
                b.min.z,
                b.max.x,
                b.max.y,
                b.max.z
            );
        }
    }
    let by_depth: Vec<String> = maps
        .stats
        .stored_by_depth
        .iter()
        .enumerate()
        .filter(|(_, n)| **n > 0)
        .map(|(d, n)| format!("{d}: {n}"))
        .collect();
    outln!("per depth:   {}", by_depth.join(", "));
    outln!(
        "stored:      {stored} photons, {:.3} per emitted",
        stored as f64 / maps.stats.emitted.max(1) as f64
    );
}

fn export(a: &ExportArgs) -> Result<()> {
    check_extension(&a.output, "ply")?;
    let maps = phm::load(&a.file)?;
    let filter = PlyFilter {
        maps: match a.map {
            MapChoice::Caustic => vec![MapKind::Caustic],
            MapChoice::Global => vec![MapKind::Global],
            MapChoice::All => vec![MapKind::Caustic, MapKind::Global],
        },
        depth: a.depth,
        channel: a.channel.map(|c| c as usize),
    };
    let color = match a.color {
        ColorChoice::Direction => PlyColor::Direction,
        ColorChoice::Power => PlyColor::Power,
        ColorChoice::Depth => PlyColor::Depth,
    };
    let encoding = if a.ascii {
        PlyEncoding::Ascii
    } else {
        PlyEncoding::Binary
    };
    let n = ply::export(&maps, &a.output, &filter, color, encoding)?;
    eprintln!("photon: wrote {n} photons to {}", a.output.display());
    Ok(())
}
