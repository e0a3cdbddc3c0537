//! A sweep of a run-time model kept in columns: each value of every sample
//! in one vector per kind (q, q', q'', points, frames, diagnostics), filled
//! as the sweep streams its samples, with no allocation per sample; read
//! by the library's CSV, text and animation through [`Table`].

use kinematics_core::runtime::{Flat, Model, Motion, PointState, SweepEnd};
use kinematics_core::sweep::{Layout, Stop, Table};
use kinematics_core::{Coordinate, FrameState, Kind};

/// The samples of a sweep, by column.
pub(crate) struct Columns {
    variable: &'static str,
    kind: Kind,
    coordinates: Vec<Coordinate>,
    point_names: Vec<&'static str>,
    frame_names: Vec<&'static str>,
    dim: usize,
    pub at: Vec<f64>,
    /// q, q', q'' (samples × coordinates each).
    pub q: [Vec<f64>; 3],
    /// Every point's position, velocity and acceleration (samples ×
    /// points × 3 × dim).
    pub points: Vec<f64>,
    /// Every frame (samples × frames).
    pub frames: Vec<FrameState>,
    pub conditioning: Vec<f64>,
    pub det_sign: Vec<f64>,
    pub residual: Vec<f64>,
    pub stop: Option<Stop>,
    pub change_points: Vec<f64>,
}

impl Columns {
    /// Empty columns for a sweep of `variable` (of `kind`) of `m`, with
    /// room for `rows` samples.
    pub(crate) fn new(m: &Model, variable: &'static str, kind: Kind, rows: usize) -> Self {
        let (nc, np, nf, dim) = (
            m.coordinates().len(),
            m.point_names().len(),
            m.frame_names().len(),
            m.point_dimension(),
        );
        Self {
            variable,
            kind,
            coordinates: m.coordinates().to_vec(),
            point_names: m.point_names().to_vec(),
            frame_names: m.frame_names().to_vec(),
            dim,
            at: Vec::with_capacity(rows),
            q: [
                Vec::with_capacity(rows * nc),
                Vec::with_capacity(rows * nc),
                Vec::with_capacity(rows * nc),
            ],
            points: Vec::with_capacity(rows * np * 3 * dim),
            frames: Vec::with_capacity(rows * nf),
            conditioning: Vec::with_capacity(rows),
            det_sign: Vec::with_capacity(rows),
            residual: Vec::with_capacity(rows),
            stop: None,
            change_points: Vec::new(),
        }
    }

    /// The swept driver's name.
    pub(crate) fn variable(&self) -> &'static str {
        self.variable
    }

    /// Appends a sample, from the flat arrays of the stepper that solved
    /// it.
    pub(crate) fn push(&mut self, at: f64, m: &Flat<'_>) {
        self.at.push(at);
        self.q[0].extend_from_slice(m.q);
        self.q[1].extend_from_slice(m.qd);
        self.q[2].extend_from_slice(m.qdd);
        let points = self.point_names.len() * 3 * self.dim;
        let (p, frames) = m.outputs.split_at(points.min(m.outputs.len()));
        self.points.extend_from_slice(p);
        for f in frames.chunks_exact(24) {
            if let Ok(values) = <&[f64; 24]>::try_from(f) {
                self.frames.push(FrameState::from_values(values));
            }
        }
        self.conditioning.push(m.conditioning);
        self.det_sign.push(m.det_sign);
        self.residual.push(m.residual);
    }

    /// Appends a sample from a motion already solved (a forward
    /// simulation's samples), in the layout of [`Columns::push`].
    pub(crate) fn push_motion(&mut self, at: f64, m: &Motion) {
        self.at.push(at);
        self.q[0].extend_from_slice(&m.q);
        self.q[1].extend_from_slice(&m.qd);
        self.q[2].extend_from_slice(&m.qdd);
        for p in &m.points {
            for v in [&p.position, &p.velocity, &p.acceleration] {
                self.points.extend_from_slice(v);
            }
        }
        self.frames.extend_from_slice(&m.frames);
        self.conditioning.push(m.conditioning);
        self.det_sign.push(m.det_sign);
        self.residual.push(m.residual);
    }

    /// The data columns moved out, leaving them empty (the names, the
    /// frames, the stop and the change points stay): `at`, q, q', q'',
    /// the points, the conditioning, the sign and the residual, for numpy
    /// arrays that take them without a copy.
    pub(crate) fn take_data(&mut self) -> [Vec<f64>; 8] {
        let [q, qd, qdd] = &mut self.q;
        [
            &mut self.at,
            q,
            qd,
            qdd,
            &mut self.points,
            &mut self.conditioning,
            &mut self.det_sign,
            &mut self.residual,
        ]
        .map(std::mem::take)
    }

    /// These columns with the data `data` (in the order of
    /// [`Columns::take_data`]) copied back in: for the tables, the CSV,
    /// the text, the animation and the deviations, which read them here.
    pub(crate) fn with_data(&self, data: [&[f64]; 8]) -> Self {
        let [at, q, qd, qdd, points, conditioning, det_sign, residual] = data.map(<[f64]>::to_vec);
        Self {
            variable: self.variable,
            kind: self.kind,
            coordinates: self.coordinates.clone(),
            point_names: self.point_names.clone(),
            frame_names: self.frame_names.clone(),
            dim: self.dim,
            at,
            q: [q, qd, qdd],
            points,
            frames: self.frames.clone(),
            conditioning,
            det_sign,
            residual,
            stop: self.stop.clone(),
            change_points: self.change_points.clone(),
        }
    }

    /// Records how the sweep ended.
    pub(crate) fn end(&mut self, end: SweepEnd) {
        self.stop = end.stop;
        self.change_points = end.change_points;
    }

    /// Sample i's motion into `out` (whose vectors are reused); returns
    /// its swept value.
    pub(crate) fn motion(&self, i: usize, out: &mut Motion) -> f64 {
        let (nc, np, nf, d) = (
            self.coordinates.len(),
            self.point_names.len(),
            self.frame_names.len(),
            self.dim,
        );
        for (k, v) in [&mut out.q, &mut out.qd, &mut out.qdd]
            .into_iter()
            .enumerate()
        {
            v.clear();
            v.extend_from_slice(&self.q[k][i * nc..(i + 1) * nc]);
        }
        out.points.resize(np, PointState::zeros(d));
        for (k, p) in out.points.iter_mut().enumerate() {
            let [r, v, a] = self.point(i, k);
            p.position.clone_from_slice(r);
            p.velocity.clone_from_slice(v);
            p.acceleration.clone_from_slice(a);
        }
        out.frames.clear();
        out.frames
            .extend_from_slice(&self.frames[i * nf..(i + 1) * nf]);
        out.conditioning = self.conditioning[i];
        out.det_sign = self.det_sign[i];
        out.residual = self.residual[i];
        self.at[i]
    }
}

impl Table for Columns {
    fn layout(&self) -> Layout<'_> {
        Layout {
            variable: self.variable,
            kind: self.kind,
            coordinates: &self.coordinates,
            points: &self.point_names,
            frames: &self.frame_names,
            point_dim: self.dim,
        }
    }
    fn rows(&self) -> usize {
        self.at.len()
    }
    fn at(&self, i: usize) -> f64 {
        self.at[i]
    }
    fn coordinate(&self, i: usize, j: usize, order: usize) -> f64 {
        let nc = self.coordinates.len();
        self.q[order.min(2)][i * nc + j]
    }
    fn point(&self, i: usize, k: usize) -> [&[f64]; 3] {
        let (np, d) = (self.point_names.len(), self.dim);
        let base = (i * np + k) * 3 * d;
        let p = &self.points[base..base + 3 * d];
        [&p[..d], &p[d..2 * d], &p[2 * d..]]
    }
    fn frame(&self, i: usize, f: usize) -> &FrameState {
        &self.frames[i * self.frame_names.len() + f]
    }
    fn stop(&self) -> Option<&Stop> {
        self.stop.as_ref()
    }
}
