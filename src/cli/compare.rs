//! `photon compare`.

use anyhow::{Result, bail};
use photon::compare::{Comparison, Crop, compare};
use photon::io::image::read_image_pair;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct CompareArgs {
    /// The image to judge (.exr or .pfm).
    image: PathBuf,
    /// The reference (.exr or .pfm).
    reference: PathBuf,
    /// Print JSON instead of a table.
    #[arg(long)]
    json: bool,
    /// Restrict to a rectangle: x0,y0,x1,y1 (pixels, end exclusive).
    #[arg(long, value_parser = parse_crop)]
    crop: Option<Crop>,
}

fn parse_crop(s: &str) -> Result<Crop, String> {
    let v: Vec<u32> = s
        .split(',')
        .map(|t| t.trim().parse::<u32>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("'{s}' is not a crop; expected x0,y0,x1,y1"))?;
    match v.as_slice() {
        &[x0, y0, x1, y1] => Ok(Crop { x0, x1, y0, y1 }),
        _ => Err(format!(
            "'{s}' is not a crop; expected four numbers x0,y0,x1,y1"
        )),
    }
}

pub fn run(a: &CompareArgs) -> Result<()> {
    let (img, reference) = read_image_pair(&a.image, &a.reference)?;
    if (img.width, img.height) != (reference.width, reference.height) {
        bail!(
            "the images differ in size: '{}' is {}×{}, '{}' is {}×{}",
            a.image.display(),
            img.width,
            img.height,
            a.reference.display(),
            reference.width,
            reference.height
        );
    }
    let Some(c) = compare(&img, &reference, a.crop) else {
        bail!(
            "the crop lies outside the {}×{} image",
            img.width,
            img.height
        );
    };
    if a.json {
        outln!("{}", serde_json::to_string_pretty(&c)?);
    } else {
        print_comparison(&c);
    }
    Ok(())
}

fn print_comparison(c: &Comparison) {
    outln!(
        "{:<8} {:>12} {:>12} {:>12}",
        "channel",
        "RMSE",
        "relMSE",
        "mean ratio"
    );
    for (name, e) in [
        ("red", &c.red),
        ("green", &c.green),
        ("blue", &c.blue),
        ("overall", &c.overall),
    ] {
        outln!(
            "{name:<8} {:>12.6} {:>12.6} {:>12.6}",
            e.rmse,
            e.rel_mse,
            e.mean_ratio
        );
    }
}
