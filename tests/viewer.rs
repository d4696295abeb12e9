//! Photon's viewer in a real browser: headless Chromium (Debian's `chromium`) loads the page
//! and runs its JavaScript; the page writes its own state to `<body data-…>`, which
//! `--dump-dom` prints, and `--screenshot` shows what it drew. Requests are also sent by hand,
//! to check what the server refuses. Without Chromium on the machine the browser tests say so
//! and pass; CI installs it.

use crate::common;

use common::{photon, stderr};
use std::collections::HashMap;
use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};

fn chromium() -> Option<PathBuf> {
    ["chromium", "chromium-browser", "google-chrome"]
        .iter()
        .find_map(|name| {
            let found = Command::new("which").arg(name).output().ok()?;
            found
                .status
                .success()
                .then(|| PathBuf::from(String::from_utf8_lossy(&found.stdout).trim()))
        })
}

fn browser(chromium: &Path, args: &[&str], url: &str) -> std::process::Output {
    // A profile of its own for each run: browsers started at once on one profile hand their
    // pages to each other.
    static RUNS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let run = RUNS.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
    let profile = common::temp_dir(&format!("chromium-profile-{run}"));
    Command::new(chromium)
        .arg(format!("--user-data-dir={}", profile.display()))
        .args(["--headless", "--no-sandbox", "--hide-scrollbars"])
        // WebGL in software, with no GPU.
        .args(["--use-angle=swiftshader", "--enable-unsafe-swiftshader"])
        .arg("--virtual-time-budget=10000")
        .args(args)
        .arg(url)
        .output()
        .expect("run chromium")
}

/// The page's own state after its scripts ran: the `data-` attributes of its body.
fn page_state(chromium: &Path, url: &str) -> HashMap<String, String> {
    let o = browser(chromium, &["--dump-dom"], url);
    let dom = String::from_utf8_lossy(&o.stdout);
    let start = dom.find("<body").expect("a body");
    let tag = &dom[start..start + dom[start..].find('>').expect("the tag's end")];
    let mut state = HashMap::new();
    let mut rest = tag;
    while let Some(i) = rest.find(" data-") {
        rest = &rest[i + 6..];
        let eq = rest.find("=\"").expect("a value");
        let end = rest[eq + 2..].find('"').expect("its end");
        state.insert(rest[..eq].to_owned(), rest[eq + 2..eq + 2 + end].to_owned());
        rest = &rest[eq + 2 + end..];
    }
    state
}

fn screenshot(chromium: &Path, url: &str, file: &Path) -> Vec<u8> {
    let arg = format!("--screenshot={}", file.display());
    let o = browser(chromium, &[&arg, "--window-size=480,360"], url);
    assert!(file.exists(), "{}", String::from_utf8_lossy(&o.stderr));
    std::fs::read(file).expect("the screenshot")
}

/// A request by hand (HTTP/1.0: the body as it is, never in chunks): the status and the body.
fn request(base: &str, method: &str, target: &str) -> (u16, Vec<u8>) {
    let host = base.trim_start_matches("http://");
    let mut s = TcpStream::connect(host).expect("the viewer");
    write!(
        s,
        "{method} {target} HTTP/1.0\r\nHost: {host}\r\nContent-Length: 0\r\n\r\n"
    )
    .expect("send");
    let mut reply = Vec::new();
    s.read_to_end(&mut reply).expect("reply");
    let head_end = reply
        .windows(4)
        .position(|w| w == b"\r\n\r\n")
        .expect("headers");
    let head = String::from_utf8_lossy(&reply[..head_end]);
    let status = head
        .split(' ')
        .nth(1)
        .expect("a status")
        .parse()
        .expect("a number");
    (status, reply[head_end + 4..].to_vec())
}

fn state_json(base: &str, token: &str) -> serde_json::Value {
    let (status, body) = request(base, "GET", &format!("/state?t={token}"));
    assert_eq!(status, 200);
    serde_json::from_slice(&body).expect("JSON")
}

/// A running `photon` with a viewer: the process and the page's base and token.
struct Running {
    child: Child,
    base: String,
    token: String,
}

/// A test that fails leaves no viewer behind.
impl Drop for Running {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn start(args: &[&str], dir: &Path) -> Running {
    let mut child = Command::new(env!("CARGO_BIN_EXE_photon"))
        .args(args)
        .current_dir(dir)
        .stderr(Stdio::piped())
        .spawn()
        .expect("photon");
    let mut lines = BufReader::new(child.stderr.take().expect("stderr")).lines();
    let url = loop {
        let line = lines.next().expect("a viewer line").expect("text");
        if let Some(i) = line.find("http://") {
            break line[i..]
                .split_whitespace()
                .next()
                .expect("the URL")
                .to_owned();
        }
    };
    std::thread::spawn(move || lines.for_each(drop));
    let (base, token) = url.split_once("/?t=").expect("a token");
    Running {
        child,
        base: base.to_owned(),
        token: token.to_owned(),
    }
}

#[test]
fn the_viewer_reads_pixels_and_exposes_as_the_file_says_and_refuses_what_it_does_not_serve() {
    let dir = common::temp_dir("viewer-file");
    let o = photon(
        &[
            "render",
            "cornell",
            "--integrator",
            "path",
            "--spp",
            "4",
            "--width",
            "32",
            "--height",
            "24",
            "-q",
            "-o",
            "still.exr",
        ],
        &dir,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let mut viewer = start(&["view", "still.exr"], &dir);
    let (base, token) = (viewer.base.clone(), viewer.token.clone());
    // What it refuses: a wrong or missing token, `..`, an absolute path, anything not a route.
    assert_eq!(request(&base, "GET", "/state?t=0123").0, 403);
    assert_eq!(request(&base, "GET", "/state").0, 403);
    assert_eq!(
        request(&base, "GET", &format!("/../still.exr?t={token}")).0,
        400
    );
    assert_eq!(
        request(&base, "GET", &format!("//etc/passwd?t={token}")).0,
        400
    );
    assert_eq!(
        request(&base, "GET", &format!("/still.exr?t={token}")).0,
        404
    );
    assert_eq!(request(&base, "GET", &format!("/image?t={token}")).0, 200);
    let Some(chromium) = chromium() else {
        eprintln!("no Chromium here: the browser checks are skipped (apt-get install chromium)");
        request(&base, "POST", &format!("/close?t={token}"));
        viewer.child.wait().expect("exits");
        return;
    };
    let url = format!("{base}/?t={token}");
    // The read-out of a pixel is the file's value, to the 7 digits the page prints.
    let exr = exr::prelude::read_first_rgba_layer_from_file(
        dir.join("still.exr"),
        |r, _| vec![[0.0f32; 3]; r.width() * r.height()],
        |px, p, (r, g, b, _a): (f32, f32, f32, f32)| px[p.x() + 32 * p.y()] = [r, g, b],
    )
    .expect("the EXR")
    .layer_data
    .channel_data
    .pixels;
    for (x, y) in [(5, 7), (16, 20), (30, 2)] {
        let state = page_state(&chromium, &format!("{url}&probe={x},{y}"));
        let read: Vec<f32> = state["probe"]
            .split(' ')
            .map(|v| v.parse().expect("a number"))
            .collect();
        for (got, want) in read.iter().zip(exr[x + 32 * y]) {
            assert!(
                (got - want).abs() <= 1e-6 * want.abs().max(1e-6),
                "({x}, {y}): {read:?} vs {:?}",
                exr[x + 32 * y]
            );
        }
    }
    // Exposure brightens what is drawn; tone mapping changes it.
    let mean = |q: &str| -> f64 {
        page_state(&chromium, &format!("{url}{q}"))["shown-mean"]
            .parse()
            .expect("a mean")
    };
    let (dark, bright) = (mean("&exposure=-2"), mean("&exposure=2"));
    assert!(bright > dark + 20.0, "exposure: {dark} → {bright}");
    assert!((mean("&tone=linear") - mean("&tone=srgb")).abs() > 5.0);
    let (status, _) = request(&base, "POST", &format!("/close?t={token}"));
    assert_eq!(status, 200);
    assert!(viewer.child.wait().expect("exits").success());
}

#[test]
fn the_viewer_follows_a_progressive_render_pass_by_pass_and_stops_it() {
    let dir = common::temp_dir("viewer-live");
    let mut r = start(
        &[
            "render",
            "cornell",
            "--integrator",
            "sppm",
            "--passes",
            "1000000",
            "--photons-per-pass",
            "3000",
            "--width",
            "48",
            "--height",
            "36",
            "-q",
            "-o",
            "live.exr",
            "--view",
        ],
        &dir,
    );
    let (base, token) = (r.base.clone(), r.token.clone());
    let version = |s: &serde_json::Value| s["version"].as_u64().expect("a version");
    // A bound on waiting, so that a viewer that never updates fails instead of hanging.
    let wait_for = |above: u64| {
        for _ in 0..2400 {
            let s = state_json(&base, &token);
            if version(&s) > above {
                return s;
            }
            std::thread::sleep(std::time::Duration::from_millis(50));
        }
        panic!("no image after version {above} in two minutes");
    };
    wait_for(0);
    if let Some(chromium) = chromium() {
        let url = format!("{base}/?t={token}");
        let first = page_state(&chromium, &url);
        let shot_a = screenshot(&chromium, &format!("{url}&zoom=4"), &dir.join("a.png"));
        let seen: u64 = first["version"].parse().expect("a version");
        assert!(seen >= 1);
        wait_for(seen + 1);
        let second = page_state(&chromium, &url);
        let shot_b = screenshot(&chromium, &format!("{url}&zoom=4"), &dir.join("b.png"));
        let later: u64 = second["version"].parse().expect("a version");
        assert!(
            later > seen,
            "the page took the new image: {seen} → {later}"
        );
        let passes = |s: &HashMap<String, String>| s["passes"].parse::<u64>().expect("passes");
        assert!(passes(&second) > passes(&first));
        assert_ne!(shot_a, shot_b, "what the page draws changed between passes");
    } else {
        eprintln!("no Chromium here: the browser checks are skipped (apt-get install chromium)");
    }
    // Pause holds the passes; stop ends the render, keeping what is done.
    assert_eq!(request(&base, "POST", &format!("/pause?t={token}")).0, 200);
    let paused = state_json(&base, &token);
    assert_eq!(paused["paused"], true);
    assert_eq!(request(&base, "POST", &format!("/stop?t={token}")).0, 200);
    let status = r.child.wait().expect("exits");
    assert_eq!(status.code(), Some(130), "stopped as an interrupt is");
    assert!(dir.join("live.exr").exists(), "the passes done are written");
}

#[test]
fn the_photon_view_draws_every_photon_over_the_wireframe_and_picks_one() {
    let dir = common::temp_dir("viewer-photons");
    let o = photon(
        &[
            "photons",
            "trace",
            "cornell",
            "--photons",
            "20000",
            "-o",
            "maps.phm",
        ],
        &dir,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let mut viewer = start(&["view", "maps.phm"], &dir);
    let (base, token) = (viewer.base.clone(), viewer.token.clone());
    let state = state_json(&base, &token);
    assert_eq!(state["kind"], "photons");
    let counts: Vec<u64> = state["photon_counts"]
        .as_array()
        .expect("counts")
        .iter()
        .map(|c| c.as_u64().expect("a count"))
        .collect();
    let (status, points) = request(&base, "GET", &format!("/photons?t={token}"));
    assert_eq!(status, 200);
    assert_eq!(points.len() as u64, (counts[0] + counts[1]) * 11 * 4);
    let (_, wire) = request(&base, "GET", &format!("/wireframe?t={token}"));
    assert!(wire.len() >= 24 * 12, "the box's walls as segments");
    if let Some(chromium) = chromium() {
        // The page fetches the points and draws them in software GL: on a busy machine a load
        // may end before it has, so it is given a few.
        let page = (0..5)
            .map(|_| page_state(&chromium, &format!("{base}/?t={token}&pick=400,300")))
            .find(|p| p.contains_key("picked-depth"))
            .expect("the page drew the photons and picked one");
        let drawn: u64 = page["points"].parse().expect("points");
        assert_eq!(
            drawn,
            counts[0] + counts[1],
            "every photon of both maps is drawn"
        );
        let lit: u64 = page["lit-pixels"].parse().expect("lit pixels");
        assert!(lit > 5_000, "the points cover the canvas: {lit} pixels");
        let depth: f32 = page["picked-depth"].parse().expect("a picked photon");
        assert!(depth >= 1.0);
        screenshot(
            &chromium,
            &format!("{base}/?t={token}"),
            &dir.join("photons.png"),
        );
    } else {
        eprintln!("no Chromium here: the browser checks are skipped (apt-get install chromium)");
    }
    request(&base, "POST", &format!("/close?t={token}"));
    assert!(viewer.child.wait().expect("exits").success());
}

#[test]
fn the_viewer_offers_a_renders_aovs_as_layers() {
    let dir = common::temp_dir("viewer-aov");
    let mut r = start(
        &[
            "render",
            "cornell",
            "--integrator",
            "path",
            "--spp",
            "2",
            "--width",
            "16",
            "--height",
            "12",
            "--aov",
            "albedo",
            "-q",
            "-o",
            "a.exr",
            "--view",
        ],
        &dir,
    );
    let (base, token) = (r.base.clone(), r.token.clone());
    // The render is done once its layers are there.
    let state = (0..2400)
        .map(|_| {
            std::thread::sleep(std::time::Duration::from_millis(25));
            state_json(&base, &token)
        })
        .find(|s| s["done"] == true)
        .expect("the render ends");
    assert_eq!(state["layers"], serde_json::json!(["albedo"]));
    let (status, served) = request(&base, "GET", &format!("/image?layer=albedo&t={token}"));
    assert_eq!(status, 200);
    let served: Vec<f32> = served
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes(b.try_into().expect("4 bytes")))
        .collect();
    // The file's albedo layer, channel by channel.
    let file = exr::prelude::read_all_flat_layers_from_file(dir.join("a.exr")).expect("EXR");
    let channel = |name: &str| -> Vec<f32> {
        let list = &file.layer_data[0].channel_data.list;
        let c = list
            .iter()
            .find(|c| c.name.to_string() == name)
            .expect(name);
        c.sample_data.values_as_f32().collect()
    };
    let (red, green, blue) = (
        channel("albedo.R"),
        channel("albedo.G"),
        channel("albedo.B"),
    );
    for i in 0..16 * 12 {
        assert_eq!(
            served[3 * i..3 * i + 3],
            [red[i], green[i], blue[i]],
            "pixel {i}"
        );
    }
    if let Some(chromium) = chromium() {
        let page = page_state(
            &chromium,
            &format!("{base}/?t={token}&layer=albedo&probe=3,4"),
        );
        assert_eq!(page["layer"], "albedo");
        let i = 3 + 16 * 4;
        let want = [red[i], green[i], blue[i]];
        let got: Vec<f32> = page["probe"]
            .split(' ')
            .map(|v| v.parse().expect("a number"))
            .collect();
        for (g, w) in got.iter().zip(want) {
            assert!(
                (g - w).abs() <= 1e-6 * w.abs().max(1e-6),
                "read-out {got:?} vs {want:?}"
            );
        }
    } else {
        eprintln!("no Chromium here: the browser checks are skipped (apt-get install chromium)");
    }
    request(&base, "POST", &format!("/close?t={token}"));
    assert!(r.child.wait().expect("exits").success());
}
