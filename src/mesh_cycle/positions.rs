//! The positions of one `flank run`, for every pair kind: each roll angle
//! taken from the checkpoint of an interrupted run or solved by the
//! [`MeshCycle`], its VTU file and CalculiX deck written as asked, the
//! checkpoint rewritten after it ([`crate::mesh_cycle::checkpoint`]), and
//! SIGINT polled between positions (what is solved is kept).

use std::path::{Path, PathBuf};

use crate::error::FlankError;
use crate::mesh_cycle::checkpoint::{Checkpoint, Position};
use crate::mesh_cycle::cycle::{MeshCycle, Solved, StepResult};
use crate::mesh_cycle::outputs::{self, position_records};
use crate::report::fe_pattern::PatternNode;
use crate::report::vtu::{vtu_name, write_vtu, PointField};

/// A position as the checkpoint keeps it: the step with its contact
/// pattern (which summary.json leaves out; empty for line contact).
#[derive(Clone, serde::Serialize, serde::Deserialize)]
struct KeptStep {
    step: StepResult,
    pattern: Vec<PatternNode>,
}

impl Position for KeptStep {
    fn roll_deg(&self) -> f64 {
        self.step.roll_deg
    }
}

/// What each position writes besides its result.
#[derive(Clone, Copy, Debug, Default)]
pub struct PositionFiles {
    /// `roll_…deg.vtu`: both bodies placed, displacement and pressure.
    pub vtu: bool,
    /// `roll_…deg.inp`: the position's problem as a CalculiX deck
    /// ([`MeshCycle::deck_model`]).
    pub decks: bool,
}

/// The positions of a run in `out`, solved or resumed one at a time.
pub struct Positions<'a> {
    cycle: &'a MeshCycle,
    out: PathBuf,
    files: PositionFiles,
    checkpoint: Checkpoint<KeptStep>,
}

impl<'a> Positions<'a> {
    /// Opens the run's checkpoint (`key`: [`crate::mesh_cycle::checkpoint::run_key`] of what
    /// determines a position's result); with `resume` the positions of a
    /// matching checkpoint are taken instead of solved.
    pub fn open(
        cycle: &'a MeshCycle,
        out: &Path,
        key: String,
        resume: bool,
        files: PositionFiles,
    ) -> Result<Self, FlankError> {
        Ok(Positions {
            cycle,
            out: out.to_path_buf(),
            files,
            checkpoint: Checkpoint::open(out, key, resume)?,
        })
    }

    /// The position at `roll_deg`: from the checkpoint, else solved (its
    /// files written, the checkpoint rewritten).
    pub fn solve(&mut self, roll_deg: f64) -> Result<StepResult, FlankError> {
        if let Some(k) = self.checkpoint.take(roll_deg)? {
            return Ok(StepResult {
                pattern: k.pattern,
                ..k.step
            });
        }
        let solved = self.cycle.solve(roll_deg)?;
        if self.files.vtu {
            write_position_vtu(self.cycle, &self.out, roll_deg, &solved)?;
        }
        if self.files.decks {
            let name = vtu_name(roll_deg).replace(".vtu", ".inp");
            self.cycle.write_deck(roll_deg, &self.out.join(name))?;
        }
        let step = solved.step;
        self.checkpoint.record(&KeptStep {
            pattern: step.pattern.clone(),
            step: step.clone(),
        })?;
        Ok(step)
    }

    /// After a position: the error of a run stopped by SIGINT, if one was
    /// asked for. The positions `steps` are in checkpoint.json (and their
    /// VTU files), and in `mesh_cycle.partial.csv` for a look; the message
    /// says how to resume.
    pub fn stop_requested(&self, steps: &[StepResult]) -> Option<FlankError> {
        if !crate::interrupt::requested() {
            return None;
        }
        let mut sorted = steps.to_vec();
        sorted.sort_by(|a, b| a.roll_deg.total_cmp(&b.roll_deg));
        let partial = self.out.join("mesh_cycle.partial.csv");
        let records = position_records(self.cycle, &sorted);
        let np = self.cycle.pair.teeth.len();
        let written = match outputs::write_mesh_cycle_csv(&partial, np, &records) {
            Ok(()) => format!(" and {}", partial.display()),
            Err(e) => format!(" ({e})"),
        };
        Some(FlankError::Interrupted(format!(
            "stopped at a position boundary after {} solved position(s); \
             they are kept in {}{written}; resume with the same command and options plus \
             --resume (`flank run SCENE --out {} ... --resume`): only the remaining positions \
             are solved",
            steps.len(),
            self.checkpoint.path().display(),
            self.out.display()
        )))
    }

    /// Positions taken from a resumed checkpoint.
    pub fn reused(&self) -> usize {
        self.checkpoint.reused()
    }

    /// The run is complete (summary.json holds every position): the
    /// checkpoint and a partial CSV of an earlier interrupt are removed.
    pub fn finish(self) -> Result<(), FlankError> {
        let partial = self.out.join("mesh_cycle.partial.csv");
        self.checkpoint.remove()?;
        let _ = std::fs::remove_file(partial);
        Ok(())
    }
}

/// `roll_…deg.vtu`: both bodies placed at the roll angle, displacement
/// (global frame) and contact pressure.
fn write_position_vtu(
    cycle: &MeshCycle,
    out: &Path,
    roll_deg: f64,
    solved: &Solved,
) -> Result<(), FlankError> {
    let placement = cycle.placement(roll_deg.to_radians());
    let mut mesh = cycle.pair.model.mesh.clone();
    mesh.coords = placement.positions(&mesh.coords);
    let u = placement.global_vectors(&solved.displacement);
    let p = out.join(vtu_name(roll_deg));
    write_vtu(
        &p,
        &mesh,
        &[
            PointField {
                name: "displacement",
                components: 3,
                values: &u,
            },
            PointField {
                name: "contact_pressure",
                components: 1,
                values: &solved.pressure,
            },
        ],
        &[],
    )
}
