//! Decoded-image memory (`photon::io::decoded`): every reader takes room from one budget,
//! from the file's header, before decoding; a texture used many times is decoded once. The
//! bombs here are headers alone (nothing is decoded, on old code either) or tiny images under
//! a tiny budget set through `PHOTON_IMAGE_MEMORY` in a child process.

use crate::common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn photon_with_budget(args: &[&str], dir: &Path, budget: &str) -> Output {
    Command::new(env!("CARGO_BIN_EXE_photon"))
        .args(args)
        .current_dir(dir)
        .env("PHOTON_IMAGE_MEMORY", budget)
        .output()
        .expect("run photon")
}

fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in bytes {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = (crc >> 1) ^ (0xEDB8_8320 & 0u32.wrapping_sub(crc & 1));
        }
    }
    !crc
}

fn png_chunk(out: &mut Vec<u8>, kind: &[u8], data: &[u8]) {
    out.extend_from_slice(&(data.len() as u32).to_be_bytes());
    let start = out.len();
    out.extend_from_slice(kind);
    out.extend_from_slice(data);
    let crc = crc32(&out[start..]);
    out.extend_from_slice(&crc.to_be_bytes());
}

/// A PNG's signature and header (16-bit RGBA of `w` × `h`), then the start of a data chunk:
/// all a decoder reads before it allocates the pixels.
fn png_header_only(w: u32, h: u32) -> Vec<u8> {
    let mut out = b"\x89PNG\r\n\x1a\n".to_vec();
    let mut ihdr = Vec::new();
    ihdr.extend_from_slice(&w.to_be_bytes());
    ihdr.extend_from_slice(&h.to_be_bytes());
    ihdr.extend_from_slice(&[16, 6, 0, 0, 0]);
    png_chunk(&mut out, b"IHDR", &ihdr);
    png_chunk(&mut out, b"IDAT", &[0x78, 0x9c]);
    out
}

fn exr_attribute(out: &mut Vec<u8>, name: &str, kind: &str, value: &[u8]) {
    for s in [name, kind] {
        out.extend_from_slice(s.as_bytes());
        out.push(0);
    }
    out.extend_from_slice(&(value.len() as i32).to_le_bytes());
    out.extend_from_slice(value);
}

/// An OpenEXR header (RGB half floats, `w` × `h`, scan lines) and nothing after it.
fn exr_header_only(w: i32, h: i32) -> Vec<u8> {
    let mut out = Vec::new();
    out.extend_from_slice(&20_000_630i32.to_le_bytes());
    out.extend_from_slice(&2i32.to_le_bytes());
    let mut channels = Vec::new();
    for c in ["B", "G", "R"] {
        channels.extend_from_slice(c.as_bytes());
        channels.push(0);
        for v in [1i32, 0, 1, 1] {
            channels.extend_from_slice(&v.to_le_bytes());
        }
    }
    channels.push(0);
    let window: Vec<u8> = [0, 0, w - 1, h - 1]
        .iter()
        .flat_map(|v: &i32| v.to_le_bytes())
        .collect();
    exr_attribute(&mut out, "channels", "chlist", &channels);
    exr_attribute(&mut out, "compression", "compression", &[3]);
    exr_attribute(&mut out, "dataWindow", "box2i", &window);
    exr_attribute(&mut out, "displayWindow", "box2i", &window);
    exr_attribute(&mut out, "lineOrder", "lineOrder", &[0]);
    exr_attribute(&mut out, "pixelAspectRatio", "float", &1f32.to_le_bytes());
    exr_attribute(&mut out, "screenWindowCenter", "v2f", &[0; 8]);
    exr_attribute(&mut out, "screenWindowWidth", "float", &1f32.to_le_bytes());
    out.push(0);
    out
}

/// The budget's refusal: the file, the decoded size, the budget and how to change it.
fn assert_over_budget(message: &str, name: &str, size: &str) {
    for needle in [
        name,
        size,
        "budget for decoded images",
        "PHOTON_IMAGE_MEMORY",
    ] {
        assert!(message.contains(needle), "'{needle}' in: {message}");
    }
}

#[test]
fn a_png_whose_header_asks_past_the_budget_is_refused_before_decoding() {
    // 16k × 16k 16-bit RGBA: 2 GiB decoded, 4 GiB of texels and alpha.
    let png = png_header_only(16384, 16384);
    let e = photon::io::texture::decode_texture(&png, Path::new("bomb.png"))
        .expect_err("over the budget")
        .to_string();
    assert_over_budget(&e, "bomb.png", "16384×16384 pixels need 6 GiB");
}

#[test]
fn an_exr_whose_header_asks_past_the_budget_is_refused_before_decoding() {
    let dir = common::temp_dir("exr-bomb");
    // Past 2³⁰ pixels by a row, so that no version of the reader allocates it.
    std::fs::write(dir.join("bomb.exr"), exr_header_only(32768, 32769)).expect("write");
    let e = photon::io::image::read_image(&dir.join("bomb.exr"))
        .expect_err("over the budget")
        .to_string();
    assert_over_budget(&e, "bomb.exr", "32768×32769 pixels need 12 GiB");
    let o = common::photon(&["compare", "bomb.exr", "bomb.exr"], &dir);
    common::assert_usage_error(&o, "budget for decoded images");
}

#[test]
fn a_texture_decoded_twice_is_the_same_texture() {
    let mut png = Vec::new();
    image::RgbImage::from_pixel(3, 2, image::Rgb([10, 20, 30]))
        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .expect("encode");
    let a = photon::io::texture::decode_texture(&png, Path::new("a.png")).expect("a");
    let b = photon::io::texture::decode_texture(&png, Path::new("b.png")).expect("b");
    assert!(std::sync::Arc::ptr_eq(&a, &b), "decoded once");
    let linear = photon::io::texture::decode_texture_as(
        &png,
        Path::new("a.png"),
        photon::io::texture::Encoding::Linear,
    )
    .expect("linear");
    assert!(!std::sync::Arc::ptr_eq(&a, &linear), "decoded differently");
}

/// A sphere in a scene whose `n` materials use the textures `files` in turn.
fn textured_scene(dir: &Path, files: &[&str], n: usize) -> PathBuf {
    let mut toml = String::from(
        "[camera]\nposition = [0, 0, 3]\nlook_at = [0, 0, 0]\nresolution = [8, 8]\n\
         [[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"m0\"\n\
         [[lights]]\ntype = \"point\"\nposition = [0, 2, 3]\nintensity = 10\n",
    );
    for i in 0..n {
        let file = files[i % files.len()];
        toml +=
            &format!("[materials.m{i}]\ntype = \"diffuse\"\nalbedo = {{ texture = \"{file}\" }}\n");
    }
    let path = dir.join("scene.toml");
    std::fs::write(&path, toml).expect("write scene");
    path
}

fn write_png(path: &Path, seed: u8) {
    // 64 × 64 RGB: 12 KiB decoded, 48 KiB of texels.
    image::RgbImage::from_fn(64, 64, |x, y| image::Rgb([x as u8, y as u8, seed]))
        .save(path)
        .expect("write png");
}

#[test]
fn textures_share_one_budget_and_each_is_decoded_once() {
    let dir = common::temp_dir("texture-budget");
    write_png(&dir.join("a.png"), 1);
    write_png(&dir.join("b.png"), 2);
    let render = [
        "render",
        "scene.toml",
        "--integrator",
        "direct",
        "--spp",
        "1",
    ];
    let out = ["-o", "out.png"];
    let args: Vec<&str> = render.iter().chain(&out).copied().collect();
    // One texture, four materials: decoded once, 60 KiB of a 100 KiB budget.
    textured_scene(&dir, &["a.png"], 4);
    let o = photon_with_budget(&args, &dir, "100K");
    assert!(o.status.success(), "{}", common::stderr(&o));
    // Two textures: the second does not fit beside the first.
    textured_scene(&dir, &["a.png", "b.png"], 4);
    let o = photon_with_budget(&args, &dir, "100K");
    common::assert_usage_error(&o, "b.png");
    assert_over_budget(
        &common::stderr(&o),
        "b.png",
        "64×64 pixels need 60 KiB decoded, more than the 100 KiB budget",
    );
    assert!(common::stderr(&o).contains("48 KiB of it already held"));
    let o = photon_with_budget(&args, &dir, "lots");
    common::assert_usage_error(&o, "PHOTON_IMAGE_MEMORY=\"lots\"");
}

fn write_exr(path: &Path, w: usize, h: usize) {
    exr::prelude::write_rgb_file(path, w, h, |x, y| (x as f32, y as f32, 0.5f32)).expect("exr");
}

#[test]
fn compared_images_fit_the_budget_together() {
    let dir = common::temp_dir("compare-budget");
    // 64 × 64: 48 KiB each.
    write_exr(&dir.join("a.exr"), 64, 64);
    write_exr(&dir.join("b.exr"), 64, 64);
    let o = photon_with_budget(&["compare", "a.exr", "b.exr"], &dir, "64K");
    common::assert_usage_error(&o, "b.exr");
    assert!(common::stderr(&o).contains("48 KiB of it already held"));
    let o = photon_with_budget(&["compare", "a.exr", "b.exr"], &dir, "96K");
    assert!(o.status.success(), "{}", common::stderr(&o));
}

#[test]
fn environment_maps_take_room_from_the_budget_in_every_format() {
    let dir = common::temp_dir("env-budget");
    std::fs::write(
        dir.join("floor.toml"),
        "[camera]\nposition = [0, 1, 3]\nlook_at = [0, 0, 0]\nresolution = [8, 8]\n\
         [materials.white]\ntype = \"diffuse\"\nalbedo = 0.8\n\
         [[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"white\"\n",
    )
    .expect("scene");
    // 64 × 32 texels of 12 bytes: 24 KiB in every format.
    write_exr(&dir.join("sky.exr"), 64, 32);
    let mut pfm = b"PF\n64 32\n-1.0\n".to_vec();
    pfm.extend(std::iter::repeat_n(0.5f32.to_le_bytes(), 64 * 32 * 3).flatten());
    std::fs::write(dir.join("sky.pfm"), pfm).expect("pfm");
    let hdr = image::Rgb32FImage::from_pixel(64, 32, image::Rgb([0.5, 0.5, 0.5]));
    image::DynamicImage::ImageRgb32F(hdr)
        .save(dir.join("sky.hdr"))
        .expect("hdr");
    for sky in ["sky.exr", "sky.pfm", "sky.hdr"] {
        let args = [
            "render",
            "floor.toml",
            "--env",
            sky,
            "--integrator",
            "direct",
            "--spp",
            "1",
            "-o",
            "out.png",
        ];
        let o = photon_with_budget(&args, &dir, "20K");
        common::assert_usage_error(&o, sky);
        assert_over_budget(&common::stderr(&o), sky, "64×32 pixels need 24 KiB");
        let o = photon_with_budget(&args, &dir, "24K");
        assert!(o.status.success(), "{sky}: {}", common::stderr(&o));
    }
}
