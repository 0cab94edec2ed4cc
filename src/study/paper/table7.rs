//! The paper's Table 7 (§6): collapse angle of the 1:4 stone wall with free and with
//! restrained ends against Kn and φ, from its YADE clump model, compared number by number;
//! and the trends the paper reads from it.

use super::{restrained, PaperError};
use crate::io::plot::BandSeries;
use crate::io::table::{SimpleTable, TableColumn};
use crate::study::summary::CellSummary;
use crate::study::text::{fixed, md_table, verdict};
use crate::study::{Study, SweepKey};
use std::fmt::Write as _;
use std::path::Path;

/// One value per sweep point, for the free and the restrained wall.
#[derive(Debug, Clone, Default)]
pub struct Pair {
    /// Free ends.
    pub free: Vec<f64>,
    /// Restrained ends.
    pub restrained: Vec<f64>,
}

/// Table 7 as simulated and as published, one entry per sweep point.
#[derive(Debug, Clone)]
pub struct Table7 {
    /// Kn of each point, Pa/m.
    pub kn: Vec<f64>,
    /// φ of each point, degrees.
    pub phi: Vec<f64>,
    /// The paper's collapse angle, degrees (NaN where it has none).
    pub paper: Pair,
    /// drystone's mean collapse angle, degrees.
    pub mean: Pair,
    /// drystone's σ of the collapse angle, degrees.
    pub sd: Pair,
    /// drystone's collapsed realizations.
    pub n: (Vec<usize>, Vec<usize>),
    /// Capacity ratio sin α restrained / sin α free, drystone.
    pub ratio: Vec<f64>,
    /// Capacity ratio sin α restrained / sin α free, the paper.
    pub paper_ratio: Vec<f64>,
}

impl Table7 {
    /// The table from a study's cells and its measured `paper_dem` angles.
    pub fn collect(study: &Study, cells: &[CellSummary]) -> Table7 {
        let gfree = study.groups.iter().position(|g| !restrained(&g.walls[0].ends)).unwrap_or(0);
        let grest = study.groups.iter().position(|g| restrained(&g.walls[0].ends)).unwrap_or(0);
        let paper = |ends: &str, kn: f64, phi: f64| {
            study
                .measured
                .paper_dem
                .iter()
                .find(|a| {
                    a.ends == ends && (a.kn_pa_per_m / kn - 1.0).abs() < 1e-6 && (a.friction_deg - phi).abs() < 1e-9
                })
                .map_or(f64::NAN, |a| a.collapse_angle_deg)
        };
        let stats = |gi: usize, p: usize| {
            cells
                .iter()
                .find(|c| c.group_index == gi && c.point == p)
                .map_or((f64::NAN, f64::NAN, 0), |c| (c.collapse.mean, c.collapse.sd, c.collapse.n))
        };
        let sin_ratio = |r: f64, f: f64| r.to_radians().sin() / f.to_radians().sin();
        let mut t = Table7 {
            kn: vec![],
            phi: vec![],
            paper: Pair::default(),
            mean: Pair::default(),
            sd: Pair::default(),
            n: (vec![], vec![]),
            ratio: vec![],
            paper_ratio: vec![],
        };
        for p in 0..study.points.len() {
            let kn = study.sweep_number(p, SweepKey::KnPaPerM).unwrap_or(f64::NAN);
            let phi = study.sweep_number(p, SweepKey::FrictionDeg).unwrap_or(f64::NAN);
            let (af, sdf, nf) = stats(gfree, p);
            let (ar, sdr, nr) = stats(grest, p);
            let (paf, par) = (paper("free", kn, phi), paper("restrained", kn, phi));
            t.kn.push(kn);
            t.phi.push(phi);
            t.paper.free.push(paf);
            t.paper.restrained.push(par);
            t.mean.free.push(af);
            t.mean.restrained.push(ar);
            t.sd.free.push(sdf);
            t.sd.restrained.push(sdr);
            t.n.0.push(nf);
            t.n.1.push(nr);
            t.ratio.push(sin_ratio(ar, af));
            t.paper_ratio.push(sin_ratio(par, paf));
        }
        t
    }

    /// The report section: the table, the differences, the trends.
    pub fn section(&self, study: &Study, cells: &[CellSummary]) -> String {
        let mut md = String::new();
        self.rows(&mut md);
        self.differences(&mut md);
        self.trends(noise(study, cells), &mut md);
        md
    }

    fn rows(&self, md: &mut String) {
        let _ = writeln!(md, "## Collapse angle against Kn and φ: the paper's Table 7\n");
        let _ = writeln!(md, "Simulated: mean ± σ of α_max [deg] over the realizations (n); paper: its YADE clump model (Table 7, `data/paper/paper_dem_collapse_angles.csv`). Ks = Kn/2, c = 0.\n");
        let _ = writeln!(md, "| Kn [1e7 Pa/m] | φ [deg] | free: paper | free: drystone | diff | restrained: paper | restrained: drystone | diff | ratio sin α restrained / free |");
        let _ = writeln!(md, "| --- | --- | --- | --- | --- | --- | --- | --- | --- |");
        for p in 0..self.kn.len() {
            let (paf, af, par, ar) =
                (self.paper.free[p], self.mean.free[p], self.paper.restrained[p], self.mean.restrained[p]);
            let _ = writeln!(
                md,
                "| {} | {} | {} | {} ± {} ({}) | {} | {} | {} ± {} ({}) | {} | {} |",
                fixed(self.kn[p] / 1e7, 1),
                fixed(self.phi[p], 0),
                fixed(paf, 1),
                fixed(af, 2),
                fixed(self.sd.free[p], 2),
                self.n.0[p],
                fixed(af - paf, 2),
                fixed(par, 1),
                fixed(ar, 2),
                fixed(self.sd.restrained[p], 2),
                self.n.1[p],
                fixed(ar - par, 2),
                fixed(self.ratio[p], 3)
            );
        }
    }

    /// Mean and RMS of drystone − paper, free and restrained.
    fn differences(&self, md: &mut String) {
        let diffs = |s: &[f64], p: &[f64]| -> Vec<f64> {
            s.iter().zip(p).map(|(a, b)| a - b).filter(|d| d.is_finite()).collect()
        };
        let (df, dr) = (diffs(&self.mean.free, &self.paper.free), diffs(&self.mean.restrained, &self.paper.restrained));
        let rms = |d: &[f64]| {
            if d.is_empty() {
                f64::NAN
            } else {
                (d.iter().map(|x| x * x).sum::<f64>() / d.len() as f64).sqrt()
            }
        };
        let mean = |d: &[f64]| if d.is_empty() { f64::NAN } else { crate::stats::mean(d) };
        let _ = writeln!(
            md,
            "\nDifference drystone − paper: free ends mean {} °, RMS {} °; restrained ends mean {} °, RMS {} °.\n",
            fixed(mean(&df), 2),
            fixed(rms(&df), 2),
            fixed(mean(&dr), 2),
            fixed(rms(&dr), 2)
        );
    }

    /// The distinct Kn and φ values, ascending.
    fn levels(&self) -> (Vec<f64>, Vec<f64>) {
        let sorted = |v: &[f64]| {
            let mut v = v.to_vec();
            v.sort_by(f64::total_cmp);
            v.dedup();
            v
        };
        (sorted(&self.kn), sorted(&self.phi))
    }

    /// `v` at the point (kn, phi), NaN if the sweep has no such point.
    fn at(&self, v: &[f64], kn: f64, phi: f64) -> f64 {
        (0..self.kn.len()).find(|&p| self.kn[p] == kn && self.phi[p] == phi).map_or(f64::NAN, |p| v[p])
    }

    /// The trends the paper reads from its Table 7 (§6), checked on ours: a change counts
    /// when larger than `noise`.
    fn trends(&self, noise: f64, md: &mut String) {
        let (kn_levels, phi_levels) = self.levels();
        let (sf, sr) = (&self.mean.free, &self.mean.restrained);
        let flat_free = kn_levels.iter().all(|&k| {
            let v: Vec<f64> = phi_levels.iter().filter(|&&p| p >= 30.0).map(|&p| self.at(sf, k, p)).collect();
            let (lo, hi) =
                (v.iter().cloned().fold(f64::INFINITY, f64::min), v.iter().cloned().fold(f64::NEG_INFINITY, f64::max));
            hi - lo <= noise.max(0.5)
        });
        let rising_kn = |v: &[f64]| {
            phi_levels.iter().all(|&p| kn_levels.windows(2).all(|w| self.at(v, w[1], p) > self.at(v, w[0], p)))
        };
        let rising_phi_rest = kn_levels.iter().all(|&k| {
            let first = self.at(sr, k, phi_levels[0]);
            let last = self.at(sr, k, *phi_levels.last().unwrap_or(&phi_levels[0]));
            last - first > noise && phi_levels.windows(2).all(|w| self.at(sr, k, w[1]) >= self.at(sr, k, w[0]) - noise)
        });
        let rising = |b: bool| if b { "rising" } else { "not rising" };
        let row = |finding: String, ours: &str, ok: bool| vec![finding, ours.to_string(), verdict(ok).to_string()];
        let rows = vec![
            row(
                format!("free ends: flat in φ for φ ≥ 30° (range within {:.2}° at every Kn)", noise.max(0.5)),
                if flat_free { "flat" } else { "not flat" },
                flat_free,
            ),
            row("free ends: rising with Kn at every φ".into(), rising(rising_kn(sf)), rising_kn(sf)),
            row("restrained ends: rising with φ at every Kn".into(), rising(rising_phi_rest), rising_phi_rest),
            row("restrained ends: rising with Kn at every φ".into(), rising(rising_kn(sr)), rising_kn(sr)),
        ];
        md_table(md, &["finding (paper §6)", "drystone", ""], rows);
        md.push('\n');
    }

    /// `table7_kn_phi.svg` and `table7.csv`, and the markdown that shows them.
    ///
    /// # Errors
    /// [`PaperError`] naming the file.
    pub fn figure(&self, dir: &Path) -> Result<String, PaperError> {
        let (kn_levels, phi_levels) = self.levels();
        let mut series = Vec::new();
        let sides = [
            (&self.mean.free, &self.paper.free, "free"),
            (&self.mean.restrained, &self.paper.restrained, "restrained"),
        ];
        for (sim, pap, label) in sides {
            for &k in &kn_levels {
                let y: Vec<f64> = phi_levels.iter().map(|&p| self.at(sim, k, p)).collect();
                let meas: Vec<(f64, f64)> =
                    phi_levels.iter().map(|&p| (p, self.at(pap, k, p))).filter(|(_, v)| v.is_finite()).collect();
                series.push(BandSeries {
                    label: format!("{label}, Kn {:.1}e7", k / 1e7),
                    x: phi_levels.clone(),
                    mid: y.clone(),
                    lo: y.clone(),
                    hi: y,
                    measured: meas,
                    points_label: Some("paper".into()),
                    specimens: vec![],
                });
            }
        }
        super::plot_bands(
            dir,
            "table7_kn_phi.svg",
            "Collapse angle vs φ per Kn: drystone (lines), paper Table 7 (points)",
            "friction angle φ [deg]",
            "collapse angle [deg]",
            &series,
        )?;
        let col = |name: &str, v: &[f64]| (name.to_string(), TableColumn::Number(v.to_vec()));
        SimpleTable {
            columns: vec![
                col("kn_pa_per_m", &self.kn),
                col("friction_deg", &self.phi),
                col("free_paper_deg", &self.paper.free),
                col("free_drystone_deg", &self.mean.free),
                col("restrained_paper_deg", &self.paper.restrained),
                col("restrained_drystone_deg", &self.mean.restrained),
                col("ratio_drystone", &self.ratio),
                col("ratio_paper", &self.paper_ratio),
            ],
        }
        .write_csv(&dir.join("table7.csv"))?;
        Ok("![Table 7](table7_kn_phi.svg)\n\nData: `table7.csv`.\n\n".into())
    }
}

/// What a change of the collapse angle must exceed to count: the tilt resolution plus twice
/// the largest standard error of a cell's mean.
fn noise(study: &Study, cells: &[CellSummary]) -> f64 {
    study.protocol.tilt().copied().unwrap_or_default().resolution_deg
        + 2.0
            * cells
                .iter()
                .filter(|c| c.collapse.n > 1)
                .map(|c| c.collapse.sd / (c.collapse.n as f64).sqrt())
                .fold(0.0, f64::max)
}
