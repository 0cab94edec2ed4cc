#!/usr/bin/env python3
"""Stacks four stones of the StonePacking-3D data set into a small dry wall.

Run once by hand, from anywhere:

    python3 data/stones/stack.py

It reads the meshes of `source/` (as published: centimetres, the height along x) and writes
the posed meshes, one OBJ file per stone, into `wall/` (centimetres, z up), which
`drystone import data/stones/wall --unit cm ...` reads (docs/survey.md, "Real stones").
Standard library only, no randomness: the same sources give the same files bit for bit.

The wall (x along the wall, y across it, z up; the table is z = 0):

* course 1: stone_003 and stone_067 side by side, each resting on a face of its convex hull
  on the table. Their top faces (one hull face each) lean by the same angle from their
  bases (8.804°, within 0.001°), so each stone is turned about the vertical until its top
  face's normal points in the azimuth PSI_DEG; stone_067 stands GAP_CM beyond stone_003
  along x (between their bounding boxes) and is moved along y until its top face lies in
  the plane of stone_003's: the two top faces are one bed;
* course 2: stone_110 on that bed across the joint, a face of its hull on the bed plane;
* course 3: stone_089 on a face of stone_110's hull.

Every stone touches the stones below it face to face (a face of its hull in the plane of a
face of each stone's hull below), so the contacts have no gap and no overlap; drystone's
blocks are the stones' convex hulls, so the hulls are what is posed and checked here. A
face is named by its three corners, the 1-based vertex numbers of the source file.
"""

import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE = os.path.join(HERE, "source")
OUT = os.path.join(HERE, "wall")

GAP_CM = 0.4  # the head joint of course 1, between bounding boxes along x
PSI_DEG = 50.0  # azimuth of the bed's normal (from +x towards +y)
# (output name, source stone, face it rests on, [top face that makes the bed])
COURSE_1 = [
    ("c1_stone_003", "stone_003", (334, 297, 445), (355, 271, 442)),
    ("c1_stone_067", "stone_067", (336, 317, 478), (424, 3, 492)),
]
# course 2: (name, stone, face on the bed, turn about the bed's normal [deg],
# offset [cm] of its centroid's vertical projection from the mean corner of the support
# region, in the bed's frame (e1: +x projected on the bed; e2 = n × e1))
COURSE_2 = ("c2_stone_110", "stone_110", (2, 54, 57), 60.0, (-2.0, 1.0))
# course 3: (name, stone, face it rests on, turn [deg], the face of course 2 it rests on);
# its centroid's vertical projection on that face's centroid
COURSE_3 = ("c3_stone_089", "stone_089", (2, 117, 120), 30.0, (473, 470, 501))


# --- vectors ---------------------------------------------------------------------------

def add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def scale(a, k):
    return (a[0] * k, a[1] * k, a[2] * k)


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def norm(a):
    return math.sqrt(dot(a, a))


def unit(a):
    return scale(a, 1.0 / norm(a))


def matmul(a, b):
    return tuple(tuple(sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)) for i in range(3))


def apply(r, v):
    return tuple(r[i][0] * v[0] + r[i][1] * v[1] + r[i][2] * v[2] for i in range(3))


def rotation(axis, angle):
    """The rotation by `angle` (rad) about `axis` (Rodrigues)."""
    x, y, z = unit(axis)
    c, s = math.cos(angle), math.sin(angle)
    t = 1.0 - c
    return (
        (c + x * x * t, x * y * t - z * s, x * z * t + y * s),
        (y * x * t + z * s, c + y * y * t, y * z * t - x * s),
        (z * x * t - y * s, z * y * t + x * s, c + z * z * t),
    )


def rotation_onto(a, b):
    """The shortest rotation taking the direction a onto the direction b (not opposite)."""
    a, b = unit(a), unit(b)
    axis = cross(a, b)
    return rotation(axis, math.atan2(norm(axis), dot(a, b)))


# --- meshes ----------------------------------------------------------------------------

def read_obj(path):
    """Vertices and triangles (0-based) of an OBJ file."""
    vertices, faces = [], []
    with open(path) as f:
        for line in f:
            t = line.split()
            if t and t[0] == "v":
                vertices.append(tuple(float(x) for x in t[1:4]))
            elif t and t[0] == "f":
                idx = [int(x.split("/")[0]) - 1 for x in t[1:]]
                faces.extend((idx[0], idx[k], idx[k + 1]) for k in range(1, len(idx) - 1))
    return vertices, faces


def hull(points):
    """The convex hull's triangles (outward, counter-clockwise), incremental construction."""
    n = len(points)
    size = max(norm(sub(p, points[0])) for p in points)
    eps = 1e-9 * size
    i0 = min(range(n), key=lambda i: points[i])
    i1 = max(range(n), key=lambda i: norm(sub(points[i], points[i0])))
    d01 = sub(points[i1], points[i0])
    i2 = max(range(n), key=lambda i: norm(cross(d01, sub(points[i], points[i0]))))
    nrm = cross(d01, sub(points[i2], points[i0]))
    i3 = max(range(n), key=lambda i: abs(dot(nrm, sub(points[i], points[i0]))))
    if dot(nrm, sub(points[i3], points[i0])) > 0:
        i1, i2 = i2, i1
    faces = {}

    def new_face(a, b, c):
        m = unit(cross(sub(points[b], points[a]), sub(points[c], points[a])))
        faces[(a, b, c)] = (m, dot(m, points[a]))

    for f in [(i0, i1, i2), (i0, i3, i1), (i1, i3, i2), (i2, i3, i0)]:
        new_face(*f)
    for p in range(n):
        if p in (i0, i1, i2, i3):
            continue
        visible = [f for f, (m, d) in faces.items() if dot(m, points[p]) - d > eps]
        if not visible:
            continue
        edges = set()
        for a, b, c in visible:
            edges.update([(a, b), (b, c), (c, a)])
            del faces[(a, b, c)]
        for a, b in edges:
            if (b, a) not in edges:
                new_face(a, b, p)
    return list(faces)


def volume_centroid(vertices, triangles):
    """Volume and centroid of a closed, outward-oriented triangle mesh (divergence theorem)."""
    six, c = 0.0, [0.0, 0.0, 0.0]
    for a, b, d in triangles:
        v6 = dot(vertices[a], cross(vertices[b], vertices[d]))
        six += v6
        for k in range(3):
            c[k] += v6 * (vertices[a][k] + vertices[b][k] + vertices[d][k]) / 4.0
    return six / 6.0, tuple(x / six for x in c)


class Stone:
    """A source mesh with its hull, posed by a rotation r (about the source origin) and a
    translation t."""

    def __init__(self, name):
        self.name = name
        self.vertices, self.triangles = read_obj(os.path.join(SOURCE, name + ".obj"))
        # The stone is its surface: a vertex no face uses (stone_067 has twelve) is no part
        # of it, nor of its hull (drystone's import drops them too).
        used = sorted({i for t in self.triangles for i in t})
        self.hull = [tuple(used[k] for k in f) for f in hull([self.vertices[i] for i in used])]
        self.volume, _ = volume_centroid(self.vertices, self.triangles)
        self.hull_volume, self.centroid = volume_centroid(self.vertices, self.hull)
        self.r = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))
        self.t = (0.0, 0.0, 0.0)

    def face(self, corners):
        """The hull face with these three corners (1-based vertex numbers)."""
        want = sorted(i - 1 for i in corners)
        found = [f for f in self.hull if sorted(f) == want]
        assert found, f"{self.name}: no hull face with corners {corners}"
        return found[0]

    def at(self, p):
        return add(apply(self.r, p), self.t)

    def normal(self, face):
        a, b, c = (self.at(self.vertices[i]) for i in face)
        return unit(cross(sub(b, a), sub(c, a)))

    def corners(self, face):
        return [self.at(self.vertices[i]) for i in face]

    def points(self):
        return [self.at(self.vertices[i]) for i in sorted({i for f in self.hull for i in f})]

    def c(self):
        return self.at(self.centroid)

    def turn(self, r):
        """Turns the stone by r about its centroid."""
        c = self.c()
        self.r = matmul(r, self.r)
        self.t = sub(c, apply(self.r, self.centroid))

    def move(self, d):
        self.t = add(self.t, d)

    def bounds(self):
        ps = self.points()
        return [min(p[k] for p in ps) for k in range(3)], [max(p[k] for p in ps) for k in range(3)]


# --- planes and polygons -----------------------------------------------------------------

def plane_frame(n):
    """(e1, e2) in the plane of normal n: e1 is +x projected on the plane, e2 = n × e1."""
    e1 = unit(sub((1.0, 0.0, 0.0), scale(n, n[0])))
    return e1, cross(n, e1)


def in_plane(p, n):
    e1, e2 = plane_frame(n)
    return (dot(p, e1), dot(p, e2))


def vertical_foot(p, n, d):
    """p moved vertically onto the plane n·x = d."""
    return sub(p, (0.0, 0.0, (dot(n, p) - d) / n[2]))


def ccw(poly):
    area2 = sum(poly[i][0] * poly[i - 1][1] - poly[i - 1][0] * poly[i][1] for i in range(len(poly)))
    return poly if area2 < 0 else poly[::-1]


def clip(subject, clipper):
    """Intersection of two convex polygons (Sutherland–Hodgman)."""
    out = ccw(subject)
    clipper = ccw(clipper)
    for i in range(len(clipper)):
        a, b = clipper[i], clipper[(i + 1) % len(clipper)]
        side = lambda p: (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])
        inp, out = out, []
        for j in range(len(inp)):
            p, q = inp[j], inp[(j + 1) % len(inp)]
            sp, sq = side(p), side(q)
            if sp >= 0:
                out.append(p)
            if (sp >= 0) != (sq >= 0):
                s = sp / (sp - sq)
                out.append((p[0] + s * (q[0] - p[0]), p[1] + s * (q[1] - p[1])))
        if not out:
            break
    return out


def hull2(points):
    """Convex hull of 2-D points, counter-clockwise (monotone chain)."""
    pts = sorted(set(points))
    cr = lambda o, a, b: (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    lower, upper = [], []
    for p in pts:
        while len(lower) >= 2 and cr(lower[-2], lower[-1], p) <= 0:
            lower.pop()
        lower.append(p)
    for p in reversed(pts):
        while len(upper) >= 2 and cr(upper[-2], upper[-1], p) <= 0:
            upper.pop()
        upper.append(p)
    return lower[:-1] + upper[:-1]


def area(poly):
    return 0.5 * abs(sum(poly[i][0] * poly[i - 1][1] - poly[i - 1][0] * poly[i][1] for i in range(len(poly))))


def margin(poly, p):
    """Distance from p to the nearest edge of the convex polygon (negative outside)."""
    poly = ccw(poly)
    m = math.inf
    for i in range(len(poly)):
        a, b = poly[i], poly[(i + 1) % len(poly)]
        e = (b[0] - a[0], b[1] - a[1])
        m = min(m, (e[0] * (p[1] - a[1]) - e[1] * (p[0] - a[0])) / math.hypot(*e))
    return m


# --- the stacking ----------------------------------------------------------------------

def rest_on_table(stone, face):
    """The stone on the table on a hull face, its centroid above x = y = 0."""
    stone.turn(rotation_onto(stone.normal(face), (0.0, 0.0, -1.0)))
    c, z = stone.c(), stone.corners(face)[0][2]
    stone.move((-c[0], -c[1], -z))


def rest_on_plane(stone, face, n, d, turn_deg, target):
    """The stone with a hull face on the plane n·x = d (its outward normal −n), turned by
    turn_deg about n, its centroid's vertical projection at `target` (the plane's frame)."""
    stone.turn(rotation_onto(stone.normal(face), scale(n, -1.0)))
    stone.turn(rotation(n, math.radians(turn_deg)))
    stone.move(scale(n, d - dot(n, stone.corners(face)[0])))
    foot = in_plane(vertical_foot(stone.c(), n, d), n)
    e1, e2 = plane_frame(n)
    stone.move(add(scale(e1, target[0] - foot[0]), scale(e2, target[1] - foot[1])))


def support(upper, face, lowers, n, d):
    """The contacts of `upper`'s face on the faces (stone, face) of `lowers`, all in the plane
    n·x = d: each contact polygon's area, the support polygon (their hull) and the margin of
    the upper stone's centroid (its vertical projection) inside it, cm."""
    mine = [in_plane(p, n) for p in upper.corners(face)]
    contacts = [clip(mine, [in_plane(p, n) for p in s.corners(f)]) for s, f in lowers]
    region = hull2([p for c in contacts for p in c])
    foot = in_plane(vertical_foot(upper.c(), n, d), n)
    return [area(c) if len(c) > 2 else 0.0 for c in contacts], region, margin(region, foot)


def build():
    course1 = []
    for name, source, base, top in COURSE_1:
        s = Stone(source)
        b, t = s.face(base), s.face(top)
        rest_on_table(s, b)
        m = s.normal(t)
        s.turn(rotation((0.0, 0.0, 1.0), math.radians(PSI_DEG) - math.atan2(m[1], m[0])))
        course1.append((name, s, b, t))
    (_, s1, _, t1), (_, s2, _, t2) = course1
    n = s1.normal(t1)
    d = dot(n, s1.corners(t1)[0])
    x1 = s1.bounds()[1][0]
    s2.move((x1 + GAP_CM - s2.bounds()[0][0], 0.0, 0.0))
    # Along y until the top face is in the bed plane: its highest point along n on it.
    s2.move((0.0, (d - max(dot(n, p) for p in s2.points())) / n[1], 0.0))
    lean = [math.degrees(math.acos(-dot(s.normal(b), s.normal(t)))) for _, s, b, t in course1]

    name2, src2, face2, turn2, offset2 = COURSE_2
    a = Stone(src2)
    fa = a.face(face2)
    region = hull2([in_plane(p, n) for s, t in ((s1, t1), (s2, t2)) for p in s.corners(t)])
    mean = (sum(p[0] for p in region) / len(region), sum(p[1] for p in region) / len(region))
    rest_on_plane(a, fa, n, d, turn2, (mean[0] + offset2[0], mean[1] + offset2[1]))

    name3, src3, face3, turn3, on3 = COURSE_3
    c = Stone(src3)
    fc, fo = c.face(face3), a.face(on3)
    n3 = a.normal(fo)
    d3 = dot(n3, a.corners(fo)[0])
    target = in_plane(scale(add(add(*a.corners(fo)[:2]), a.corners(fo)[2]), 1.0 / 3.0), n3)
    rest_on_plane(c, fc, n3, d3, turn3, target)

    report = {
        "lean": lean,
        "bed": (n, d),
        "course2": support(a, fa, [(s1, t1), (s2, t2)], n, d),
        "course3": support(c, fc, [(a, fo)], n3, d3),
        "separations": separations([(s1, t1, n, d), (s2, t2, n, d)], a, n, d, c, n3, d3),
    }
    stones = [(nm, s) for nm, s, _, _ in course1] + [(name2, a), (name3, c)]
    return stones, report


def separations(beds, a, n, d, c, n3, d3):
    """Clearances that keep the stones apart where they do not rest on each other, cm:
    every course-1 stone below the bed and stone_110 above it; stone_089 above its bed and
    stone_110 below it; the head joint of course 1; the lowest point of courses 2 and 3."""
    (s1, _, _, _), (s2, _, _, _) = beds
    return {
        "course 1 below the bed": d - max(dot(n, p) for s in (s1, s2) for p in s.points()),
        "course 2 above the bed": min(dot(n, p) for p in a.points()) - d,
        "course 2 below its top face": d3 - max(dot(n3, p) for p in a.points()),
        "course 3 above it": min(dot(n3, p) for p in c.points()) - d3,
        "head joint of course 1 (bounding boxes)": s2.bounds()[0][0] - s1.bounds()[1][0],
        "lowest point of courses 2 and 3 above the table": min(p[2] for s in (a, c) for p in s.points()),
        "course 3 above course 1 (bounding boxes)": c.bounds()[0][2] - max(s.bounds()[1][2] for s in (s1, s2)),
    }


def write(stones):
    os.makedirs(OUT, exist_ok=True)
    for name, s in stones:
        with open(os.path.join(OUT, name + ".obj"), "w") as f:
            f.write(f"# {s.name} of StonePacking-3D (data/stones/README.md), posed by stack.py\n")
            f.write("# centimetres, z up\n")
            for v in s.vertices:
                f.write("v %.7f %.7f %.7f\n" % s.at(v))
            for t in s.triangles:
                f.write("f %d %d %d\n" % (t[0] + 1, t[1] + 1, t[2] + 1))


def main():
    stones, report = build()
    write(stones)
    print("stone            mesh cm3   hull cm3  hull adds %   bounds in the wall, cm (x, y, z)")
    for name, s in stones:
        lo, hi = s.bounds()
        box = "  ".join(f"[{a:.2f}, {b:.2f}]" for a, b in zip(lo, hi))
        excess = 100.0 * (s.hull_volume / s.volume - 1.0)
        print(f"{name:14} {s.volume:10.3f} {s.hull_volume:10.3f} {excess:11.2f}   {box}")
    print("course 1 top faces lean from their bases by %.4f and %.4f deg" % tuple(report["lean"]))
    n, d = report["bed"]
    print("the bed: normal (%.5f, %.5f, %.5f), %.3f deg from vertical" % (*n, math.degrees(math.acos(n[2]))))
    for key, label in (("course2", "c2_stone_110 on course 1"), ("course3", "c3_stone_089 on c2_stone_110")):
        areas, region, m = report[key]
        print(f"{label}: contacts {', '.join(f'{x:.2f}' for x in areas)} cm2, support {area(region):.2f} cm2, "
              f"centroid {m:.2f} cm inside it")
    for label, value in report["separations"].items():
        print(f"{label}: {value:.6f} cm")


if __name__ == "__main__":
    main()
