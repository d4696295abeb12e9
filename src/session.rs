//! A progressive render's run: passes under a budget (passes, time, or both), checkpoints at
//! a cadence, snapshot times, cancel and resume, once for every front end. The command line,
//! the Python module, the Blender add-on, job workers and [`crate::render_job::RenderJob`]
//! all drive a [`Session`]; they differ only in what they show and where they write.
//!
//! A finished run leaves no checkpoint unless its [`CheckpointPlan`] keeps one; an
//! interrupted or cancelled run leaves one (with every completed pass) to resume from.

use crate::error::{Error, Result, SettingError};
use crate::io::checkpoint::{self, RunInfo};
use crate::progressive::{PassSeconds, PassStats, ProgressiveState};
use crate::scene::Scene;
use crate::settings::MAX_PASSES;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// Checkpoints at least this often, and after the first pass.
pub const CHECKPOINT_EVERY: Duration = Duration::from_secs(30);
/// Snapshots after passes 1, 2, 4, 8, … and at least this often.
pub const SNAPSHOT_EVERY: Duration = Duration::from_secs(60);

/// How long a run may go on: until the pass before `passes` (a pass number, so a resumed
/// run counts on from its checkpoint), or `seconds` of this run, whichever comes first. A
/// time budget runs at least one pass.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Budget {
    pub passes: Option<u64>,
    pub seconds: Option<f64>,
}

impl Budget {
    /// A budget a run can keep: passes, a time or both; at least one pass; a positive,
    /// finite time.
    pub fn check(&self) -> Result<()> {
        let refuse = |name, value: Option<String>, problem: &str| {
            Err(Error::Setting(SettingError {
                name,
                value,
                problem: problem.into(),
            }))
        };
        match (self.passes, self.seconds) {
            (None, None) => {
                return refuse(
                    "passes",
                    None,
                    "a progressive render needs a number of passes or a time",
                );
            }
            (Some(p), _) if p > MAX_PASSES => {
                return refuse(
                    "passes",
                    Some(p.to_string()),
                    &format!("must be at most {MAX_PASSES}"),
                );
            }
            (Some(0), _) => {
                return refuse(
                    "passes",
                    Some("0".into()),
                    "a render needs at least one pass",
                );
            }
            (_, Some(s)) if !(s > 0.0 && s.is_finite()) => {
                return refuse(
                    "time",
                    Some(s.to_string()),
                    "must be a positive number of seconds",
                );
            }
            _ => {}
        }
        Ok(())
    }
}

/// Where and how often a run saves its state.
#[derive(Clone, Debug)]
pub struct CheckpointPlan {
    pub path: PathBuf,
    pub info: RunInfo,
    pub every: Duration,
    /// Keep the checkpoint when the run finishes (to extend it later); otherwise it is
    /// removed then, and kept only by an interrupted run.
    pub keep: bool,
}

/// What the passes of a run did.
#[derive(Clone, Copy, Debug, Default)]
pub struct Totals {
    pub photons: u64,
    pub rays: u64,
    pub seconds: PassSeconds,
}

/// How a run ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ending {
    /// The budget was spent.
    Finished,
    /// Stopped or cancelled: the completed passes are kept.
    Interrupted,
}

/// A progressive render being run.
pub struct Session {
    state: ProgressiveState,
    budget: Budget,
    checkpoint: Option<CheckpointPlan>,
    /// The pass this run started at: a time budget runs at least one pass past it.
    first: u64,
    started: Option<Instant>,
    last_checkpoint: Option<Instant>,
    last_snapshot: Option<Instant>,
    totals: Totals,
}

impl Session {
    /// A run of `state` (fresh, or loaded from a checkpoint) under `budget`.
    pub fn new(state: ProgressiveState, budget: Budget) -> Result<Self> {
        budget.check()?;
        Ok(Self {
            first: state.next_pass(),
            state,
            budget,
            checkpoint: None,
            started: None,
            last_checkpoint: None,
            last_snapshot: None,
            totals: Totals::default(),
        })
    }

    /// Save checkpoints as `plan` says.
    pub fn with_checkpoints(mut self, plan: CheckpointPlan) -> Self {
        self.checkpoint = Some(plan);
        self
    }

    /// A run continued from the checkpoint at `path`, saving to it again (and keeping it,
    /// since it was there before); its budget counts on from the checkpoint's passes.
    pub fn resume(path: &Path, budget: Budget) -> Result<(Self, RunInfo)> {
        let (state, info) = checkpoint::load_with(path)?;
        let budget = Budget {
            passes: budget.passes.or(if budget.seconds.is_some() {
                None
            } else {
                info.target_passes
            }),
            seconds: budget.seconds,
        };
        if let Some(target) = budget.passes
            && target != 0
            && target <= state.next_pass()
        {
            return Err(Error::Setting(SettingError {
                name: "passes",
                value: Some(target.to_string()),
                problem: format!(
                    "the checkpoint already holds passes up to {}; give more to go on",
                    state.next_pass()
                ),
            }));
        }
        let plan = CheckpointPlan {
            // Absolute: the process may change folders while it runs.
            path: std::path::absolute(path).unwrap_or_else(|_| path.to_owned()),
            // The run's output, exposure and environment stay; its target is this run's, or
            // the run's own under a time budget.
            info: RunInfo {
                target_passes: budget.passes.or(info.target_passes),
                ..info.clone()
            },
            every: CHECKPOINT_EVERY,
            keep: true,
        };
        Ok((Self::new(state, budget)?.with_checkpoints(plan), info))
    }

    /// Checkpoint at least every `every` (after the first pass, and on interrupts, as always).
    pub fn with_checkpoint_every(mut self, every: Duration) -> Self {
        if let Some(plan) = &mut self.checkpoint {
            plan.every = every;
        }
        self
    }

    pub fn state(&self) -> &ProgressiveState {
        &self.state
    }

    /// The state, leaving checkpoints as they are.
    pub fn into_state(self) -> ProgressiveState {
        self.state
    }

    pub fn budget(&self) -> Budget {
        self.budget
    }

    pub fn totals(&self) -> &Totals {
        &self.totals
    }

    /// Seconds since the first pass of this run began.
    pub fn elapsed(&self) -> f64 {
        self.started.map_or(0.0, |s| s.elapsed().as_secs_f64())
    }

    /// Whether the budget is spent.
    pub fn is_done(&self) -> bool {
        let next = self.state.next_pass();
        self.budget.passes.is_some_and(|t| next >= t)
            || (next > self.first && self.budget.seconds.is_some_and(|s| self.elapsed() >= s))
    }

    /// Run the next pass, unless the budget is spent (then `None`). Setting `abandon`
    /// abandons the pass in flight (`Error::Cancelled`) and leaves the state as it was. Saves a
    /// checkpoint after the first pass and then at the plan's cadence.
    pub fn next_pass(&mut self, scene: &Scene, abandon: &AtomicBool) -> Result<Option<PassStats>> {
        if self.is_done() {
            return Ok(None);
        }
        self.started.get_or_insert_with(Instant::now);
        let stats = self.state.run_pass_cancellable(scene, abandon)?;
        self.totals.photons += stats.photons_emitted;
        self.totals.rays += stats.rays.total();
        self.totals.seconds.camera += stats.seconds.camera;
        self.totals.seconds.photons += stats.seconds.photons;
        self.totals.seconds.gather += stats.seconds.gather;
        if let Some(plan) = &self.checkpoint
            && self
                .last_checkpoint
                .is_none_or(|t| t.elapsed() >= plan.every)
        {
            checkpoint::save_with(&self.state, &plan.info, &plan.path)?;
            self.last_checkpoint = Some(Instant::now());
        }
        Ok(Some(stats))
    }

    /// Save the checkpoint now, if the run has one and a completed pass (an interrupt
    /// that the caller may follow with more passes).
    pub fn save_checkpoint(&mut self) -> Result<()> {
        if let Some(plan) = &self.checkpoint
            && self.state.passes > 0
        {
            checkpoint::save_with(&self.state, &plan.info, &plan.path)?;
            self.last_checkpoint = Some(Instant::now());
        }
        Ok(())
    }

    /// Whether a snapshot of the image is due after the pass just run: after passes 1, 2, 4,
    /// 8, … and at least every [`SNAPSHOT_EVERY`]. Asking marks it taken.
    pub fn take_snapshot(&mut self) -> bool {
        let due = self.state.passes.is_power_of_two()
            || self
                .last_snapshot
                .is_none_or(|t| t.elapsed() >= SNAPSHOT_EVERY);
        if due {
            self.last_snapshot = Some(Instant::now());
        }
        due
    }

    /// Passes until the budget is spent, `stop` is set (the pass in flight finishes) or
    /// `abandon` is set (the pass in flight is dropped); `after_pass` sees each pass.
    pub fn run(
        &mut self,
        scene: &Scene,
        stop: &AtomicBool,
        abandon: &AtomicBool,
        mut after_pass: impl FnMut(&mut Self, &PassStats) -> Result<()>,
    ) -> Result<Ending> {
        loop {
            if stop.load(Ordering::SeqCst) {
                return Ok(Ending::Interrupted);
            }
            match self.next_pass(scene, abandon) {
                Ok(Some(stats)) => after_pass(self, &stats)?,
                Ok(None) => return Ok(Ending::Finished),
                Err(Error::Cancelled) => return Ok(Ending::Interrupted),
                Err(e) => return Err(e),
            }
        }
    }

    /// End the run: an interrupted run (or one whose plan keeps it) saves its checkpoint; a
    /// finished one removes the checkpoint it wrote. Returns the state.
    pub fn finish(self, ending: Ending) -> Result<ProgressiveState> {
        if let Some(plan) = &self.checkpoint {
            if ending == Ending::Interrupted || plan.keep {
                if self.state.passes > 0 {
                    checkpoint::save_with(&self.state, &plan.info, &plan.path)?;
                }
            } else if self.last_checkpoint.is_some() {
                match std::fs::remove_file(&plan.path) {
                    Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
                        return Err(Error::Write {
                            path: plan.path.clone(),
                            source: e,
                        });
                    }
                    _ => {}
                }
            }
        }
        Ok(self.state)
    }
}
