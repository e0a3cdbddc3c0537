//! Batches of designs of one run-time model: every design (a set of
//! parameter values) stepped at one pose or swept, only the outputs asked
//! for kept, written where they are returned.
//!
//! A batch costs what its steps cost: each worker keeps one copy of the
//! model and sets each design's values into it (no compilation, no copy
//! of the model per design), each sample's outputs are copied from the
//! stepper's arrays straight into the design's record of the result (no
//! collection per design, no second copy), and the sweep is the one
//! sweep driver, so that a design's samples, stop and change points are
//! those of [`Model::sweep`] with its values. A batch of positions only
//! ([`Batch::positions_only`]) assembles each sample as
//! [`SweepBuilder::for_each_pose`](super::SweepBuilder::for_each_pose)
//! does, with no velocity or acceleration analysis. Where the model's
//! machine code has its form in lanes, the designs go in pairs, two per
//! instruction ([`Batch::in_lanes`]), each design's record still its own
//! sweep's, bit for bit.

use alloc::vec;
use alloc::vec::Vec;
use core::fmt;

mod lanes;
mod steps;

use super::drive::Sink;
use super::stepper::FlatAt;
use super::{Flat, Model, Motion, Stepper};
use crate::error::Error;
use crate::options::Options;
use crate::sweep::{ChangePoints, Stop};

/// What a batch keeps of each sample of each design.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Output {
    /// Coordinate j (drivers first): q_j.
    Coordinate(usize),
    /// Its rate q̇_j.
    Rate(usize),
    /// Its acceleration q̈_j.
    Acceleration(usize),
    /// Point i's position r (in declaration order;
    /// [`Model::point_dimension`] components).
    Position(usize),
    /// Point i's velocity v = ṙ.
    Velocity(usize),
    /// Point i's acceleration a = v̇.
    PointAcceleration(usize),
    /// The conditioning of Φ_u ([`Motion::conditioning`]).
    Conditioning,
}

/// What a batch keeps of each output over a design's samples: every
/// sample, or one value per design (NaN for a design with no sample),
/// so that a study of many designs keeps what it reduces them to and
/// not every sample.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Reduce {
    /// Every sample, a row each.
    #[default]
    Samples,
    /// The largest value of each component over the samples.
    Max,
    /// The smallest value of each component over the samples.
    Min,
    /// The peak: the largest magnitude over the samples, |x| of a
    /// coordinate, the Euclidean norm √(Σ xᵢ²) of a point's vector (one
    /// value per design).
    Peak,
}

/// The sweep every design of a batch runs: as [`Model::sweep`] of driver
/// `driver` (its index among the coordinates) with the builder's
/// settings; `to` before `turns` where both are given.
#[derive(Clone, Debug, PartialEq)]
pub struct BatchSweep {
    /// The swept driver's index (a driver: below [`Model::drivers`]).
    pub driver: usize,
    /// The first value ([`SweepBuilder::from`](super::SweepBuilder::from)); the start's value if `None`.
    pub from: Option<f64>,
    /// The last value, included ([`SweepBuilder::to`](super::SweepBuilder::to)).
    pub to: Option<f64>,
    /// Whole turns ([`SweepBuilder::turns`](super::SweepBuilder::turns)), the end left out.
    pub turns: Option<f64>,
    /// The steps.
    pub steps: usize,
    /// What to do at a change point.
    pub change_points: ChangePoints,
}

impl BatchSweep {
    /// The samples of a sweep that runs to its end: steps + 1 with a
    /// given end (included), else steps (a whole turn leaves its end out).
    fn samples(&self) -> usize {
        self.steps.max(1) + usize::from(self.to.is_some())
    }
}

/// Why a design of a batch ended before its last sample.
#[derive(Clone, Debug, PartialEq)]
pub enum Early {
    /// Its sweep stopped: a limit position, a change point, a failure.
    Stopped(Stop),
    /// It did not run: invalid parameter values, or the step failed.
    Failed(Error),
}

impl fmt::Display for Early {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Stopped(s) => write!(f, "{s}"),
            Self::Failed(e) => write!(f, "{e}"),
        }
    }
}

/// Where an output's values come from in a sample's flat arrays.
#[derive(Clone, Copy, Debug)]
enum From {
    Q,
    Qd,
    Qdd,
    Outputs,
    Conditioning,
    /// The points' positions of a pose (positions only).
    Positions,
}

/// An output as copied: `width` values from `at` in the arrays of `from`
/// into the record at `dest` + row × `width` (every sample), or reduced
/// into the `kept` values at `dest`.
#[derive(Clone, Copy, Debug)]
struct Slot {
    from: From,
    at: usize,
    width: usize,
    kept: usize,
    dest: usize,
}

impl Slot {
    /// Where the slot's first value lies in a fused step's buffer laid
    /// out as `at` says (`None` for the points' positions of a pose).
    #[inline(always)]
    fn in_buffer(&self, at: &FlatAt) -> Option<usize> {
        let base = match self.from {
            From::Q => at.q,
            From::Qd => at.qd,
            From::Qdd => at.qdd,
            From::Outputs => at.out,
            From::Conditioning => at.conditioning,
            From::Positions => return None,
        };
        Some(base + self.at)
    }
}

/// A batch of designs of one model: the pose each design starts from, the
/// rates and accelerations of its drivers, the sweep it runs (or one step
/// at the start), the outputs kept and the options. Made once, run on any
/// number of designs ([`Batch::run`]).
///
/// The results of design d are its record: for each output k in turn,
/// [`Batch::rows`] × [`Batch::width`]`(k)` values, row r the r-th sample
/// (NaN past the samples the design has).
///
/// ```
/// use kinematics_core::runtime::{Batch, BatchSweep, Model, Output};
/// use kinematics_core::sweep::ChangePoints;
/// use kinematics_core::Options;
/// let m = Model::compile(
///     "struct SliderCrank {
///          params   { a, b }
///          drivers  { phi }
///          unknowns { th, x }
///          loops    { polar(a, phi) + polar(b, th) == vec2(x, 0.0); }
///      }",
/// )?;
/// let sweep = BatchSweep { driver: 0, from: None, to: None, turns: Some(1.0), steps: 360, change_points: ChangePoints::Stop };
/// let batch = Batch::new(&m, &[0.0, 0.0, 0.4], &[1.0], &[0.0], Some(sweep), &[Output::Coordinate(2)], &Options::DEFAULT)?;
/// // Three designs: crank 0.1 and rods 0.3, 0.4 and 0.05, which stops at
/// // the limit position a sin φ = b (φ = 30°, the sweep's 31st degree).
/// let results = batch.run(&[0.1, 0.3, 0.1, 0.4, 0.1, 0.05]);
/// let stroke = |d: usize| {
///     let x = results.output(&batch, d, 0);
///     x.iter().copied().fold(f64::NEG_INFINITY, f64::max) - x.iter().copied().fold(f64::INFINITY, f64::min)
/// };
/// // The slider's stroke is twice the crank.
/// assert!((stroke(0) - 0.2).abs() < 1e-12 && (stroke(1) - 0.2).abs() < 1e-12);
/// assert_eq!(results.samples[..2], [360, 360]);
/// assert!(results.early[2].is_some() && (30..=31).contains(&results.samples[2]));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug)]
pub struct Batch<'m> {
    model: &'m Model,
    start: Vec<f64>,
    rates: Vec<f64>,
    accelerations: Vec<f64>,
    sweep: Option<BatchSweep>,
    options: Options,
    slots: Vec<Slot>,
    /// The samples a design has at most.
    samples: usize,
    reduce: Reduce,
    record: usize,
    /// Positions only ([`Batch::positions_only`]).
    poses: bool,
    /// Designs in pairs in vector lanes: where they can be, if asked;
    /// never; or `None`, where they can be and the batch is large
    /// enough to pay for the code's compilation ([`Batch::in_lanes`]).
    lanes: Option<bool>,
}

/// The results of a batch: the designs' records one after the other
/// ([`Batch`]), the samples each design has, and why it ended early.
#[derive(Clone, Debug, PartialEq)]
pub struct BatchResults {
    /// Design d's record at `values[d · record .. (d + 1) · record]`.
    pub values: Vec<f64>,
    /// The values per design.
    pub record: usize,
    /// The samples each design has.
    pub samples: Vec<usize>,
    /// Why each design ended before its last sample (`None` if it did not).
    pub early: Vec<Option<Early>>,
}

impl BatchResults {
    /// Output `k`'s values of design `d`: [`Batch::rows`] ×
    /// [`Batch::width`]`(k)`, row by row (empty past the last design).
    #[must_use]
    pub fn output(&self, batch: &Batch<'_>, d: usize, k: usize) -> &[f64] {
        let Some(s) = batch.slots.get(k) else {
            return &[];
        };
        let at = d * self.record + s.dest;
        self.values
            .get(at..at + batch.rows() * s.kept)
            .unwrap_or(&[])
    }
}

impl<'m> Batch<'m> {
    /// A batch of designs of `model`: each starts from the pose `start`
    /// (drivers first), its drivers at `rates` and `accelerations` (one
    /// each; for a sweep, the swept driver's entries are the sweep's),
    /// runs `sweep` (or one step at `start`), and keeps `outputs`.
    ///
    /// # Errors
    /// [`Error::WrongLength`] for a start, rates or accelerations of the
    /// wrong length; [`Error::InvalidOption`] for an output or a driver
    /// the model does not have, no output at all, or invalid options.
    pub fn new(
        model: &'m Model,
        start: &[f64],
        rates: &[f64],
        accelerations: &[f64],
        sweep: Option<BatchSweep>,
        outputs: &[Output],
        options: &Options,
    ) -> Result<Self, Error> {
        options.validate()?;
        let (n, nd) = (model.coordinates.len(), model.drivers);
        model.length("start pose", n, start.len())?;
        model.length("driver rates", nd, rates.len())?;
        model.length("driver accelerations", nd, accelerations.len())?;
        let invalid = |name: &'static str, value: usize| {
            #[allow(clippy::cast_precision_loss)]
            let value = value as f64;
            Error::InvalidOption {
                name: crate::names::intern(name),
                value,
                requirement: "must be an index the model has",
            }
        };
        if let Some(s) = &sweep
            && s.driver >= nd
        {
            return Err(invalid("swept driver", s.driver));
        }
        let samples = sweep.as_ref().map_or(1, BatchSweep::samples);
        let (points, dim) = (model.points.len(), model.point_dim);
        let mut slots = Vec::with_capacity(outputs.len());
        for o in outputs {
            let (from, at, width, limit, what) = match *o {
                Output::Coordinate(j) => (From::Q, j, 1, n, "coordinate"),
                Output::Rate(j) => (From::Qd, j, 1, n, "coordinate"),
                Output::Acceleration(j) => (From::Qdd, j, 1, n, "coordinate"),
                Output::Position(i) => (From::Outputs, 3 * i * dim, dim, points, "point"),
                Output::Velocity(i) => (From::Outputs, (3 * i + 1) * dim, dim, points, "point"),
                Output::PointAcceleration(i) => {
                    (From::Outputs, (3 * i + 2) * dim, dim, points, "point")
                }
                Output::Conditioning => (From::Conditioning, 0, 1, 1, "output"),
            };
            let index = match *o {
                Output::Coordinate(j) | Output::Rate(j) | Output::Acceleration(j) => j,
                Output::Position(i) | Output::Velocity(i) | Output::PointAcceleration(i) => i,
                Output::Conditioning => 0,
            };
            if index >= limit {
                return Err(invalid(what, index));
            }
            slots.push(Slot {
                from,
                at,
                width,
                kept: width,
                dest: 0,
            });
        }
        if slots.is_empty() {
            return Err(Error::InvalidOption {
                name: crate::names::intern("outputs"),
                value: 0.0,
                requirement: "must name at least one output to keep",
            });
        }
        let mut batch = Self {
            model,
            start: start.to_vec(),
            rates: rates.to_vec(),
            accelerations: accelerations.to_vec(),
            sweep,
            options: *options,
            slots,
            samples,
            reduce: Reduce::Samples,
            record: 0,
            poses: false,
            lanes: None,
        };
        batch.lay_out();
        Ok(batch)
    }

    /// The batch of positions only: each sample assembled from the last
    /// (the closed-form blocks in the start's modes) and the points'
    /// positions evaluated, with no rates, accelerations or conditioning,
    /// as [`SweepBuilder::for_each_pose`](super::SweepBuilder::for_each_pose)
    /// sweeps: what coupler curves and data sets of paths need, for less
    /// than a step costs (1.07–1.24× the stepper's `pose` per position in
    /// the benchmark). A sweep then stops only where the mechanism does
    /// not assemble (a limit position): a change point is passed on the
    /// branch the closed forms carry, whatever the sweep's
    /// `change_points`, and the rates and accelerations given are not
    /// read.
    ///
    /// # Errors
    /// [`Error::InvalidOption`] when an output is not a coordinate's value
    /// or a point's position.
    pub fn positions_only(mut self) -> Result<Self, Error> {
        let dim = self.model.point_dim;
        for (k, s) in self.slots.iter_mut().enumerate() {
            match s.from {
                From::Q | From::Positions => {}
                // A point's position lies at 3 i dim among the outputs,
                // at i dim among a pose's positions.
                From::Outputs if s.at % (3 * dim) == 0 => {
                    s.from = From::Positions;
                    s.at /= 3;
                }
                _ => {
                    #[allow(clippy::cast_precision_loss)]
                    let value = k as f64;
                    return Err(Error::InvalidOption {
                        name: crate::names::intern("output of a batch of positions only"),
                        value,
                        requirement: "must be a coordinate's value or a point's position (a \
                                      batch of positions only has no rates, accelerations or \
                                      conditioning)",
                    });
                }
            }
        }
        self.poses = true;
        Ok(self)
    }

    /// The batch with its designs taken in pairs, each pair's poses, or
    /// steps with rates and accelerations, by the machine code in vector
    /// lanes (two f64 per instruction), where it applies
    /// ([`Batch::in_pairs`]), or not (`on` false: each design alone).
    /// The results are each design's sweep's either way, bit for bit: a
    /// pose or step where a design leaves the common path is taken by
    /// each design's stepper; a pair of poses in which a design fails a
    /// check (a limit position ahead, say) is swept alone, design by
    /// design, from its start; a pair of steps goes on alone, each
    /// design's sweep from the sample where either leaves its common
    /// path (a change of branch ahead, a limit), and takes a step alone
    /// where a check fails in lanes.
    ///
    /// Unless this is called, a batch takes its designs in pairs where it
    /// applies and either the model's code in lanes is compiled already
    /// or the batch is large enough to pay for compiling it: at least
    /// [`Batch::LANES_FROM_STEPS`] positions (designs × samples) of
    /// steps, or [`Batch::LANES_FROM_POSES`] of positions only.
    #[must_use]
    pub fn in_lanes(mut self, on: bool) -> Self {
        self.lanes = Some(on);
        self
    }

    /// The batch keeping `reduce` of each output over a design's samples
    /// (every sample by default).
    #[must_use]
    pub fn reduced(mut self, reduce: Reduce) -> Self {
        self.reduce = reduce;
        self.lay_out();
        self
    }

    /// Places the outputs one after the other in a design's record.
    fn lay_out(&mut self) {
        let rows = self.rows();
        let mut dest = 0;
        for s in &mut self.slots {
            s.kept = if self.reduce == Reduce::Peak {
                1
            } else {
                s.width
            };
            s.dest = dest;
            dest += rows * s.kept;
        }
        self.record = dest;
    }

    /// The rows of each output in a design's record: the samples of a
    /// design that runs to its end (1 for a step, the sweep's samples
    /// otherwise), 1 where the outputs are reduced.
    #[must_use]
    pub fn rows(&self) -> usize {
        if self.reduce == Reduce::Samples {
            self.samples
        } else {
            1
        }
    }

    /// The values per row of output `k` (0 past the last output).
    #[must_use]
    pub fn width(&self, k: usize) -> usize {
        self.slots.get(k).map_or(0, |s| s.kept)
    }

    /// The values of a design's record.
    #[must_use]
    pub fn record(&self) -> usize {
        self.record
    }

    /// Where output `k`'s values start in a design's record ([`Batch::rows`]
    /// × [`Batch::width`]`(k)` of them, row by row; `None` past the last
    /// output): so that the records of every design, taken as one
    /// designs × [`Batch::record`] array, hold each output as the columns
    /// `offset .. offset + rows · width` of its rows.
    #[must_use]
    pub fn offset(&self, k: usize) -> Option<usize> {
        self.slots.get(k).map(|s| s.dest)
    }

    /// Runs the designs of `designs` (row-major: one value per parameter,
    /// in declaration order, per design), on every core with the feature
    /// `parallel`; a trailing partial row is not a design.
    #[must_use]
    pub fn run(&self, designs: &[f64]) -> BatchResults {
        let width = self.model.params.len().max(1);
        let count = designs.len() / width;
        let mut values = vec![f64::NAN; count * self.record];
        let ends = self.run_into(&designs[..count * width], &mut values);
        let (samples, early) = ends.into_iter().unzip();
        BatchResults {
            values,
            record: self.record,
            samples,
            early,
        }
    }

    #[cfg(feature = "parallel")]
    fn run_into(&self, designs: &[f64], values: &mut [f64]) -> Vec<(usize, Option<Early>)> {
        use rayon::prelude::*;
        let width = self.model.params.len().max(1);
        let record = self.record.max(1);
        if self.pairs_for(designs.len() / width) {
            let pairs: Vec<Vec<(usize, Option<Early>)>> = values
                .par_chunks_mut(2 * record)
                .zip(designs.par_chunks(2 * width))
                .map_init(
                    || (self.model.clone(), self.model.clone()),
                    |(a, b), (out, d)| self.two(a, b, d, out),
                )
                .collect();
            return pairs.into_iter().flatten().collect();
        }
        values
            .par_chunks_mut(record)
            .zip(designs.par_chunks(width))
            .map_init(|| self.model.clone(), |m, (out, d)| self.design(m, d, out))
            .collect()
    }

    #[cfg(not(feature = "parallel"))]
    fn run_into(&self, designs: &[f64], values: &mut [f64]) -> Vec<(usize, Option<Early>)> {
        let width = self.model.params.len().max(1);
        let record = self.record.max(1);
        if self.pairs_for(designs.len() / width) {
            let (mut a, mut b) = (self.model.clone(), self.model.clone());
            return values
                .chunks_mut(2 * record)
                .zip(designs.chunks(2 * width))
                .flat_map(|(out, d)| self.two(&mut a, &mut b, d, out))
                .collect();
        }
        let mut m = self.model.clone();
        values
            .chunks_mut(record)
            .zip(designs.chunks(width))
            .map(|(out, d)| self.design(&mut m, d, out))
            .collect()
    }

    /// Two designs (`d`: two rows of values, `out` their records), as a
    /// pair in lanes; one design (the last of an odd count) alone.
    fn two(
        &self,
        a: &mut Model,
        b: &mut Model,
        d: &[f64],
        out: &mut [f64],
    ) -> Vec<(usize, Option<Early>)> {
        let width = self.model.params.len().max(1);
        let record = self.record.max(1);
        if d.len() < 2 * width || out.len() < 2 * record {
            return vec![self.design(a, d, out)];
        }
        let (d0, d1) = d.split_at(width);
        let (o0, o1) = out.split_at_mut(record);
        self.pair([a, b], [d0, d1], [o0, o1]).into()
    }

    /// Runs one design with `model`'s values set to `values`, writing its
    /// record into `out` (whose entries past its samples are left as they
    /// are): its samples and why it ended early.
    fn design(&self, model: &mut Model, values: &[f64], out: &mut [f64]) -> (usize, Option<Early>) {
        if model.params.is_empty() {
            // A model without parameters: each row of one value is a
            // design of the same model.
        } else if let Err(e) = model.set_values(values) {
            return (0, Some(Early::Failed(e)));
        }
        let model = &*model;
        let mut keep = self.keep(model, out);
        if self.poses {
            return self.poses_of(model, &mut keep);
        }
        let Some(s) = &self.sweep else {
            // One step, as `Model::step` takes it.
            return match model.step(&self.start, &self.rates, &self.accelerations) {
                Ok(motion) => {
                    (&mut keep).motion(0.0, &motion);
                    (1, None)
                }
                Err(e) => (0, Some(Early::Failed(e))),
            };
        };
        let builder = match self.sweep_of(model, s) {
            Ok(b) => b
                .rate(self.rates[s.driver])
                .acceleration(self.accelerations[s.driver])
                .change_points(s.change_points),
            Err(e) => return (0, Some(Early::Failed(e))),
        };
        let end = builder.drive(&mut keep);
        (keep.row, end.stop.map(Early::Stopped))
    }

    /// [`Batch::design`] of positions only: the sweep's poses, or the one
    /// pose at the start.
    fn poses_of(&self, model: &Model, keep: &mut Keep<'_>) -> (usize, Option<Early>) {
        let put = |keep: &mut Keep<'_>, q: &[f64], r: &[f64]| keep.put_pose(q, r);
        let Some(s) = &self.sweep else {
            let mut stepper = match model.stepper(&self.options) {
                Ok(stepper) => stepper,
                Err(e) => return (0, Some(Early::Failed(e))),
            };
            let mut r = vec![0.0; model.points.len() * model.point_dim];
            let pose = stepper.pose(&self.start).map(<[f64]>::to_vec);
            return match pose.and_then(|q| stepper.positions(&mut r).map(|()| q)) {
                Ok(q) => {
                    put(keep, &q, &r);
                    (1, None)
                }
                Err(e) => (0, Some(Early::Failed(e))),
            };
        };
        let builder = match self.sweep_of(model, s) {
            Ok(b) => b,
            Err(e) => return (0, Some(Early::Failed(e))),
        };
        let end = builder.for_each_pose(|_, q, r| put(keep, q, r));
        (keep.row, end.stop.map(Early::Stopped))
    }

    /// The sweep `s` of `model` from the batch's start, with its grid and
    /// options (the rates and the rule at change points left to the
    /// caller).
    fn sweep_of<'a>(
        &self,
        model: &'a Model,
        s: &BatchSweep,
    ) -> Result<super::SweepBuilder<'a>, Error> {
        let name = model.coordinates[s.driver].name;
        let builder = model
            .sweep(name, &self.start)?
            .steps(s.steps)
            .options(&self.options);
        let builder = match s.from {
            Some(f) => builder.from(f),
            None => builder,
        };
        Ok(match (s.to, s.turns) {
            (Some(t), _) => builder.to(t),
            (None, Some(n)) => builder.turns(n),
            (None, None) => builder,
        })
    }
}

impl Batch<'_> {
    /// What keeps a design's samples of `model` in its record `out`.
    fn keep<'a>(&'a self, model: &'a Model, out: &'a mut [f64]) -> Keep<'a> {
        Keep {
            model,
            slots: &self.slots,
            out,
            row: 0,
            rows: self.samples,
            reduce: self.reduce,
            scratch: Vec::new(),
        }
    }
}

/// Copies each sample's outputs into a design's record.
struct Keep<'a> {
    /// The model whose layout of the outputs the slots read.
    model: &'a Model,
    slots: &'a [Slot],
    out: &'a mut [f64],
    row: usize,
    rows: usize,
    reduce: Reduce,
    /// A held-back motion's outputs, flattened.
    scratch: Vec<f64>,
}

impl Keep<'_> {
    /// Copies the outputs of the sample in `f` into the next row.
    #[inline(always)]
    fn put(&mut self, f: &Flat<'_>) {
        self.put_from(|s| {
            let from = match s.from {
                From::Q => f.q,
                From::Qd => f.qd,
                From::Qdd => f.qdd,
                From::Outputs => f.outputs,
                From::Conditioning => core::slice::from_ref(&f.conditioning),
                // Only a batch of positions only has them, which takes
                // no step.
                From::Positions => &[],
            };
            (from, s.at)
        });
    }

    /// [`Keep::put`] of the sample a fused step left in the stepper's
    /// buffer `buffer`, laid out as `at` says: each output read where it
    /// lies, without the slices of a [`Flat`].
    #[inline(always)]
    fn put_fused(&mut self, buffer: &[f64], at: &FlatAt) {
        self.put_from(|s| match s.in_buffer(at) {
            Some(i) => (buffer, i),
            // As in `put`: none in a step.
            None => (&[], 0),
        });
    }

    /// Keeps a pose `q` and its points' positions `r` as the next row.
    #[inline(always)]
    fn put_pose(&mut self, q: &[f64], r: &[f64]) {
        self.put_from(|s| match s.from {
            From::Positions => (r, s.at),
            _ => (q, s.at),
        });
    }

    /// Keeps each slot's values, which `source` says where to read (an
    /// array and the index of the first), as the next row.
    #[inline(always)]
    fn put_from<'b>(&mut self, source: impl Fn(&Slot) -> (&'b [f64], usize)) {
        let row = self.row;
        if row >= self.rows {
            return;
        }
        for s in self.slots {
            let (from, at) = source(s);
            keep(self.out, s, row, self.reduce, from, at);
        }
        self.row = row + 1;
    }
}

/// Keeps the values of slot `s` at `at` in `from`, of sample `row`, in
/// `out`: copied into its row, or combined with what is kept of the
/// rows before (`reduce`; the record starts as NaN).
#[inline(always)]
fn keep(out: &mut [f64], s: &Slot, row: usize, reduce: Reduce, from: &[f64], at: usize) {
    if reduce == Reduce::Samples {
        copy(out, s.dest + row * s.width, from, at, s.width);
        return;
    }
    let Some(v) = from.get(at..at + s.width) else {
        return;
    };
    let Some(kept) = out.get_mut(s.dest..s.dest + s.kept) else {
        return;
    };
    match reduce {
        Reduce::Peak => {
            let norm = v.iter().map(|x| x * x).sum::<f64>().sqrt();
            // NaN kept (no sample yet) is replaced.
            if let Some(k) = kept.first_mut()
                && (k.is_nan() || *k < norm)
            {
                *k = norm;
            }
        }
        Reduce::Max => {
            for (k, x) in kept.iter_mut().zip(v) {
                if k.is_nan() || *k < *x {
                    *k = *x;
                }
            }
        }
        _ => {
            for (k, x) in kept.iter_mut().zip(v) {
                if k.is_nan() || *k > *x {
                    *k = *x;
                }
            }
        }
    }
}

/// Copies `width` values of `from` at `at` into `out` at `dest` (nothing
/// where either range is out of bounds: a batch checks its slots against
/// the model when it is made): one, two or three values (a coordinate, a
/// planar or spatial vector) by hand, more by `copy_from_slice`.
#[inline(always)]
fn copy(out: &mut [f64], dest: usize, from: &[f64], at: usize, width: usize) {
    let (Some(d), Some(v)) = (out.get_mut(dest..dest + width), from.get(at..at + width)) else {
        return;
    };
    match (d, v) {
        ([d], [v]) => *d = *v,
        ([d0, d1], [v0, v1]) => (*d0, *d1) = (*v0, *v1),
        ([d0, d1, d2], [v0, v1, v2]) => (*d0, *d1, *d2) = (*v0, *v1, *v2),
        (d, v) => d.copy_from_slice(v),
    }
}

impl Sink for &mut Keep<'_> {
    #[inline(always)]
    fn stepped(&mut self, _: f64, stepper: &mut Stepper<'_>) {
        match stepper.fused_results() {
            Some((buffer, at)) => self.put_fused(buffer, at),
            None => self.put(&stepper.flat()),
        }
    }

    fn motion(&mut self, _: f64, motion: &Motion) {
        let mut scratch = core::mem::take(&mut self.scratch);
        self.model.flatten_outputs(motion, &mut scratch);
        self.put(&Flat {
            q: &motion.q,
            qd: &motion.qd,
            qdd: &motion.qdd,
            outputs: &scratch,
            conditioning: motion.conditioning,
            det_sign: motion.det_sign,
            residual: motion.residual,
        });
        self.scratch = scratch;
    }
}
