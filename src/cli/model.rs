//! `photon model`: write procedural models as OBJ or PLY.

use anyhow::{Result, bail};
use clap::ValueEnum;
use photon::io::mesh::{Part, write_obj, write_ply};
use photon::modeling::pot::{PotParams, pot};
use std::path::PathBuf;
use std::time::Instant;

#[derive(Clone, Copy, ValueEnum)]
enum ModelName {
    /// The original project's plant pot: body (lathe, solidify, Catmull–Clark), soil, NURBS leaves.
    Pot,
}

#[derive(clap::Args)]
pub struct ModelArgs {
    #[arg(value_enum)]
    model: ModelName,
    /// Output file: .obj (named parts pot, soil, leaves) or .ply.
    #[arg(short, long)]
    output: PathBuf,
    /// Catmull–Clark levels for the pot body.
    #[arg(long, default_value_t = 2)]
    subdivisions: u32,
    /// Varies the leaves.
    #[arg(long, default_value_t = 0)]
    seed: u64,
}

pub fn run(a: &ModelArgs) -> Result<()> {
    if a.subdivisions > 6 {
        bail!(
            "--subdivisions {} is too many (at most 6: each level multiplies faces by 4)",
            a.subdivisions
        );
    }
    let ext = a
        .output
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    if !matches!(ext.as_deref(), Some("obj" | "ply")) {
        bail!(
            "'{}': expected a .obj or .ply file name",
            a.output.display()
        );
    }
    photon::io::atomic::check_writable_path(&a.output)?;
    let start = Instant::now();
    let ModelName::Pot = a.model;
    let model = pot(&PotParams {
        subdivisions: a.subdivisions,
        seed: a.seed,
    });
    let secs = start.elapsed().as_secs_f64();
    let (soil, leaves) = (model.soil_mesh(), model.leaves_mesh());
    let parts = [
        Part {
            name: "pot",
            mesh: &model.body,
        },
        Part {
            name: "soil",
            mesh: &soil,
        },
        Part {
            name: "leaves",
            mesh: &leaves,
        },
    ];
    if ext.as_deref() == Some("obj") {
        write_obj(&a.output, &parts)?;
    } else {
        write_ply(&a.output, &parts)?;
    }
    let tris: usize = parts.iter().map(|p| p.mesh.triangles().len()).sum();
    eprintln!(
        "photon: pot built in {:.1} ms: {} faces, {tris} triangles (pot {}, soil {}, leaves {}) → {}",
        secs * 1e3,
        parts.iter().map(|p| p.mesh.faces.len()).sum::<usize>(),
        model.body.triangles().len(),
        soil.triangles().len(),
        leaves.triangles().len(),
        a.output.display()
    );
    Ok(())
}
