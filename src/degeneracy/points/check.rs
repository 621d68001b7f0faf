//! Validation of each record before it reaches a sink: finite values (a
//! non-finite point is skipped and counted), coordinates within
//! [`MAX_COORDINATE`], a non-zero normal (renormalised when off unit length by
//! more than [`NORMAL_UNIT_TOL`]), a non-negative finite weight.

use super::record::Sink;
use crate::degeneracy::BLOCK;
use crate::diagnostic::{Code, Error, Warning};
use crate::tolerances::{MAX_COORDINATE, NORMAL_UNIT_TOL, NORMAL_ZERO_TOL};

/// What was wrong with one record.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Fault {
    Coordinate(f64),
    ZeroNormal([f64; 3]),
    Weight(f64),
}

impl Fault {
    /// The error, `what` naming the record ("point on line 4"), at `line`.
    pub(crate) fn error(self, what: String, line: Option<usize>) -> Error {
        let e = Error::parse(match self {
            Fault::Coordinate(x) => {
                format!("{what}: expected coordinates within +-{MAX_COORDINATE:e}, found {x:e}")
            }
            Fault::ZeroNormal(n) => format!(
                "{what}: expected a unit normal, found a zero normal [{}, {}, {}]",
                n[0], n[1], n[2]
            ),
            Fault::Weight(w) => {
                format!("{what}: expected a non-negative finite weight, found {w}")
            }
        });
        match line {
            Some(l) => e.at_line(l, None),
            None => e,
        }
    }
}

/// What the checks did to a file (summed over threads in any order).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct Stats {
    pub renormalised: usize,
    pub worst_norm_dev: f64,
    pub skipped_nonfinite: usize,
}

impl Stats {
    pub(crate) fn merge(&mut self, o: &Stats) {
        self.renormalised += o.renormalised;
        self.worst_norm_dev = self.worst_norm_dev.max(o.worst_norm_dev);
        self.skipped_nonfinite += o.skipped_nonfinite;
    }

    pub(crate) fn warnings(&self) -> Vec<Warning> {
        let mut warnings = Vec::new();
        if self.renormalised > 0 {
            warnings.push(Warning::new(
                Code::AssumedConvention,
                format!(
                    "{} normals were not unit length (largest | |n| - 1 | = {:.3e}); renormalised",
                    self.renormalised, self.worst_norm_dev
                ),
            ));
        }
        if self.skipped_nonfinite > 0 {
            warnings.push(Warning::new(
                Code::Ignored,
                format!(
                    "{} points with a non-finite coordinate or normal (NaN marks invalid points in PCL) were skipped",
                    self.skipped_nonfinite
                ),
            ));
        }
        warnings
    }
}

/// Checks records and hands the valid ones to a sink, ending a block every
/// [`BLOCK`] records (skipped ones included, so that blocks depend on the file
/// alone).
pub(crate) struct Checker<'s, S: Sink> {
    pub sink: &'s mut S,
    weighted: bool,
    pub stats: Stats,
    records: usize,
}

impl<'s, S: Sink> Checker<'s, S> {
    /// `weighted`: the file has a weight column (`v[6]`); otherwise `v[6]` is 1.
    pub(crate) fn new(sink: &'s mut S, weighted: bool, capacity_hint: usize) -> Self {
        sink.begin(weighted, capacity_hint);
        Checker {
            sink,
            weighted,
            stats: Stats::default(),
            records: 0,
        }
    }

    /// Records left before the current block ends.
    pub(crate) fn until_block_end(&self) -> usize {
        BLOCK - self.records % BLOCK
    }

    /// A batch of records (`p`, `n`, `w` of equal lengths, not crossing a
    /// block end): one branch-free test of the whole batch, then one bulk
    /// hand-over; a batch with anything to skip, renormalise or refuse goes
    /// record by record. On error, the index in the batch and the fault.
    pub(crate) fn batch(
        &mut self,
        p: &[[f64; 3]],
        n: &[[f64; 3]],
        w: &[f64],
    ) -> Result<(), (usize, Fault)> {
        let m = p.len().min(n.len()).min(w.len());
        let (p, n, w) = (&p[..m], &n[..m], &w[..m]);
        let mut ok = true;
        for ((pi, ni), wi) in p.iter().zip(n).zip(w) {
            // NaN fails every comparison, so it clears `ok` too.
            let n2 = ni[0] * ni[0] + ni[1] * ni[1] + ni[2] * ni[2];
            ok &= (pi[0].abs() <= MAX_COORDINATE)
                & (pi[1].abs() <= MAX_COORDINATE)
                & (pi[2].abs() <= MAX_COORDINATE)
                & ((n2 - 1.0).abs() <= NORMAL_UNIT_TOL)
                & (*wi >= 0.0 && *wi <= f64::MAX);
        }
        if !ok {
            for i in 0..m {
                let v = [p[i][0], p[i][1], p[i][2], n[i][0], n[i][1], n[i][2], w[i]];
                self.record(&v).map_err(|f| (i, f))?;
            }
            return Ok(());
        }
        self.sink.points(p, n, w);
        self.records += m;
        if self.records.is_multiple_of(BLOCK) {
            self.sink.end_block();
        }
        Ok(())
    }

    /// One record `x y z nx ny nz w`.
    #[inline(always)]
    pub(crate) fn record(&mut self, v: &[f64; 7]) -> Result<(), Fault> {
        let r = self.check(v);
        self.records += 1;
        if self.records.is_multiple_of(BLOCK) {
            self.sink.end_block();
        }
        r
    }

    #[inline(always)]
    fn check(&mut self, v: &[f64; 7]) -> Result<(), Fault> {
        let p = [v[0], v[1], v[2]];
        let mut n = [v[3], v[4], v[5]];
        if !p.iter().chain(n.iter()).all(|x| x.is_finite()) {
            self.stats.skipped_nonfinite += 1;
            return Ok(());
        }
        if let Some(x) = p.iter().find(|x| x.abs() > MAX_COORDINATE) {
            return Err(Fault::Coordinate(*x));
        }
        let n2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
        // Fast path: | |n|^2 - 1 | <= tol puts | |n| - 1 | below tol / 2 (plus
        // rounding), well inside the tolerance: no square root, no division.
        if (n2 - 1.0).abs() > NORMAL_UNIT_TOL {
            n = self.unit_normal(n)?;
        }
        let w = if self.weighted {
            let w = v[6];
            if !(w.is_finite() && w >= 0.0) {
                return Err(Fault::Weight(w));
            }
            w
        } else {
            1.0
        };
        self.sink.point(&p, &n, w);
        Ok(())
    }

    /// The careful path: a scaled norm (a normal like [1e200, 0, 0] must not
    /// overflow to inf and then normalise to zero), renormalised when off unit
    /// length by more than the tolerance.
    #[cold]
    fn unit_normal(&mut self, n: [f64; 3]) -> Result<[f64; 3], Fault> {
        let scale = n[0].abs().max(n[1].abs()).max(n[2].abs());
        let norm = if scale > 0.0 {
            let (a, b, c) = (n[0] / scale, n[1] / scale, n[2] / scale);
            scale * (a * a + b * b + c * c).sqrt()
        } else {
            0.0
        };
        if norm < NORMAL_ZERO_TOL {
            return Err(Fault::ZeroNormal(n));
        }
        let dev = (norm - 1.0).abs();
        if dev > NORMAL_UNIT_TOL {
            self.stats.renormalised += 1;
            self.stats.worst_norm_dev = self.stats.worst_norm_dev.max(dev);
            return Ok([n[0] / norm, n[1] / norm, n[2] / norm]);
        }
        Ok(n)
    }
}
