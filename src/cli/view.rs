//! The live viewer: `photon render … --view` and `photon view FILE`. A small HTTP server on
//! the loopback interface serves one page (`view.html`, plain JavaScript, no build step) and
//! the image it shows as raw floats, so the page tone-maps, zooms and reads pixels itself.
//!
//! Security: the server listens on 127.0.0.1 only, every request must carry the random token
//! printed in the URL (`?t=…`), and it answers nothing but its fixed routes: no path is ever
//! read from disk. A wrong or missing token gets 403, a path with `..` or not starting at `/`
//! gets 400, anything else not a route 404.
//!
//! Routes: `GET /` the page; `GET /state` JSON (the image's version, size, passes, seconds,
//! whether it is done or paused, the relMSE history against `--reference`, the AOV layers);
//! `GET /image` (`&layer=NAME` for an AOV) and `GET /reference` the pixels (little-endian f32 R, G, B, rows from the top); `POST /pause`,
//! `/resume`, `/stop` (the progressive session's cancel: what is done is kept) and `/close`
//! (ends a finished viewer).

use anyhow::{Context, Result};
use photon::film::Image;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::{Duration, Instant};

const PAGE: &str = include_str!("view.html");

/// What the page shows and what it has asked for.
struct Shared {
    frame: Mutex<Frame>,
    paused: AtomicBool,
    closed: AtomicBool,
    /// The render's stop flag (a progressive session's cancel, also set by Ctrl-C).
    stop: Arc<AtomicBool>,
}

#[derive(Default)]
struct Frame {
    version: u64,
    image: Option<Arc<Image>>,
    /// A photon map's points and its scene's wireframe (see `view_photons`), and how many
    /// photons each map holds (global, caustic).
    photons: Option<Arc<Vec<u8>>>,
    wireframe: Option<Arc<Vec<u8>>>,
    photon_counts: [usize; 2],
    /// Further images of the render (its AOVs), by name.
    layers: Vec<(String, Arc<Image>)>,
    reference: Option<Arc<Image>>,
    passes: u64,
    seconds: f64,
    done: bool,
    /// (seconds, relMSE against the reference) of each image shown.
    history: Vec<(f64, f64)>,
}

/// A running viewer; its server stops when it is dropped.
pub struct Viewer {
    shared: Arc<Shared>,
    server: Arc<tiny_http::Server>,
    thread: Option<std::thread::JoinHandle<()>>,
    pub url: String,
    start: Instant,
}

impl Viewer {
    /// Serve on 127.0.0.1:`port` (0: any free port), with `stop` as the render's stop flag.
    pub fn start(port: u16, stop: Arc<AtomicBool>, reference: Option<Image>) -> Result<Self> {
        let server = tiny_http::Server::http(("127.0.0.1", port))
            .map_err(|e| anyhow::anyhow!("cannot serve the viewer on 127.0.0.1:{port}: {e}"))?;
        let server = Arc::new(server);
        let port = server
            .server_addr()
            .to_ip()
            .context("the viewer's address")?
            .port();
        let token = random_token();
        let shared = Arc::new(Shared {
            frame: Mutex::new(Frame {
                reference: reference.map(Arc::new),
                ..Frame::default()
            }),
            paused: AtomicBool::new(false),
            closed: AtomicBool::new(false),
            stop,
        });
        let thread = {
            let (server, shared, token) = (server.clone(), shared.clone(), token.clone());
            std::thread::spawn(move || {
                for request in server.incoming_requests() {
                    respond(&shared, &token, request);
                }
            })
        };
        Ok(Self {
            shared,
            server,
            thread: Some(thread),
            url: format!("http://127.0.0.1:{port}/?t={token}"),
            start: Instant::now(),
        })
    }

    /// Show `image`, `passes` in (0 for a render that is not progressive).
    pub fn show(&self, image: Image, passes: u64, done: bool) {
        let seconds = self.start.elapsed().as_secs_f64();
        let mut frame = self
            .shared
            .frame
            .lock()
            .unwrap_or_else(PoisonError::into_inner);
        if let Some(reference) = &frame.reference
            && let Some(c) = photon::compare::compare(&image, reference, None)
        {
            frame.history.push((seconds, c.overall.rel_mse));
        }
        frame.image = Some(Arc::new(image));
        frame.version += 1;
        frame.passes = passes;
        frame.seconds = seconds;
        frame.done = done;
    }

    /// The AOVs to offer beside the image, by name.
    pub fn set_layers(&self, layers: Vec<(String, Image)>) {
        let mut frame = self
            .shared
            .frame
            .lock()
            .unwrap_or_else(PoisonError::into_inner);
        frame.layers = layers.into_iter().map(|(n, i)| (n, Arc::new(i))).collect();
    }

    /// Show a photon map: its points and its scene's wireframe (see `view_photons`).
    pub fn show_photons(&self, photons: Vec<u8>, wireframe: Vec<u8>, counts: [usize; 2]) {
        let mut frame = self
            .shared
            .frame
            .lock()
            .unwrap_or_else(PoisonError::into_inner);
        frame.photons = Some(Arc::new(photons));
        frame.wireframe = Some(Arc::new(wireframe));
        frame.photon_counts = counts;
        frame.version += 1;
        frame.done = true;
    }

    /// While the page has paused the render: wait, unless it is stopped.
    pub fn wait_while_paused(&self) {
        while self.shared.paused.load(Ordering::SeqCst) && !self.shared.stop.load(Ordering::SeqCst)
        {
            std::thread::sleep(Duration::from_millis(50));
        }
    }

    /// After the render: keep serving until Ctrl-C or the page's Close.
    pub fn serve_until_closed(&self) {
        eprintln!("photon: the viewer stays at {} until Ctrl-C", self.url);
        while !self.shared.closed.load(Ordering::SeqCst) && !self.shared.stop.load(Ordering::SeqCst)
        {
            std::thread::sleep(Duration::from_millis(100));
        }
    }
}

impl Drop for Viewer {
    fn drop(&mut self) {
        self.server.unblock();
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

/// 128 bits from the operating system's random source, through the keys `RandomState` takes
/// from it, as 32 hex digits.
fn random_token() -> String {
    use std::hash::{BuildHasher, Hasher};
    let half = || {
        let mut h = std::collections::hash_map::RandomState::new().build_hasher();
        h.write_u128(Instant::now().elapsed().as_nanos());
        h.finish()
    };
    format!("{:016x}{:016x}", half(), half())
}

/// Answer one request.
fn respond(shared: &Shared, token: &str, request: tiny_http::Request) {
    let (status, content_type, body) = route(shared, token, request.method(), request.url());
    let header = tiny_http::Header::from_bytes(&b"Content-Type"[..], content_type.as_bytes())
        .expect("a valid header");
    let no_store = tiny_http::Header::from_bytes(&b"Cache-Control"[..], &b"no-store"[..])
        .expect("a valid header");
    let length = body.0.len();
    let response = tiny_http::Response::new(
        tiny_http::StatusCode(status),
        vec![header, no_store],
        std::io::Cursor::new(body),
        Some(length),
        None,
    );
    let _ = request.respond(response);
}

/// A response's body, shared with the frame it came from: a photon map of tens of
/// megabytes is sent without a copy per request.
struct Body(Arc<Vec<u8>>);

impl AsRef<[u8]> for Body {
    fn as_ref(&self) -> &[u8] {
        &self.0
    }
}

impl From<Vec<u8>> for Body {
    fn from(bytes: Vec<u8>) -> Self {
        Body(Arc::new(bytes))
    }
}

type Answer = (u16, &'static str, Body);

fn text(status: u16, message: &str) -> Answer {
    (
        status,
        "text/plain; charset=utf-8",
        message.as_bytes().to_vec().into(),
    )
}

/// The answer to `method url`: see the module's routes and rules.
fn route(shared: &Shared, token: &str, method: &tiny_http::Method, url: &str) -> Answer {
    let (path, query) = url.split_once('?').unwrap_or((url, ""));
    if !path.starts_with('/')
        || path.starts_with("//")
        || path.contains("..")
        || path.contains('\\')
    {
        return text(400, "bad path");
    }
    let given = query
        .split('&')
        .find_map(|kv| kv.strip_prefix("t="))
        .unwrap_or("");
    if given.len() != token.len() || given != token {
        return text(403, "wrong or missing token");
    }
    use tiny_http::Method::{Get, Post};
    let frame = || shared.frame.lock().unwrap_or_else(PoisonError::into_inner);
    match (method, path) {
        (Get, "/") => (
            200,
            "text/html; charset=utf-8",
            PAGE.as_bytes().to_vec().into(),
        ),
        (Get, "/state") => {
            let f = frame();
            let (w, h) = f.image.as_ref().map_or((0, 0), |i| (i.width, i.height));
            let state = serde_json::json!({
                "version": f.version,
                "width": w,
                "height": h,
                "passes": f.passes,
                "seconds": f.seconds,
                "done": f.done,
                "paused": shared.paused.load(Ordering::SeqCst),
                "stopped": shared.stop.load(Ordering::SeqCst),
                "reference": f.reference.is_some(),
                "kind": if f.photons.is_some() { "photons" } else { "image" },
                "photon_counts": f.photon_counts,
                "photon_floats": super::view_photons::PHOTON_FLOATS,
                "layers": f.layers.iter().map(|l| l.0.clone()).collect::<Vec<_>>(),
                "history": f.history,
            });
            (
                200,
                "application/json",
                state.to_string().into_bytes().into(),
            )
        }
        (Get, "/image") => {
            let f = frame();
            let layer = query.split('&').find_map(|kv| kv.strip_prefix("layer="));
            match layer {
                None | Some("") => pixels(f.image.clone()),
                Some(name) => pixels(f.layers.iter().find(|l| l.0 == name).map(|l| l.1.clone())),
            }
        }
        (Get, "/reference") => pixels(frame().reference.clone()),
        (Get, "/photons") => bytes(frame().photons.clone()),
        (Get, "/wireframe") => bytes(frame().wireframe.clone()),
        (Post, "/pause") => flag(&shared.paused, true),
        (Post, "/resume") => flag(&shared.paused, false),
        (Post, "/stop") => flag(&shared.stop, true),
        (Post, "/close") => flag(&shared.closed, true),
        _ => text(404, "not found"),
    }
}

fn flag(f: &AtomicBool, value: bool) -> Answer {
    f.store(value, Ordering::SeqCst);
    text(200, "ok")
}

fn bytes(data: Option<Arc<Vec<u8>>>) -> Answer {
    match data {
        Some(d) => (200, "application/octet-stream", Body(d)),
        None => text(404, "no photon map"),
    }
}

fn pixels(image: Option<Arc<Image>>) -> Answer {
    let Some(image) = image else {
        return text(404, "no image yet");
    };
    let mut bytes = Vec::with_capacity(image.pixels.len() * 12);
    for p in &image.pixels {
        for v in p.to_array() {
            bytes.extend(v.to_le_bytes());
        }
    }
    (200, "application/octet-stream", bytes.into())
}

#[derive(clap::Args)]
pub struct ViewArgs {
    /// The image to show (.exr, .pfm or .png), or a photon map (.phm, `photon photons trace`)
    /// as points over its scene's wireframe.
    file: std::path::PathBuf,
    /// The scene a photon map's wireframe is drawn from [default: the scene it was traced
    /// for, by the name it records].
    #[arg(long)]
    scene: Option<String>,
    /// The port to serve on [default: any free port].
    #[arg(long)]
    port: Option<u16>,
    /// A reference to compare with: A/B flip, relative-error heat map, relMSE.
    #[arg(long)]
    reference: Option<std::path::PathBuf>,
}

/// `photon view FILE`: the viewer on a finished image, until Ctrl-C.
pub fn view(a: &ViewArgs) -> Result<()> {
    let is_phm = a
        .file
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("phm"));
    if is_phm {
        return view_photon_map(a);
    }
    let image = read_any_image(&a.file)?;
    let reference = load_reference(a.reference.as_deref(), image.width, image.height)?;
    let stop = super::progressive::interrupts().stop;
    let viewer = Viewer::start(a.port.unwrap_or(0), stop, reference)?;
    viewer.show(image, 0, true);
    viewer.serve_until_closed();
    Ok(())
}

/// `photon view maps.phm`: the photons over the wireframe of the scene they were traced for.
fn view_photon_map(a: &ViewArgs) -> Result<()> {
    use super::view_photons::{photon_floats, to_bytes, wireframe};
    let maps = photon::io::phm::load(&a.file)?;
    let scene_name = a.scene.clone().unwrap_or_else(|| maps.scene_name.clone());
    let wire = match super::scene_with(&scene_name, &super::EnvironmentArgs::default()) {
        Ok((scene, _, _)) => wireframe(&scene),
        Err(e) => {
            eprintln!(
                "photon: warning: no wireframe: scene '{scene_name}' does not load ({e:#}); give --scene"
            );
            Vec::new()
        }
    };
    let (points, counts) = photon_floats(&maps);
    let stop = super::progressive::interrupts().stop;
    let viewer = Viewer::start(a.port.unwrap_or(0), stop, None)?;
    viewer.show_photons(to_bytes(&points), to_bytes(&wire), counts);
    viewer.serve_until_closed();
    Ok(())
}

/// An image file of any format Photon writes that has pixels: EXR and PFM (linear), PNG
/// (sRGB, decoded to linear, as a texture is).
fn read_any_image(path: &std::path::Path) -> Result<Image> {
    let is_png = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"));
    if !is_png {
        return Ok(photon::io::image::read_image(path)?);
    }
    let png = photon::io::texture::read_texture(path)?;
    Ok(Image {
        width: png.width,
        height: png.height,
        pixels: png.texels.clone(),
    })
}

/// The `--reference` image, which must have the render's size.
pub fn load_reference(
    path: Option<&std::path::Path>,
    width: u32,
    height: u32,
) -> Result<Option<Image>> {
    let Some(path) = path else {
        return Ok(None);
    };
    let image = read_any_image(path)?;
    if (image.width, image.height) != (width, height) {
        anyhow::bail!(
            "--reference '{}' is {}×{}, the image {width}×{height}",
            path.display(),
            image.width,
            image.height
        );
    }
    Ok(Some(image))
}
