"""Shaking-table runs of drystone layouts with LMGC90 (non-smooth contact dynamics), for the
side-by-side table data/lmgc90_shake.csv.

LMGC90 (Moreau-Jean time stepping, theta 0.5, hard unilateral contacts, IQS_CLB inelastic
Coulomb law, convex polyhedra) is run through the `compas_lmgc90` wheel, which carries its
Fortran core. A drystone layout file (JSON, SI units, y out of plane, z up) is read as it
is: every block the convex hull of its vertices, the layout's single material (density,
friction angle), a fixed slab under the table. The base motion a_g(t) along +y is applied
as drystone applies it, in the frame of the table: the D'Alembert force -m a_g(t) on every
block (LMGC90 interpolates the force table linearly between samples). Before the motion
the wall settles on the still table for 0.05 s, as in `drystone shake`.

What is measured, as `drystone shake` measures it: the wall overturned when a block has
turned by more than 45 degrees from its place at the start of the motion or dropped by more
than half its height (the run stops there); the largest rotation about x of any block (the
rotation vector's x component of the best-fit rotation of its vertices, Kabsch); the time
of the first fall.

Motions: `one-sine` pulses, a = A g sin(2 pi t / T) for 0 <= t <= T (g = 9.80665 m/s^2, the
g of drystone's records), and records in drystone's CSV format (`time_s,accel_g`). `record`
writes the synthetic record of the table (seeded; the same file on every run).

Usage (from the repository root, with a Python that has compas_lmgc90 0.1.11, compas,
numpy and scipy):

    python scripts/lmgc90/shake.py record data/motions/synthetic_10s.csv
    python scripts/lmgc90/shake.py run LAYOUT.json --pulse A_G T_S [--dt 1e-3] [--tail 2]
    python scripts/lmgc90/shake.py run LAYOUT.json --record FILE.csv [--pga-g P]
    python scripts/lmgc90/shake.py time LAYOUT.json --record FILE.csv   # LMGC90 alone, one run call
    python scripts/lmgc90/shake.py table > data/lmgc90_shake.csv

One LMGC90 process per run (it holds one simulation per process).
"""

import argparse
import csv
import json
import math
import os
import subprocess
import sys
import time

import numpy as np
from scipy.spatial import ConvexHull

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from rigid_limits import model  # noqa: E402  (slab + hull faces of a layout, at tilt 0)

G_RECORD = 9.80665
SETTLE_S = 0.05
FALL_DEG = 45.0

# (case, layout, motion, amplitude_g or PGA, period_s or "")
RECORD = "data/motions/synthetic_10s.csv"
CASES = [
    ("block_pulse_rock", "data/layouts/rigid/single_block.json", "one-sine", 1.0, 0.25),
    ("block_pulse_over", "data/layouts/rigid/single_block.json", "one-sine", 3.0, 0.25),
    ("wall13_pulse_rock", "data/layouts/rigid/running_bond_13.json", "one-sine", 0.42, 0.3),
    ("wall13_pulse_over", "data/layouts/rigid/running_bond_13.json", "one-sine", 2.0, 0.3),
    ("wall13_record_still", "data/layouts/rigid/running_bond_13.json", RECORD, 0.3, ""),
    ("wall13_record_rock", "data/layouts/rigid/running_bond_13.json", RECORD, 0.4, ""),
    ("wall13_record_over", "data/layouts/rigid/running_bond_13.json", RECORD, 0.6, ""),
]


def synthetic_record(path, duration=10.0, dt=0.005, seed=20261125):
    """A 10 s synthetic accelerogram: 40 sines between 0.5 and 8 Hz with seeded random
    phases and amplitudes falling as 1/f, under a Saragoni-Hart-like envelope
    t^2 exp(-t/1.25) peaking at 2.5 s, scaled to a PGA of 1 g. Written as drystone's CSV."""
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, duration + 0.5 * dt, dt)
    f = np.linspace(0.5, 8.0, 40)
    phase = rng.uniform(0.0, 2 * math.pi, f.size)
    a = (np.sin(2 * math.pi * np.outer(t, f) + phase) / f).sum(axis=1)
    env = (t / 2.5) ** 2 * np.exp(2.0 * (1.0 - t / 2.5))
    a = a * env
    a -= np.linspace(a[0], a[-1], a.size)  # starts and ends at 0
    a /= np.abs(a).max()
    with open(path, "w") as out:
        out.write("time_s,accel_g\n")
        for ti, ai in zip(t, a):
            out.write("%.4f,%.6f\n" % (ti, ai))


def read_record(path):
    """(times, accelerations in g) of a `time_s,accel_g` CSV."""
    with open(path) as f:
        rows = [r for r in csv.DictReader(f)]
    return np.array([float(r["time_s"]) for r in rows]), np.array([float(r["accel_g"]) for r in rows])


def motion_of(args):
    """(times, a_g in g) of the run's motion."""
    if args.pulse:
        amp, period = args.pulse
        t = np.linspace(0.0, period, 1001)
        return t, amp * np.sin(2 * math.pi * t / period)
    t, a = read_record(args.record)
    if args.pga_g:
        a = a * (args.pga_g / np.abs(a).max())
    return t, a


def kabsch(p0, p):
    """The rotation matrix R minimising |R p0 - p| (rows are points about their centroids)."""
    h = p0.T @ p
    u, _, vt = np.linalg.svd(h)
    d = np.sign(np.linalg.det(vt.T @ u.T))
    return vt.T @ np.diag([1.0, 1.0, d]) @ u.T


def rotation_x(r):
    """x component of the rotation vector of R (rad)."""
    angle = math.acos(max(-1.0, min(1.0, (np.trace(r) - 1.0) / 2.0)))
    if angle < 1e-12:
        return 0.0, 0.0
    axis_x = (r[2, 1] - r[1, 2]) / (2.0 * math.sin(angle))
    return angle * axis_x, angle


def build(layout, dt, times, ag):
    """The LMGC90 model of a layout with the D'Alembert forces of the motion (times from the
    start of the motion, a_g in g) shifted by the settling."""
    from compas_lmgc90.solver import Solver

    mat = layout["materials"][0]
    rho = float(mat["density_kg_per_m3"])
    if any(b.get("fixed") for b in layout["blocks"]):
        raise SystemExit("layouts with fixed blocks are not supported here")
    s = Solver(dt=dt, theta=0.5, density=rho)
    s.geometry_from_v_f(model(layout, 0.0))
    s.v_drvdof[0] = {i: np.zeros([6]) for i in range(1, 7)}  # the slab is fixed
    s.supports = [True] + [False] * len(layout["blocks"])
    s.contact_law("IQS_CLB", math.tan(math.radians(mat["friction_deg"])), alert=1e-3)
    if times[0] != 0.0:
        raise SystemExit("the motion must start at t = 0")
    # Still during the settling, the motion, then still for good.
    tt = np.concatenate([[0.0], SETTLE_S + times, [SETTLE_S + times[-1] + dt, 1e6]])
    aa = np.concatenate([[0.0], ag, [0.0, 0.0]])
    for i, b in enumerate(layout["blocks"], start=1):
        m = rho * ConvexHull(np.asarray(b["vertices"], dtype=float)).volume
        s.apply_force(i, "Fy", np.vstack([tt, -m * aa * G_RECORD]))
    s.preprocess()
    return s


def vertices(s, i):
    m = s.trimeshes[i]
    return np.array([m.vertex_coordinates(v) for v in m.vertices()])


def run(args):
    """One run; prints one JSON line."""
    with open(args.layout) as f:
        layout = json.load(f)
    times, ag = motion_of(args)
    t0 = time.perf_counter()
    s = build(layout, args.dt, times, ag)
    n = len(layout["blocks"])
    s.run(nb_steps=int(round(SETTLE_S / args.dt)))
    start = [vertices(s, i) for i in range(1, n + 1)]
    c0 = [v.mean(axis=0) for v in start]
    h = [v[:, 2].max() - v[:, 2].min() for v in start]
    p0 = [v - c for v, c in zip(start, c0)]
    steps = int(math.ceil((times[-1] + args.tail) / args.dt))
    max_rot, collapse = 0.0, None
    for k in range(1, steps + 1):
        s.run(nb_steps=1)
        fallen = False
        for i in range(n):
            v = vertices(s, i + 1)
            c = v.mean(axis=0)
            rx, angle = rotation_x(kabsch(p0[i], v - c))
            max_rot = max(max_rot, abs(rx))
            if math.degrees(angle) > FALL_DEG or c0[i][2] - c[2] > 0.5 * h[i]:
                fallen = True
        if fallen:
            collapse = k * args.dt
            break
    print(json.dumps({
        "overturned": collapse is not None,
        "collapse_time_s": collapse,
        "max_rotation_deg": math.degrees(max_rot),
        "steps": k,
        "seconds": time.perf_counter() - t0,
    }), flush=True)


def time_alone(args):
    """LMGC90's own time for the settling and the whole motion and tail in one run call."""
    with open(args.layout) as f:
        layout = json.load(f)
    times, ag = motion_of(args)
    t0, c0 = time.perf_counter(), time.process_time()
    s = build(layout, args.dt, times, ag)
    steps = int(round(SETTLE_S / args.dt)) + int(math.ceil((times[-1] + args.tail) / args.dt))
    s.run(nb_steps=steps)
    print(json.dumps({"steps": steps, "seconds": time.perf_counter() - t0, "cpu_seconds": time.process_time() - c0}),
          flush=True)


def subprocess_run(cmd):
    out = subprocess.run(cmd, capture_output=True, text=True)
    line = (out.stdout.strip().splitlines() or ["?"])[-1]
    try:
        return json.loads(line)
    except json.JSONDecodeError:
        sys.stderr.write(out.stderr[-2000:])
        raise RuntimeError("LMGC90 run failed: %s" % " ".join(cmd))


def table(args):
    me = os.path.abspath(__file__)
    print("# LMGC90 shaking-table runs (compas_lmgc90 0.1.11, Moreau-Jean theta 0.5, IQS_CLB Coulomb law):")
    print("# python scripts/lmgc90/shake.py table > data/lmgc90_shake.csv")
    print("# dt %.0e s; settling 0.05 s on the still table; D'Alembert force -m a_g(t) along +y; tail %.1f s after the motion;"
          " overturned: a block turned > 45 deg or dropped > half its height (the run stops)" % (args.dt, args.tail))
    print("# motions: one-sine a = A g sin(2 pi t/T), 0 <= t <= T; %s scaled to the PGA (written by `shake.py record`)" % RECORD)
    print("# lmgc90_cpu_s: CPU time of LMGC90 alone, settling + motion + tail in one run call (no monitoring, no stop at"
          " collapse), on a shared 2-core machine")
    print("case,layout,motion,amplitude_g,period_s,overturned,collapse_time_s,max_rotation_deg,lmgc90_cpu_s")
    for name, path, motion, amp, period in CASES:
        cmd = [sys.executable, me, "run", path, "--dt", str(args.dt), "--tail", str(args.tail)]
        if motion == "one-sine":
            cmd += ["--pulse", str(amp), str(period)]
        else:
            cmd += ["--record", motion, "--pga-g", str(amp)]
        r = subprocess_run(cmd)
        timing = subprocess_run([cmd[0], me, "time"] + cmd[3:])
        ct = "" if r["collapse_time_s"] is None else "%.3f" % r["collapse_time_s"]
        print("%s,%s,%s,%g,%s,%s,%s,%.3f,%.2f" % (
            name, path, motion, amp, period, str(r["overturned"]).lower(), ct, r["max_rotation_deg"], timing["cpu_seconds"]),
            flush=True)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("mode", choices=["record", "run", "time", "table"])
    p.add_argument("layout", nargs="?", help="layout JSON (run, time) or the output CSV (record)")
    p.add_argument("--pulse", nargs=2, type=float, metavar=("A_G", "T_S"), help="one-sine pulse")
    p.add_argument("--record", help="record CSV (time_s, accel_g)")
    p.add_argument("--pga-g", type=float, help="scale the record to this PGA, g")
    p.add_argument("--dt", type=float, default=1e-3, help="time step, s [1e-3]")
    p.add_argument("--tail", type=float, default=2.0, help="time after the motion, s [2]")
    args = p.parse_args()
    if args.mode == "record":
        synthetic_record(args.layout)
    elif args.mode == "run":
        run(args)
    elif args.mode == "time":
        time_alone(args)
    else:
        table(args)


if __name__ == "__main__":
    main()
