#![allow(dead_code)] // each test file uses a part of it
//! The collapse tilt of blocks on no-tension Winkler joints, integrated independently of
//! `drystone::verify` (which uses the closed form of the joint rotation): here each joint is
//! solved numerically from its pressure distribution, for any contact segment and centroid.
//!
//! Plane model in the y–z section (y downhill, z up), per metre of block length. A body
//! rests on a joint whose contact segment is `[c0, c1]` (m) on the body's base line, in the
//! body's own frame (origin on the base line). The joint rotates the body by θ relative to
//! the surface below and closes it by `d + θ y` (m) at `y`; the pressure is
//! `Kn max(d + θ y, 0)` (Pa), no tension. The weight `w` (N/m) acts at the centroid
//! `(yc, zc)`, at the angle β to the body's axis (the tilt plus every rotation below and in
//! the joint). Equilibrium normal to the base and of moments about the origin:
//!
//! ```text
//! ∫ Kn (d + θ y)⁺ dy     = w cos β
//! ∫ Kn (d + θ y)⁺ y dy   = w (zc sin β + yc cos β)
//! ```
//!
//! The finite rotation enters through β (gravity seen by the rotated body); the joint is
//! small-strain. α = β − (rotations) rises to a maximum along the loading path: the
//! collapse tilt under a quasi-static tilt. The shear of an interface between two blocks
//! moves the upper block downhill by `T / (Ks A_closed)`; that shifts its centroid towards
//! the lower block's edge and is included where the contact segment ends at that edge.

/// A body on a joint: contact segment, centroid and weight (module doc), m and N/m.
#[derive(Debug, Clone, Copy)]
pub struct Joint {
    pub c0: f64,
    pub c1: f64,
    pub yc: f64,
    pub zc: f64,
    pub w: f64,
    pub kn: f64,
}

/// Resultant normal force and moment about the origin (per metre) of the pressure
/// `Kn (d + θ y)⁺` over `[c0, c1]`, and the closed length.
fn resultant(j: &Joint, d: f64, theta: f64) -> (f64, f64, f64) {
    let (mut y0, mut y1) = (j.c0, j.c1);
    if theta > 0.0 {
        y0 = y0.max(-d / theta);
    } else if theta < 0.0 {
        y1 = y1.min(-d / theta);
    } else if d <= 0.0 {
        return (0.0, 0.0, 0.0);
    }
    if y1 <= y0 {
        return (0.0, 0.0, 0.0);
    }
    let n = j.kn * (d * (y1 - y0) + theta * (y1 * y1 - y0 * y0) / 2.0);
    let m = j.kn * (d * (y1 * y1 - y0 * y0) / 2.0 + theta * (y1.powi(3) - y0.powi(3)) / 3.0);
    (n, m, y1 - y0)
}

fn bisect(mut lo: f64, mut hi: f64, f: impl Fn(f64) -> f64) -> f64 {
    let flo = f(lo);
    for _ in 0..90 {
        let mid = 0.5 * (lo + hi);
        if (f(mid) > 0.0) == (flo > 0.0) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// Rotation θ (rad) and closed length (m) of the joint under gravity at β (rad) to the
/// body's axis; `None` past the joint's limit (resultant outside the segment).
pub fn rotation(j: &Joint, beta: f64) -> Option<(f64, f64)> {
    let n = j.w * beta.cos();
    let e = j.zc * beta.tan() + j.yc; // eccentricity of the resultant
    if !(e > j.c0 && e < j.c1) || n <= 0.0 {
        return None;
    }
    let span = j.c1 - j.c0;
    // For a given θ, the closure d that carries n (monotonic in d).
    let d_of = |theta: f64| {
        let hi = n / (j.kn * span) + theta.abs() * span + 1.0;
        bisect(-theta.abs() * span - 1.0, hi, |d| resultant(j, d, theta).0 - n)
    };
    // The eccentricity grows with θ: bisect on the moment.
    let moment = |theta: f64| {
        let d = d_of(theta);
        resultant(j, d, theta).1 - n * e
    };
    let (mut lo, mut hi) = (-1.0, 1.0);
    while moment(hi) < 0.0 {
        hi *= 2.0;
        if hi > 1e3 {
            return None;
        }
    }
    while moment(lo) > 0.0 {
        lo *= 2.0;
        if lo < -1e3 {
            return None;
        }
    }
    let theta = bisect(lo, hi, moment);
    let closed = resultant(j, d_of(theta), theta).2;
    Some((theta, closed))
}

/// The largest value of `alpha(β)` for β in `(0, hi)` (rad) and the β where it is reached:
/// a scan of 2000 points, then a golden-section search around the best one. `alpha`
/// returns `None` past a limit.
pub fn path_maximum(hi: f64, alpha: impl Fn(f64) -> Option<f64>) -> (f64, f64) {
    let n = 2000;
    let mut best = (0.0, f64::NEG_INFINITY);
    for k in 1..n {
        let b = hi * k as f64 / n as f64;
        match alpha(b) {
            Some(a) if a > best.1 => best = (b, a),
            Some(_) => {}
            None => break,
        }
    }
    let h = hi / n as f64;
    let (mut lo, mut up) = ((best.0 - h).max(0.0), best.0 + h);
    let f = |b: f64| alpha(b).unwrap_or(f64::NEG_INFINITY);
    let gr = (5f64.sqrt() - 1.0) / 2.0;
    for _ in 0..100 {
        let (x1, x2) = (up - gr * (up - lo), lo + gr * (up - lo));
        if f(x1) < f(x2) {
            lo = x1;
        } else {
            up = x2;
        }
    }
    let b = 0.5 * (lo + up);
    if f(b) > best.1 {
        (f(b), b)
    } else {
        (best.1, best.0)
    }
}

/// A collapse tilt: α_max (degrees) and the rotation of the joints at it (rad), β − α.
#[derive(Debug, Clone, Copy)]
pub struct Collapse {
    pub alpha_deg: f64,
    pub rotation: f64,
}

impl Collapse {
    fn of((alpha, beta): (f64, f64)) -> Collapse {
        Collapse { alpha_deg: alpha.to_degrees(), rotation: beta - alpha }
    }
}

/// Collapse tilt of one body on the table (joint `j`, its segment the body's whole base):
/// the maximum of α = β − θ(β).
pub fn on_table(j: &Joint) -> Collapse {
    let hi = ((j.c1 - j.yc) / j.zc).atan();
    Collapse::of(path_maximum(hi, |b| rotation(j, b).map(|(t, _)| b - t)))
}

/// Collapse tilt of a rectangular block `b × h` (y × z), density `rho`, on the table.
pub fn block(b: f64, h: f64, rho: f64, g: f64, kn: f64) -> Collapse {
    on_table(&Joint { c0: -b / 2.0, c1: b / 2.0, yc: 0.0, zc: h / 2.0, w: rho * g * b * h, kn })
}

/// Collapse tilt of a symmetric trapezoid (base `bb`, top `tt`, height `hh`) on the table.
pub fn trapezoid(bb: f64, tt: f64, hh: f64, rho: f64, g: f64, kn: f64) -> Collapse {
    let zc = hh * (bb + 2.0 * tt) / (3.0 * (bb + tt));
    on_table(&Joint { c0: -bb / 2.0, c1: bb / 2.0, yc: 0.0, zc, w: rho * g * 0.5 * (bb + tt) * hh, kn })
}

/// Collapse tilt of two identical blocks `b × h`, the top one offset downhill by
/// `e` (0 ≤ e < b/2), both joints of stiffness `kn` (Ks = `ks`): the path in the top block's
/// inclination β₂, with θ₂ = rotation of the interface at β₂ (its segment from the top
/// block's uphill edge to the lower block's downhill edge, which the interface's elastic
/// shear moves towards the top block's centroid), β₁ = β₂ − θ₂ the lower block's
/// inclination, θ₁ the base joint's rotation at β₁ under both blocks (the top block's
/// centroid moved by its rotation θ₂ and its shear), and α = β₁ − θ₁.
pub fn offset_stack(b: f64, h: f64, e: f64, rho: f64, g: f64, kn: f64, ks: f64) -> Collapse {
    let w = rho * g * b * h;
    let alpha = |beta2: f64| -> Option<f64> {
        // Interface, in the top block's frame (its centroid at y = 0): the lower block's top
        // face ends at b/2 − e − s, s the elastic shear.
        let mut s = 0.0;
        let mut theta2 = 0.0;
        for _ in 0..50 {
            let top = Joint { c0: -b / 2.0, c1: b / 2.0 - e - s, yc: 0.0, zc: h / 2.0, w, kn };
            let (t, closed) = rotation(&top, beta2)?;
            theta2 = t;
            let s_new = w * beta2.sin() / (ks * closed);
            if (s_new - s).abs() < 1e-15 {
                break;
            }
            s = s_new;
        }
        let beta1 = beta2 - theta2;
        // Base joint, in the lower block's frame: both blocks, the top one's centroid at
        // y = e + s + (h/2) sin θ₂, z = h + (h/2) cos θ₂.
        let yc2 = e + s + 0.5 * h * theta2.sin();
        let zc2 = h + 0.5 * h * theta2.cos();
        let base = Joint { c0: -b / 2.0, c1: b / 2.0, yc: 0.5 * yc2, zc: 0.5 * (0.5 * h + zc2), w: 2.0 * w, kn };
        let (theta1, _) = rotation(&base, beta1)?;
        Some(beta1 - theta1)
    };
    let hi = ((b - 2.0 * e) / h).atan().max(((b - e) / (2.0 * h)).atan()) + 0.2;
    Collapse::of(path_maximum(hi, alpha))
}
