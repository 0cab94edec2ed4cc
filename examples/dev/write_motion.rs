//! Writes a generated ground motion (`ground::stochastic`, the model of the shaking
//! studies) as a two-column CSV record (`time_s,accel_g`) that `drystone shake --record`
//! reads: the motion of a study, run by itself.
//!
//! `cargo run --release --example write_motion -- SEED INDEX DURATION_S ENVELOPE_PEAK_S PGA_G OUT.csv`
//! (e.g. `20210917 0 10 2.5 0.6 kt10.csv`: motion `kt_20210917_0` of 10 s, scaled to 0.6 g).

mod common;

use drystone::ground::stochastic::StochasticMotion;
use std::io::Write;

fn main() {
    let args = common::args(6, "write_motion SEED INDEX DURATION_S ENVELOPE_PEAK_S PGA_G OUT.csv");
    let model = StochasticMotion {
        duration_s: common::number(&args[2], "DURATION_S"),
        envelope_peak_s: common::number(&args[3], "ENVELOPE_PEAK_S"),
        pga_g: common::number(&args[4], "PGA_G"),
        ..StochasticMotion::default()
    };
    model.validate().expect("motion parameters");
    let m = model.generate(common::number(&args[0], "SEED"), common::number(&args[1], "INDEX"));
    let mut out = std::io::BufWriter::new(std::fs::File::create(&args[5]).expect("OUT.csv"));
    writeln!(out, "time_s,accel_g").expect("write");
    for (k, a) in m.horizontal_g.iter().enumerate() {
        writeln!(out, "{},{a}", k as f64 * m.dt_s).expect("write");
    }
    eprintln!("{}: {} samples of {} s, PGA {:.3} g", m.name, m.horizontal_g.len(), m.dt_s, m.pga_g());
}
