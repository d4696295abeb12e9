//! Where a render is shown while it runs: a tev viewer (`--tev`) and Photon's own viewer
//! (`--view`), both fed the image after each progressive pass (at most every
//! [`SHOW_EVERY`]) and when the render ends.

use super::view::{Viewer, load_reference};
use anyhow::{Context, Result};
use photon::film::Image;
use photon::io::tev::Tev;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

/// The shortest time between two images shown while passes land.
const SHOW_EVERY: Duration = Duration::from_millis(250);

/// What the command line asked to show the render in.
#[derive(Clone, Debug, Default)]
pub struct LiveOutputs {
    /// tev's HOST:PORT.
    pub tev: Option<String>,
    /// The viewer's port (0: any free one), if asked for.
    pub view: Option<u16>,
    /// The viewer's reference image.
    pub reference: Option<PathBuf>,
}

/// The displays of one render.
pub struct Live {
    tev: Option<Tev>,
    viewer: Option<Viewer>,
    last: Option<Instant>,
}

impl Live {
    /// Connect to tev and start the viewer as `asked`, before any work is done: an address
    /// that cannot be reached or a reference of another size is an error. `image` gives the
    /// render's current image (its size checks the reference). The image is named in tev
    /// after `output`'s file name.
    pub fn start(
        asked: &LiveOutputs,
        output: &Path,
        stop: Arc<AtomicBool>,
        image: impl FnOnce() -> Image,
    ) -> Result<Self> {
        let tev = asked
            .tev
            .as_deref()
            .map(|address| {
                let name = output
                    .file_name()
                    .map_or_else(|| "photon".into(), |n| n.to_string_lossy().into_owned());
                Tev::connect(address, &name).with_context(|| {
                    format!(
                        "cannot reach tev at '{address}' (start tev first; it listens on 127.0.0.1:14158)"
                    )
                })
            })
            .transpose()?;
        let viewer = match asked.view {
            Some(port) => {
                let size = asked.reference.as_ref().map(|_| image());
                let (w, h) = size.map_or((0, 0), |i| (i.width, i.height));
                let reference = load_reference(asked.reference.as_deref(), w, h)?;
                let viewer = Viewer::start(port, stop, reference)?;
                eprintln!("photon: viewer at {}", viewer.url);
                Some(viewer)
            }
            None => None,
        };
        Ok(Self {
            tev,
            viewer,
            last: None,
        })
    }

    /// After a pass: show the image if the last one is old enough, then wait while the
    /// viewer has paused the render.
    pub fn pass(&mut self, image: impl FnOnce() -> Image, passes: u64) {
        if self.tev.is_none() && self.viewer.is_none() {
            return;
        }
        if self.last.is_none_or(|t| t.elapsed() >= SHOW_EVERY) {
            self.show(image(), passes, false);
            self.last = Some(Instant::now());
        }
        if let Some(v) = &self.viewer {
            v.wait_while_paused();
        }
    }

    /// The render's final image.
    pub fn finish(&mut self, image: Image, passes: u64) {
        self.show(image, passes, true);
    }

    /// The render's final image and its AOVs, by name (the viewer offers them as layers).
    pub fn finish_with_layers(&mut self, image: Image, passes: u64, layers: Vec<(String, Image)>) {
        if let Some(v) = &self.viewer {
            v.set_layers(layers);
        }
        self.show(image, passes, true);
    }

    fn show(&mut self, image: Image, passes: u64, done: bool) {
        if let Some(tev) = &mut self.tev
            && let Err(e) = tev.show(&image)
        {
            eprintln!(
                "photon: warning: tev at {} stopped taking the image ({e}); rendering goes on",
                tev.address()
            );
        }
        if let Some(v) = &self.viewer {
            v.show(image, passes, done);
        }
    }

    /// Keep the viewer up after the render, until Ctrl-C or the page's Close.
    pub fn linger(&self) {
        if let Some(v) = &self.viewer {
            v.serve_until_closed();
        }
    }
}
