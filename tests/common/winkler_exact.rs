#![allow(dead_code)] // each test file uses a part of it
//! The collapse tilt of a rigid block on a no-tension Winkler joint with the finite
//! rotation of the block exact, derived from statics here, independently of the library.
//!
//! # Model
//!
//! Plane section (per metre of block length), table frame: y down the table, z normal to
//! it; the tilt α turns gravity to `W (sin α, −cos α)`, W = ρ g b h (N/m). The block
//! (width b along y, height h) is rigid; it turns by θ (toppling down the table, θ > 0)
//! and its base sinks into the joint. A point of the base at the body coordinate s
//! (−b/2 … b/2 from the base centre B, down the table positive) sits at
//! `B + s e_s`, `e_s = (cos θ, −sin θ)`; the centroid at `B + (h/2) e_t`,
//! `e_t = (sin θ, cos θ)`.
//!
//! The joint is a bed of independent springs (Kn per unit area of the block's base, no
//! tension) along the unit normal `n = (sin κθ, cos κθ)`: κ = 0 springs normal to the
//! table (the Winkler foundation of the tilting table), κ = ½ along the plane that bisects
//! the table and the base (the common plane of the penalty joint, 3DEC style), κ = 1
//! normal to the base. The base point at s lies `z = −(c + s sin θ)` below the table
//! surface (c the sinking of B), so its closure along n is linear in s,
//!
//! ```text
//! δ(s) = (c + s sin θ) / cos κθ ,     pressure  Kn δ⁺        (along +n, on the block)
//! ```
//!
//! The shear T acts along the joint's plane `m = (cos κθ, −sin κθ)`, up the table on the
//! block, spread evenly over the closed length L (every closed point has moved with the
//! block; the open ones carry nothing). It acts at the deformed interface: at the block's
//! base (ζ = 0), or, as the penalty joint applies it, a fraction ζ of the local closure
//! higher along n (ζ = ½: the mid-plane between the two faces).
//!
//! # Equilibrium
//!
//! Forces along n and m:
//!
//! ```text
//! Kn ∫ δ⁺ ds = W cos(α + κθ)                                    (1)
//! T          = W sin(α + κθ)                                    (2)
//! ```
//!
//! Moments about B (2-D cross product `r × F = r_y F_z − r_z F_y`): a base point
//! `r = s e_s` gives `s e_s × n = s cos((1−κ)θ)` and `s e_s × m = s sin((1−κ)θ)`; the
//! shear's offset `ζ δ n` gives `ζ δ n × (−τ m) = ζ δ τ`; gravity at the centroid gives
//! `(h/2) e_t × W(sin α, −cos α) = −(h/2) W sin(α + θ)`. With τ = T/L:
//!
//! ```text
//! R(θ, α) = Kn cos((1−κ)θ) ∫ s δ⁺ ds − T sin((1−κ)θ) s̄ + ζ T (∫ δ⁺ ds) / L
//!           − (h/2) W sin(α + θ) = 0                            (3)
//! ```
//!
//! s̄ the centroid of the closed length. For given θ and α, (1) fixes c (the closed
//! integral grows monotonically with c), and (3) is the moment left over: positive, the
//! joint holds the block back. Under a slowly rising tilt the block follows the branch
//! α(θ) that starts at θ = 0, α = 0, the first root of (3) in α at each θ. Its
//! maximum, the fold dα/dθ = 0, is the collapse tilt α_max: past it no equilibrium lies
//! near the path. The resultant of the joint's forces passes through the rotated block's
//! centroid along gravity: that is (1)–(3), no small-angle approximation is made.
//!
//! # Limits
//!
//! - κ = 1, ζ = 0 is the joint of `common/winkler.rs` (its equations, written in the
//!   block's frame, are these), but for the slope of the closure, tan θ here, θ there:
//!   its collapse tilt is lower by tan θ − θ ≈ θ³/3.
//! - For small θ (`cos → 1`, `sin θ → θ`) the shear's lever `T sin((1−κ)θ) s̄` drops, and
//!   with ζ = 0 (1), (3) are the small-rotation Winkler equations with gravity at
//!   β = α + θ to the body, whatever κ: the springs' direction moves α_max by O(θ²).
//! - As Kn → ∞, θ and δ → 0 and α_max → atan(b/h), the rigid limit, from below.
//!
//! Where the shear acts (ζ) is the one term of order δ/b that these models do not fix: the
//! penalty joint applies it on its mid-plane, ζ = ½. At b/h = 2 and Kn 2.5e6 Pa/m
//! (ρ 2200 kg/m³) the penalty joint's geometry (κ = ζ = ½) gives an α_max 0.44° above the
//! Winkler foundation's (κ = ζ = 0); the springs' direction alone (κ) moves it by less
//! than 0.03° there.

use std::f64::consts::FRAC_PI_2;

/// How the joint acts on the block (module doc): the springs' direction κ and where the
/// shear acts, ζ.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Interface {
    /// κ: the springs' direction, turned from the table's normal towards the base's by
    /// this fraction of θ.
    pub plane: f64,
    /// ζ: the shear acts this fraction of the local closure above the block's base.
    pub shear_lever: f64,
}

impl Interface {
    /// The Winkler foundation: springs normal to the table, every force at the block's base.
    pub const WINKLER: Interface = Interface { plane: 0.0, shear_lever: 0.0 };
    /// Springs along the plane bisecting table and base, shear on the joint's mid-plane
    /// (the penalty joint's geometry).
    pub const MID_PLANE: Interface = Interface { plane: 0.5, shear_lever: 0.5 };
    /// Springs normal to the block's base, shear at the base (`common/winkler.rs`).
    pub const BODY: Interface = Interface { plane: 1.0, shear_lever: 0.0 };
}

/// A rectangular block b × h (m), weight w per metre of length (N/m), on a joint of normal
/// stiffness kn (Pa/m).
#[derive(Debug, Clone, Copy)]
pub struct Block {
    pub b: f64,
    pub h: f64,
    pub w: f64,
    pub kn: f64,
}

impl Block {
    pub fn new(b: f64, h: f64, rho: f64, g: f64, kn: f64) -> Block {
        Block { b, h, w: rho * g * b * h, kn }
    }
}

/// `(∫δ⁺ ds, ∫ s δ⁺ ds, closed length, ∫_closed s ds)` of `δ = a + k s` over
/// `[−b/2, b/2]`.
fn closed(a: f64, k: f64, b: f64) -> (f64, f64, f64, f64) {
    let (mut s0, mut s1) = (-b / 2.0, b / 2.0);
    if k > 0.0 {
        s0 = s0.max(-a / k);
    } else if k < 0.0 {
        s1 = s1.min(-a / k);
    } else if a <= 0.0 {
        return (0.0, 0.0, 0.0, 0.0);
    }
    if s1 <= s0 {
        return (0.0, 0.0, 0.0, 0.0);
    }
    let (d1, d2, d3) = (s1 - s0, (s1 * s1 - s0 * s0) / 2.0, (s1.powi(3) - s0.powi(3)) / 3.0);
    (a * d1 + k * d2, a * d2 + k * d3, d1, d2)
}

/// A root of `f` in `[lo, hi]` (opposite signs at the ends), to the last bit.
fn bisect(mut lo: f64, mut hi: f64, f: impl Fn(f64) -> f64) -> f64 {
    let flo = f(lo) > 0.0;
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if (f(mid) > 0.0) == flo {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// The moment left over, R(θ, α) of (3) (N·m/m; positive: the joint holds the block).
pub fn residual(blk: &Block, at: Interface, theta: f64, alpha: f64) -> f64 {
    let k = at.plane;
    let n = blk.w * (alpha + k * theta).cos();
    let t = blk.w * (alpha + k * theta).sin();
    let slope = theta.sin() / (k * theta).cos();
    let span = slope.abs() * blk.b + n / (blk.kn * blk.b) + 1.0;
    let c = bisect(-span, span, |a| blk.kn * closed(a, slope, blk.b).0 - n);
    let (i0, i1, len, s1) = closed(c, slope, blk.b);
    blk.kn * ((1.0 - k) * theta).cos() * i1 - t * ((1.0 - k) * theta).sin() * s1 / len + at.shear_lever * t * i0 / len
        - 0.5 * blk.h * blk.w * (alpha + theta).sin()
}

/// The tilt α (rad) of the equilibrium path at the rotation θ (rad): the first root of
/// (3) from α = 0 (scanned in 400 steps up to α + θ = 90°, then bisected); `None` if the
/// joint cannot hold the block at θ at any tilt.
pub fn alpha_at(blk: &Block, at: Interface, theta: f64) -> Option<f64> {
    let f = |a: f64| residual(blk, at, theta, a);
    let top = FRAC_PI_2 - theta;
    if !(f(0.0) > 0.0) {
        return None;
    }
    let n = 400;
    let mut lo = 0.0;
    for i in 1..=n {
        let a = top * i as f64 / n as f64;
        if f(a) <= 0.0 {
            return Some(bisect(lo, a, f));
        }
        lo = a;
    }
    None
}

/// A collapse: α_max (degrees) and the joint rotation θ at it (rad).
#[derive(Debug, Clone, Copy)]
pub struct Collapse {
    pub alpha_deg: f64,
    pub rotation: f64,
}

/// The collapse tilt: the maximum of α(θ) along the path (module doc), from a scan of θ
/// over 1e-7 … 0.8 rad (400 points, logarithmic; it stops where α has fallen below half
/// its best) and a golden-section search around the best point.
pub fn collapse(blk: &Block, at: Interface) -> Collapse {
    let f = |t: f64| alpha_at(blk, at, t).unwrap_or(f64::NEG_INFINITY);
    let n = 400;
    let (l0, l1) = (1e-7f64.ln(), 0.8f64.ln());
    let thetas: Vec<f64> = (0..=n).map(|i| (l0 + (l1 - l0) * i as f64 / n as f64).exp()).collect();
    let (mut best, mut best_i) = (f64::NEG_INFINITY, 0);
    for (i, &t) in thetas.iter().enumerate() {
        let a = f(t);
        if a > best {
            (best, best_i) = (a, i);
        } else if !(a > 0.5 * best) {
            break;
        }
    }
    let (mut lo, mut hi) = (thetas[best_i.saturating_sub(1)], thetas[(best_i + 1).min(n)]);
    let gr = (5f64.sqrt() - 1.0) / 2.0;
    for _ in 0..80 {
        let (x1, x2) = (hi - gr * (hi - lo), lo + gr * (hi - lo));
        if f(x1) < f(x2) {
            lo = x1;
        } else {
            hi = x2;
        }
    }
    let t = 0.5 * (lo + hi);
    Collapse { alpha_deg: f(t).to_degrees(), rotation: t }
}
