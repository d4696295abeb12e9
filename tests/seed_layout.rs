//! The `seed` scene frames the original project's scene as its final image did
//! (tests/fixtures/shared/seed/final.png): same camera, walls, boxes and spheres in the same places.

use crate::common;

use photon::description::builtin;
use photon::film::PixelFilter;
use photon::integrator::{Integrator, PathConfig};
use photon::io::image::linear_to_srgb;
use photon::render::{RenderSettings, render};

const N: u32 = 50;

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Hue {
    Red,
    Green,
    Neutral,
}

fn hue(r: f32, g: f32, b: f32) -> Hue {
    if r > 2.0 * g.max(b) && r > 0.05 {
        Hue::Red
    } else if g > 2.0 * r.max(b) && g > 0.05 {
        Hue::Green
    } else {
        Hue::Neutral
    }
}

#[test]
fn seed_scene_matches_the_original_layout() {
    let original = image::open(common::shared_dir().join("seed/final.png"))
        .expect("final.png in tests/fixtures/shared/seed")
        .to_rgb8();
    let scene = builtin::load("seed").expect("builds");
    let settings = RenderSettings {
        seed: 3,
        filter: PixelFilter::Box,
        ..RenderSettings::new(N, N, 16)
    };
    let ours = render(
        &scene,
        &Integrator::Path(PathConfig::default()),
        &settings,
        &|_, _| {},
    )
    .expect("renders")
    .image;
    let (agreement, corr) = layout_scores(&original, &ours, false);
    let (mirrored_agreement, mirrored_corr) = layout_scores(&original, &ours, true);
    eprintln!(
        "seed layout: hue agreement {agreement:.3}, rank correlation {corr:.3}; \
         mirrored: {mirrored_agreement:.3}, {mirrored_corr:.3}"
    );
    // Disagreement lives at the pot (not modelled yet), the ceiling corners and the tall box's
    // red-lit side, whose hue sits at the classification threshold (about 10% of cells).
    assert!(
        agreement > 0.85,
        "wall colours agree in {:.1}% of cells",
        100.0 * agreement
    );
    assert!(corr > 0.65, "brightness layout rank correlation {corr:.3}");
    // The measure can tell: the same render mirrored (red and green walls swapped) fails it.
    assert!(
        mirrored_agreement < agreement - 0.2,
        "mirrored agreement {mirrored_agreement:.3}"
    );
}

/// Hue agreement and brightness rank correlation between the original and our render, per cell
/// of an N×N grid; `mirror` flips our render left to right.
fn layout_scores(
    original: &image::RgbImage,
    ours: &photon::film::Image,
    mirror: bool,
) -> (f32, f32) {
    let block = original.width() / N;
    let max = ours
        .pixels
        .iter()
        .map(|p| p.max_element())
        .fold(0.0f32, f32::max);
    let (mut agree, mut lum_a, mut lum_b) = (0, Vec::new(), Vec::new());
    for y in 0..N {
        for x in 0..N {
            // Block average of the original (sRGB bytes, compared as such).
            let mut s = [0f32; 3];
            for dy in 0..block {
                for dx in 0..block {
                    let p = original.get_pixel(x * block + dx, y * block + dy);
                    for c in 0..3 {
                        s[c] += f32::from(p[c]) / 255.0;
                    }
                }
            }
            let k = (block * block) as f32;
            let theirs = [s[0] / k, s[1] / k, s[2] / k];
            let ox = if mirror { N - 1 - x } else { x };
            let p = ours.get(ox, y) / max;
            let mine = p.to_array().map(|c| linear_to_srgb(c.min(1.0)));
            agree +=
                usize::from(hue(theirs[0], theirs[1], theirs[2]) == hue(mine[0], mine[1], mine[2]));
            lum_a.push(theirs.iter().sum::<f32>());
            lum_b.push(mine.iter().sum::<f32>());
        }
    }
    (
        agree as f32 / (N * N) as f32,
        rank_correlation(&lum_a, &lum_b),
    )
}

/// Spearman's rank correlation: insensitive to the (unknown, non-physical) tone curve of the
/// original image.
fn rank_correlation(a: &[f32], b: &[f32]) -> f32 {
    correlation(&ranks(a), &ranks(b))
}

fn ranks(v: &[f32]) -> Vec<f32> {
    let mut idx: Vec<usize> = (0..v.len()).collect();
    idx.sort_by(|&i, &j| v[i].total_cmp(&v[j]));
    let mut r = vec![0.0; v.len()];
    for (rank, &i) in idx.iter().enumerate() {
        r[i] = rank as f32;
    }
    r
}

fn correlation(a: &[f32], b: &[f32]) -> f32 {
    let n = a.len() as f32;
    let (ma, mb) = (a.iter().sum::<f32>() / n, b.iter().sum::<f32>() / n);
    let cov: f32 = a.iter().zip(b).map(|(x, y)| (x - ma) * (y - mb)).sum();
    let va: f32 = a.iter().map(|x| (x - ma).powi(2)).sum();
    let vb: f32 = b.iter().map(|y| (y - mb).powi(2)).sum();
    cov / (va * vb).sqrt()
}
