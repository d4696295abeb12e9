//! Parts, and their merge: one part in memory at a time besides the sums, so merging is
//! linear in the parts with memory independent of their number.

use crate::error::{Error, Result};
use crate::film::Image;
use crate::io::sample_part::{self, PartOrigin};
use crate::progressive::ProgressiveState;
use crate::render::SampleSums;
use std::path::Path;

/// A partial render: PPM passes, or samples of each pixel.
pub enum Part {
    Passes(ProgressiveState),
    Samples(SampleSums, Box<PartOrigin>),
}

impl Part {
    /// The range `[start, end)` of passes or samples it holds.
    pub fn range(&self) -> (u64, u64) {
        match self {
            Part::Passes(s) => (s.first_pass, s.first_pass.saturating_add(s.passes)),
            Part::Samples(s, o) => (
                u64::from(o.first_sample),
                u64::from(o.first_sample) + u64::from(s.samples),
            ),
        }
    }
}

impl Part {
    /// The content hash of the scene it was rendered from, hexadecimal.
    pub fn scene_hash(&self) -> String {
        match self {
            Part::Passes(s) => format!("{:016x}", s.scene_hash),
            Part::Samples(_, o) => o.scene_hash.clone(),
        }
    }
}

/// Read a `.part` file of either kind, bare or as a job wrote it (the job's label is not
/// checked here: see [`super::load_job_part`]).
pub fn load_part(path: &Path) -> Result<Part> {
    let bytes = crate::io::input::read_file(path)?;
    let bad = |message| Error::BadCheckpoint {
        path: path.to_owned(),
        message,
    };
    if super::part_file::is_job_part(&bytes) {
        return super::part_file::decode(&bytes)
            .map(|(_, part)| part)
            .map_err(bad);
    }
    decode_part(&bytes).map_err(bad)
}

/// A bare part in memory: a sample part, or a PPM checkpoint of a pass range.
pub fn decode_part(bytes: &[u8]) -> std::result::Result<Part, String> {
    if sample_part::is_sample_part(bytes) {
        let (sums, origin) = sample_part::decode(bytes)?;
        return Ok(Part::Samples(sums, Box::new(origin)));
    }
    let (state, _) = crate::io::checkpoint::decode_with(bytes)?;
    if !state.config.method.has_independent_passes() {
        return Err("an sppm checkpoint is not a part: sppm passes depend on each other".into());
    }
    Ok(Part::Passes(state))
}

/// Parts added one at a time. They must come from the same scene and settings, and their
/// ranges must not overlap; they need not join (a merge of the parts present so far).
#[derive(Default)]
pub struct Merger {
    sum: Option<Part>,
    /// The ranges added, to refuse a part added twice.
    ranges: Vec<(u64, u64)>,
}

impl Merger {
    pub fn add(&mut self, part: Part) -> Result<()> {
        let range = part.range();
        if let Some(&(a, b)) = self
            .ranges
            .iter()
            .find(|&&(a, b)| range.0 < b && a < range.1)
        {
            return Err(Error::InvalidSetting(format!(
                "parts overlap: {}..{} and {a}..{b}",
                range.0, range.1
            )));
        }
        match (&mut self.sum, part) {
            (None, part) => self.sum = Some(part),
            (Some(Part::Passes(sum)), Part::Passes(p)) => {
                sum.add_passes(&p)?;
            }
            (Some(Part::Samples(sum, origin)), Part::Samples(s, o)) => {
                if (&o.scene_hash, &o.settings) != (&origin.scene_hash, &origin.settings) {
                    return Err(Error::InvalidSetting(
                        "the parts differ in scene or settings".into(),
                    ));
                }
                sum.add(&s)?;
                origin.first_sample = origin.first_sample.min(o.first_sample);
            }
            _ => {
                return Err(Error::InvalidSetting(
                    "ppm parts and sample parts cannot be merged together".into(),
                ));
            }
        }
        self.ranges.push(range);
        Ok(())
    }

    /// How many passes or samples per pixel the merged image holds.
    pub fn units(&self) -> u64 {
        self.ranges.iter().map(|(a, b)| b - a).sum()
    }

    /// The image of everything added; `None` before the first part.
    pub fn image(&self) -> Option<Image> {
        Some(match self.sum.as_ref()? {
            Part::Passes(state) => state.image(),
            Part::Samples(sums, _) => sums.image(),
        })
    }
}
