//! SVG plots of ensemble results (plotters): collapse-angle histograms with the measured
//! values marked, displacement against tilt with the ensemble band and the measured points,
//! standardized residuals of observations against models (the discrepancy report's),
//! fragility curves (empirical and fitted lognormal), and x–y curves with a ±σ band.

use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use std::path::Path;

/// Plot errors carry the file and plotters' message.
#[derive(Debug, thiserror::Error)]
#[error("plot {path}: {message}")]
pub struct PlotError {
    /// The file.
    pub path: String,
    /// The message.
    pub message: String,
}

fn err(path: &Path) -> impl Fn(String) -> PlotError + '_ {
    move |message| PlotError { path: path.display().to_string(), message }
}

const PALETTE: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
    RGBColor(140, 86, 75),
];

/// The colour of series `i`.
pub fn colour(i: usize) -> RGBColor {
    PALETTE[i % PALETTE.len()]
}

/// An x–y chart of an SVG drawing.
type XyChart<'a, 'b> = ChartContext<'a, SVGBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// The legend of `chart`'s labelled series: at `position` (`None`: plotters' default), on
/// white of opacity `opacity`, framed in black.
///
/// # Errors
/// Plotters' message.
fn legend_box<'b>(
    chart: &mut XyChart<'b, 'b>,
    position: Option<SeriesLabelPosition>,
    opacity: f64,
) -> Result<(), String> {
    let mut labels = chart.configure_series_labels();
    if let Some(p) = position {
        labels.position(p);
    }
    labels.background_style(WHITE.mix(opacity)).border_style(BLACK).draw().map_err(|x| x.to_string())
}

/// The points `(x, y)` of a curve whose `y` is finite.
fn finite_points(x: &[f64], y: &[f64]) -> Vec<(f64, f64)> {
    x.iter().zip(y).filter(|(_, y)| y.is_finite()).map(|(x, y)| (*x, *y)).collect()
}

/// A shaded band between `lo` and `hi` over `x` (their finite values: along `hi`, back
/// along `lo`) in colour `c`; nothing when fewer than three points remain.
///
/// # Errors
/// Plotters' message.
fn draw_band(chart: &mut XyChart, x: &[f64], lo: &[f64], hi: &[f64], c: RGBColor) -> Result<(), String> {
    let mut poly = finite_points(x, hi);
    poly.extend(x.iter().zip(lo).rev().filter(|(_, y)| y.is_finite()).map(|(x, y)| (*x, *y)));
    if poly.len() >= 3 {
        chart.draw_series(std::iter::once(Polygon::new(poly, c.mix(0.18).filled()))).map_err(|x| x.to_string())?;
    }
    Ok(())
}

/// One histogram panel: simulated values and measured values (vertical lines).
#[derive(Debug, Clone)]
pub struct HistogramPanel {
    /// Panel title.
    pub title: String,
    /// Simulated values.
    pub simulated: Vec<f64>,
    /// Measured values.
    pub measured: Vec<f64>,
}

/// Histograms side by side (`x_label`, e.g. "collapse angle \[deg\]"), bins of `bin` width.
///
/// # Errors
/// [`PlotError`].
pub fn histograms(path: &Path, x_label: &str, bin: f64, panels: &[HistogramPanel]) -> Result<(), PlotError> {
    let e = err(path);
    let w = 420 * panels.len().max(1) as u32;
    let root = SVGBackend::new(path, (w, 360)).into_drawing_area();
    root.fill(&WHITE).map_err(|x| e(x.to_string()))?;
    let areas = root.split_evenly((1, panels.len().max(1)));
    for (k, (p, area)) in panels.iter().zip(areas.iter()).enumerate() {
        let all: Vec<f64> = p.simulated.iter().chain(p.measured.iter()).copied().filter(|v| v.is_finite()).collect();
        if all.is_empty() {
            continue;
        }
        let lo = (all.iter().cloned().fold(f64::INFINITY, f64::min) / bin).floor() * bin - bin;
        let hi = (all.iter().cloned().fold(f64::NEG_INFINITY, f64::max) / bin).ceil() * bin + bin;
        let nb = ((hi - lo) / bin).round() as usize;
        let mut counts = vec![0usize; nb.max(1)];
        for v in p.simulated.iter().filter(|v| v.is_finite()) {
            let i = (((v - lo) / bin).floor() as usize).min(counts.len() - 1);
            counts[i] += 1;
        }
        let ymax = (*counts.iter().max().unwrap_or(&1)).max(1) as f64 * 1.15;
        let mut chart = ChartBuilder::on(area)
            .caption(&p.title, ("sans-serif", 16))
            .margin(10)
            .x_label_area_size(35)
            .y_label_area_size(40)
            .build_cartesian_2d(lo..hi, 0.0..ymax)
            .map_err(|x| e(x.to_string()))?;
        chart.configure_mesh().x_desc(x_label).y_desc("realizations").draw().map_err(|x| e(x.to_string()))?;
        let c = colour(k);
        chart
            .draw_series(counts.iter().enumerate().map(|(i, &n)| {
                let x0 = lo + i as f64 * bin;
                Rectangle::new([(x0, 0.0), (x0 + bin, n as f64)], c.mix(0.5).filled())
            }))
            .map_err(|x| e(x.to_string()))?
            .label("simulated")
            .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 10, y + 5)], c.mix(0.5).filled()));
        if !p.measured.is_empty() {
            chart
                .draw_series(
                    p.measured.iter().map(|&m| PathElement::new(vec![(m, 0.0), (m, ymax)], BLACK.stroke_width(2))),
                )
                .map_err(|x| e(x.to_string()))?
                .label("measured")
                .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 12, y)], BLACK.stroke_width(2)));
        }
        legend_box(&mut chart, None, 0.8).map_err(&e)?;
    }
    root.present().map_err(|x| e(x.to_string()))
}

/// A curve with a band: `x`, `mid`, `lo`, `hi` of equal length, and measured points.
#[derive(Debug, Clone)]
pub struct BandSeries {
    /// Legend label.
    pub label: String,
    /// Abscissae.
    pub x: Vec<f64>,
    /// Middle line (mean).
    pub mid: Vec<f64>,
    /// Lower edge of the band.
    pub lo: Vec<f64>,
    /// Upper edge of the band.
    pub hi: Vec<f64>,
    /// Measured points (x, y).
    pub measured: Vec<(f64, f64)>,
    /// Legend suffix of the points \[`measured`\] (e.g. `paper` for a reference result,
    /// `simulated` for the ensemble's own empirical points).
    pub points_label: Option<String>,
    /// Measured specimens (x, y), drawn as hollow circles in the series' colour and
    /// labelled `LABEL measured` (empty: none).
    pub specimens: Vec<(f64, f64)>,
}

/// One model's standardized residuals, one per observation (non-finite ones are not
/// drawn).
#[derive(Debug, Clone)]
pub struct ResidualSeries {
    /// Legend label.
    pub label: String,
    /// z = (measured − predicted) / σ of every observation, in the order of the labels.
    pub z: Vec<f64>,
}

/// Standardized residuals, one column per observation (`labels`, at most 40 shown on the
/// axis), one point per series in its colour (series `k` offset by 0.15 k), with the
/// ±2 lines; the y range is symmetric, at least ±3.3.
///
/// # Errors
/// [`PlotError`].
pub fn residuals(path: &Path, title: &str, labels: &[String], series: &[ResidualSeries]) -> Result<(), PlotError> {
    let e = err(path);
    let lim = series.iter().flat_map(|s| &s.z).filter(|v| v.is_finite()).fold(3.0f64, |m, v| m.max(v.abs())) * 1.1;
    let root = SVGBackend::new(path, (760, 420)).into_drawing_area();
    root.fill(&WHITE).map_err(|x| e(x.to_string()))?;
    let n = labels.len();
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(60)
        .y_label_area_size(50)
        .build_cartesian_2d(-0.5f64..n as f64 - 0.5, -lim..lim)
        .map_err(|x| e(x.to_string()))?;
    chart
        .configure_mesh()
        .x_labels(n.min(40))
        .x_label_formatter(&|x| labels.get(x.round().max(0.0) as usize).cloned().unwrap_or_default())
        .y_desc("z = (measured − predicted) / σ")
        .draw()
        .map_err(|x| e(x.to_string()))?;
    for lvl in [-2.0, 2.0] {
        chart
            .draw_series(LineSeries::new(vec![(-0.5, lvl), (n as f64 - 0.5, lvl)], BLACK.mix(0.3)))
            .map_err(|x| e(x.to_string()))?;
    }
    for (k, s) in series.iter().enumerate() {
        let c = colour(k);
        chart
            .draw_series(
                s.z.iter()
                    .enumerate()
                    .filter(|(_, z)| z.is_finite())
                    .map(|(i, &z)| Circle::new((i as f64 + 0.15 * k as f64, z), 4, c.filled())),
            )
            .map_err(|x| e(x.to_string()))?
            .label(s.label.clone())
            .legend(move |(x, y)| Circle::new((x, y), 4, c.filled()));
    }
    legend_box(&mut chart, None, 0.8).map_err(&e)?;
    root.present().map_err(|x| e(x.to_string()))?;
    Ok(())
}

/// Curves with shaded bands and measured points on one chart.
///
/// # Errors
/// [`PlotError`].
pub fn bands(path: &Path, title: &str, x_label: &str, y_label: &str, series: &[BandSeries]) -> Result<(), PlotError> {
    let e = err(path);
    let root = SVGBackend::new(path, (720, 460)).into_drawing_area();
    root.fill(&WHITE).map_err(|x| e(x.to_string()))?;
    let points = |s: &BandSeries| s.measured.iter().chain(s.specimens.iter()).copied().collect::<Vec<_>>();
    let xs: Vec<f64> =
        series.iter().flat_map(|s| s.x.iter().copied().chain(points(s).into_iter().map(|m| m.0))).collect();
    let ys: Vec<f64> = series
        .iter()
        .flat_map(|s| {
            s.lo.iter().chain(s.hi.iter()).chain(s.mid.iter()).copied().chain(points(s).into_iter().map(|m| m.1))
        })
        .filter(|v| v.is_finite())
        .collect();
    if xs.is_empty() || ys.is_empty() {
        return root.present().map_err(|x| e(x.to_string()));
    }
    let (x0, x1) =
        (xs.iter().cloned().fold(f64::INFINITY, f64::min), xs.iter().cloned().fold(f64::NEG_INFINITY, f64::max));
    let (y0, y1) =
        (ys.iter().cloned().fold(f64::INFINITY, f64::min), ys.iter().cloned().fold(f64::NEG_INFINITY, f64::max));
    let pad = 0.05 * (y1 - y0).max(1e-9);
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(55)
        .build_cartesian_2d(x0..x1.max(x0 + 1e-9), (y0 - pad).min(0.0)..y1 + pad)
        .map_err(|x| e(x.to_string()))?;
    chart.configure_mesh().x_desc(x_label).y_desc(y_label).draw().map_err(|x| e(x.to_string()))?;
    for (k, s) in series.iter().enumerate() {
        let c = colour(k);
        draw_band(&mut chart, &s.x, &s.lo, &s.hi, c).map_err(&e)?;
        let line = finite_points(&s.x, &s.mid);
        chart
            .draw_series(LineSeries::new(line, c.stroke_width(2)))
            .map_err(|x| e(x.to_string()))?
            .label(s.label.clone())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 14, y)], c.stroke_width(2)));
        if !s.measured.is_empty() {
            chart
                .draw_series(s.measured.iter().map(|&(x, y)| Circle::new((x, y), 4, c.filled())))
                .map_err(|x| e(x.to_string()))?
                .label(format!("{} {}", s.label, s.points_label.as_deref().unwrap_or("measured")))
                .legend(move |(x, y)| Circle::new((x + 6, y), 4, c.filled()));
        }
        if !s.specimens.is_empty() {
            chart
                .draw_series(s.specimens.iter().map(|&(x, y)| Circle::new((x, y), 5, c.stroke_width(2))))
                .map_err(|x| e(x.to_string()))?
                .label(format!("{} measured", s.label))
                .legend(move |(x, y)| Circle::new((x + 6, y), 5, c.stroke_width(2)));
        }
    }
    legend_box(&mut chart, Some(SeriesLabelPosition::UpperLeft), 0.85).map_err(&e)?;
    root.present().map_err(|x| e(x.to_string()))
}

/// One curve of an incremental dynamic analysis: a response against the intensity, one
/// point per level, for one motion and one realization.
#[derive(Debug, Clone)]
pub struct IdaCurve {
    /// Colour index (the group's).
    pub series: usize,
    /// `(intensity, response, collapsed)` by increasing intensity; a collapsed point is
    /// drawn at the chart's cap with a cross.
    pub points: Vec<(f64, f64, bool)>,
}

/// A fitted fragility against an intensity with its band, the empirical fractions and a
/// static capacity drawn beside it.
#[derive(Debug, Clone)]
pub struct IntensityFragilityPanel {
    /// Legend label (the group).
    pub label: String,
    /// Colour index.
    pub series: usize,
    /// Intensities of the fitted curve and its band (empty without a fit).
    pub x: Vec<f64>,
    /// Fitted P(collapse).
    pub p: Vec<f64>,
    /// Lower edge of the band.
    pub lo: Vec<f64>,
    /// Upper edge of the band.
    pub hi: Vec<f64>,
    /// `(intensity, collapses / runs)` per level.
    pub empirical: Vec<(f64, f64)>,
    /// The static capacities (one per realization, same unit as the intensity): drawn as
    /// their empirical distribution (a dashed step line) over a shaded min–max band.
    pub capacity: Vec<f64>,
}

/// Incremental dynamic analysis and fragility side by side on one intensity axis: on the
/// left the IDA curves (`y_label` against `x_label`, capped at `cap`), on the right the
/// fragility curves with their bands, the empirical fractions (points) and the static
/// capacities (dashed steps over a shaded band).
///
/// # Errors
/// [`PlotError`].
pub fn ida_and_fragility(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    cap: f64,
    ida: &[IdaCurve],
    fragility: &[IntensityFragilityPanel],
) -> Result<(), PlotError> {
    let e = err(path);
    let root = SVGBackend::new(path, (1100, 470)).into_drawing_area();
    root.fill(&WHITE).map_err(|x| e(x.to_string()))?;
    let root = root.titled(title, ("sans-serif", 18)).map_err(|x| e(x.to_string()))?;
    let (left, right) = root.split_horizontally(540);
    let xs: Vec<f64> = ida
        .iter()
        .flat_map(|c| c.points.iter().map(|p| p.0))
        .chain(fragility.iter().flat_map(|f| f.x.iter().chain(&f.capacity).copied()))
        .filter(|v| v.is_finite())
        .collect();
    let x1 = xs.iter().cloned().fold(0.0_f64, f64::max).max(1e-6) * 1.05;
    let mut chart = ChartBuilder::on(&left)
        .caption("IDA curves (one per motion and realization)", ("sans-serif", 14))
        .margin(10)
        .x_label_area_size(40)
        .y_label_area_size(50)
        .build_cartesian_2d(0.0..x1, 0.0..cap * 1.08)
        .map_err(|x| e(x.to_string()))?;
    chart.configure_mesh().x_desc(x_label).y_desc(y_label).draw().map_err(|x| e(x.to_string()))?;
    for c in ida {
        let col = colour(c.series);
        let line: Vec<(f64, f64)> =
            c.points.iter().map(|&(x, y, fell)| (x, if fell { cap } else { y.min(cap) })).collect();
        chart.draw_series(LineSeries::new(line, col.mix(0.35).stroke_width(1))).map_err(|x| e(x.to_string()))?;
        chart
            .draw_series(c.points.iter().filter(|p| p.2).map(|&(x, _, _)| Cross::new((x, cap), 4, col.stroke_width(1))))
            .map_err(|x| e(x.to_string()))?;
    }
    let mut chart = ChartBuilder::on(&right)
        .caption("P(collapse | PGA) with its band; static capacity λ g", ("sans-serif", 14))
        .margin(10)
        .x_label_area_size(40)
        .y_label_area_size(50)
        .build_cartesian_2d(0.0..x1, 0.0..1.02)
        .map_err(|x| e(x.to_string()))?;
    chart.configure_mesh().x_desc(x_label).y_desc("P(collapse)").draw().map_err(|x| e(x.to_string()))?;
    for f in fragility {
        let col = colour(f.series);
        if let (Some(lo), Some(hi)) = (
            f.capacity.iter().cloned().filter(|v| v.is_finite()).reduce(f64::min),
            f.capacity.iter().cloned().filter(|v| v.is_finite()).reduce(f64::max),
        ) {
            let w = (hi - lo).max(0.004 * x1);
            chart
                .draw_series(std::iter::once(Rectangle::new([(lo, 0.0), (lo + w, 1.0)], col.mix(0.10).filled())))
                .map_err(|x| e(x.to_string()))?;
            let mut sorted: Vec<f64> = f.capacity.iter().cloned().filter(|v| v.is_finite()).collect();
            sorted.sort_by(f64::total_cmp);
            let n = sorted.len() as f64;
            let mut step = vec![(0.0, 0.0)];
            for (i, v) in sorted.iter().enumerate() {
                step.push((*v, i as f64 / n));
                step.push((*v, (i + 1) as f64 / n));
            }
            step.push((x1, 1.0));
            chart
                .draw_series(DashedLineSeries::new(step, 6, 4, col.stroke_width(2)))
                .map_err(|x| e(x.to_string()))?
                .label(format!("{} static capacity (tilt, λ g)", f.label))
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 14, y)], col.stroke_width(1)));
        }
        draw_band(&mut chart, &f.x, &f.lo, &f.hi, col).map_err(&e)?;
        if !f.x.is_empty() {
            let line: Vec<(f64, f64)> = f.x.iter().zip(&f.p).map(|(x, y)| (*x, *y)).collect();
            chart
                .draw_series(LineSeries::new(line, col.stroke_width(2)))
                .map_err(|x| e(x.to_string()))?
                .label(format!("{} shaking table (fit)", f.label))
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 14, y)], col.stroke_width(2)));
        }
        chart
            .draw_series(f.empirical.iter().map(|&(x, y)| Circle::new((x, y), 4, col.filled())))
            .map_err(|x| e(x.to_string()))?
            .label(format!("{} observed", f.label))
            .legend(move |(x, y)| Circle::new((x + 6, y), 4, col.filled()));
    }
    legend_box(&mut chart, Some(SeriesLabelPosition::LowerRight), 0.85).map_err(&e)?;
    root.present().map_err(|x| e(x.to_string()))
}
