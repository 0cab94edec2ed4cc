"""Rigid-limit collapse tilts of drystone layouts with LMGC90 (non-smooth contact dynamics).

LMGC90 (Moreau-Jean time stepping, hard unilateral contacts, Coulomb friction, convex
polyhedra) is run here through the `compas_lmgc90` wheel, which carries its Fortran core.
Its blocks are rigid and its contacts hard: the tilts it finds are the rigid-block limits
that drystone approaches as Kn grows (the no-tension Winkler loss shrinks as Kn^(-1/3)).

A drystone layout file (JSON, SI units, y downhill, z up in the table frame) is read as it
is: every block the convex hull of its vertices, one friction angle (the layout's single
material), a fixed slab under the table. For a tilt alpha the whole model is rotated about
the x axis so that LMGC90's gravity (along -z) reads g (0, sin alpha, -cos alpha) in the
table frame, as in drystone. The model is released from rest and run for `--time` seconds;
the tilt is *unstable* if a block's centroid moves more than `--disp` or it turns more than
`--rot-deg`. One LMGC90 process per tilt (it holds one simulation per process); the tilt
is bisected between 0 and 45 degrees to `--tol-deg`.

Usage (from the repository root, with a Python that has compas_lmgc90 0.1.11, compas,
numpy and scipy):

    python scripts/lmgc90/rigid_limits.py trial LAYOUT.json ALPHA_DEG
    python scripts/lmgc90/rigid_limits.py bisect LAYOUT.json
    python scripts/lmgc90/rigid_limits.py table > data/lmgc90_rigid_limits.csv

`table` bisects the layouts of CASES and prints the CSV (with this command as a header
comment). Base-held layouts (`"base_sliding": "held"`) are run with their lowest course
free to slide, which does not govern at the friction angles of the cases.
"""

import argparse
import json
import math
import os
import subprocess
import sys
import time

import numpy as np
from scipy.spatial import ConvexHull

G = 9.81

# (case name, layout path relative to the repository root, closed-form rigid limit in
# degrees or empty)
CASES = [
    ("single_block", "data/layouts/rigid/single_block.json", math.degrees(math.atan(0.15 / 0.30))),
    ("offset_stack", "data/layouts/rigid/offset_stack.json", math.degrees(math.atan((0.15 - 2 * 0.06) / 0.075))),
    ("running_bond_13", "data/layouts/rigid/running_bond_13.json", math.degrees(math.atan(0.1 / 0.3))),
]


def hull_faces(vertices):
    """Triangles of the convex hull of `vertices`, wound outwards."""
    pts = np.asarray(vertices, dtype=float)
    hull = ConvexHull(pts)
    centre = pts[hull.vertices].mean(axis=0)
    faces = []
    for tri in hull.simplices:
        a, b, c = pts[tri]
        n = np.cross(b - a, c - a)
        if np.dot(n, a - centre) < 0:
            tri = [tri[0], tri[2], tri[1]]
        faces.append([int(i) for i in tri])
    return faces


def rotate_x(points, angle):
    """Points rotated about the x axis by `angle` (rad)."""
    c, s = math.cos(angle), math.sin(angle)
    return [[p[0], c * p[1] - s * p[2], s * p[1] + c * p[2]] for p in points]


def model(layout, alpha_deg):
    """LMGC90 blocks (slab first) of a layout tilted by alpha: the table frame rotated by
    -alpha about x, so that world gravity (0, 0, -g) is g (0, sin a, -cos a) in it."""
    blocks = [b["vertices"] for b in layout["blocks"]]
    pts = np.array([p for b in blocks for p in b])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    m = 0.5 * (hi - lo).max() + 0.2
    slab = [[x, y, z] for z in (-0.1, 0.0) for y in (lo[1] - m, hi[1] + m) for x in (lo[0] - m, hi[0] + m)]
    rot = -math.radians(alpha_deg)
    return [{"vertices": rotate_x(v, rot), "faces": hull_faces(v)} for v in [slab] + blocks]


def trial(layout_path, alpha_deg, t_end, dt, disp_tol, rot_tol):
    """Runs one tilt; prints `UNSTABLE|STABLE alpha disp rot steps seconds`."""
    from compas_lmgc90.solver import Solver

    with open(layout_path) as f:
        layout = json.load(f)
    mat = layout["materials"][0]
    mu = math.tan(math.radians(mat["friction_deg"]))
    t0 = time.perf_counter()
    s = Solver(dt=dt, theta=0.5, density=float(mat["density_kg_per_m3"]))
    s.geometry_from_v_f(model(layout, alpha_deg))
    s.v_drvdof[0] = {i: np.zeros([6]) for i in range(1, 7)}  # the slab is fixed
    s.supports = [True] + [False] * len(layout["blocks"])
    s.contact_law("IQS_CLB", mu, alert=1e-3)
    s.preprocess()
    c0 = [np.array(m.centroid()) for m in s.trimeshes]
    r0 = [np.array(m.vertex_coordinates(0)) - c for m, c in zip(s.trimeshes, c0)]
    steps = int(round(t_end / dt))
    s.run(nb_steps=steps)
    disp, rot = 0.0, 0.0
    for i in range(1, len(s.trimeshes)):
        c = np.array(s.trimeshes[i].centroid())
        r = np.array(s.trimeshes[i].vertex_coordinates(0)) - c
        disp = max(disp, float(np.linalg.norm(c - c0[i])))
        cos = float(np.dot(r, r0[i]) / (np.linalg.norm(r) * np.linalg.norm(r0[i])))
        rot = max(rot, math.acos(max(-1.0, min(1.0, cos))))
    unstable = disp > disp_tol or rot > rot_tol
    print(
        "%s %.6f %.3e %.4f %d %.2f"
        % ("UNSTABLE" if unstable else "STABLE", alpha_deg, disp, math.degrees(rot), steps, time.perf_counter() - t0),
        flush=True,
    )


def bisect(layout_path, args):
    """Bisects the tilt between 0 and 45 degrees; returns (last stable, first unstable,
    trials, seconds)."""
    lo, hi, n = 0.0, 45.0, 0
    t0 = time.perf_counter()
    while hi - lo > args.tol_deg:
        mid = 0.5 * (lo + hi)
        cmd = [sys.executable, os.path.abspath(__file__), "trial", layout_path, repr(mid)]
        cmd += ["--time", str(args.time), "--dt", str(args.dt), "--disp", str(args.disp), "--rot-deg", str(args.rot_deg)]
        out = subprocess.run(cmd, capture_output=True, text=True)
        n += 1
        line = (out.stdout.strip().splitlines() or ["?"])[-1]
        print("  " + line, file=sys.stderr, flush=True)
        if line.startswith("UNSTABLE"):
            hi = mid
        elif line.startswith("STABLE"):
            lo = mid
        else:
            sys.stderr.write(out.stderr[-2000:])
            raise RuntimeError("LMGC90 trial failed at %r" % mid)
    return lo, hi, n, time.perf_counter() - t0


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("mode", choices=["trial", "bisect", "table"])
    p.add_argument("layout", nargs="?")
    p.add_argument("alpha", nargs="?", type=float)
    p.add_argument("--time", type=float, default=0.6, help="simulated time per trial, s [0.6]")
    p.add_argument("--dt", type=float, default=1e-3, help="time step, s [1e-3]")
    p.add_argument("--disp", type=float, default=2e-3, help="centroid motion of an unstable trial, m [2e-3]")
    p.add_argument("--rot-deg", type=float, default=1.0, help="rotation of an unstable trial, deg [1]")
    p.add_argument("--tol-deg", type=float, default=0.05, help="width of the final bracket, deg [0.05]")
    args = p.parse_args()
    if args.mode == "trial":
        trial(args.layout, args.alpha, args.time, args.dt, args.disp, math.radians(args.rot_deg))
    elif args.mode == "bisect":
        lo, hi, n, secs = bisect(args.layout, args)
        print("last_stable %.4f first_unstable %.4f trials %d seconds %.1f" % (lo, hi, n, secs))
    else:
        print("# LMGC90 rigid-limit collapse tilts (compas_lmgc90 0.1.11, Moreau-Jean, IQS_CLB Coulomb law):")
        print("# python scripts/lmgc90/rigid_limits.py table > data/lmgc90_rigid_limits.csv")
        print(
            "# each trial released from rest and run %.2f s at dt %.0e s; unstable past %.0e m or %.1f deg;"
            " bisection to %.3f deg" % (args.time, args.dt, args.disp, args.rot_deg, args.tol_deg)
        )
        print("# cases: the layouts of data/layouts/rigid/ (friction 35 deg); measured on a 2-core machine, one LMGC90 process per trial")
        print("case,layout,last_stable_deg,first_unstable_deg,closed_form_deg,trials,seconds")
        for name, path, exact in CASES:
            lo, hi, n, secs = bisect(path, args)
            ex = "" if exact is None else "%.4f" % exact
            print("%s,%s,%.4f,%.4f,%s,%d,%.1f" % (name, path, lo, hi, ex, n, secs), flush=True)


if __name__ == "__main__":
    main()
