#!/usr/bin/env python3
"""Trace the as-built course pattern of the granite walls from their crack maps.

Reads the three drawings in ../crackmaps/ (PNG, Vasconcelos 2005, monotonic specimens WS100,
WS175, WS250) and writes one SVG elevation per specimen, `traced_<unit>.svg`, that
`drystone import` reads (each stone a closed <path>, a 1 m scale bar). Standard library only
(the PNG is decoded with zlib); run once by hand from this folder:

    python3 trace_crackmaps.py

The trace, step by step (every constant is named below):

1. Pixels are "paper" when all three channels exceed PAPER (the lines are grey or black,
   the open joints' hatching yellow and red).
2. Each 4-connected region of paper that does not touch the drawing's border and covers
   at least MIN_STONE_SHARE of the wall's drawn area is one stone's face (the slivers
   between the hatching's strokes are far smaller; the paper around the wall touches the
   border).
3. A face's four corners are its extreme pixels along x + y and x - y (the drawn stones are
   quadrilaterals). Faces are grouped into courses by their mid-height. The pieces of a
   stone that a crack split during the test are joined (SPLIT_STONES, read by eye: every
   other red or hatched line of the drawings runs along a joint).
4. The drawings are not to one scale (their outlines are trapezia, and a crushed toe moves
   a corner), so each is rectified by the bilinear map that takes the wall's four corners
   to its nominal rectangle, LENGTH_M x HEIGHT_M (walls.csv: 1.0 m by 1.2 m). The wall's
   ends are the lines fitted through the courses' end faces' outer edges (a course whose end
   departs by more than END_OUTLIER_SHARE of the length, a displaced toe, left out); its
   base and top the lowest and highest corners of the end faces.
5. The drawings show the walls at the end of the test: the stepped crack is open (hatched
   bands up to about 45 mm wide) and the joints are drawn as lines about 2 mm wide. The
   as-built pattern closes them: a course's beds are the means of its faces' bottoms and
   tops, the joint between two courses the mean of the lower one's top and the upper one's
   bottom (the base 0, the top HEIGHT_M); along a course the faces' rectified widths (the
   mean of a face's top and bottom edges, so a stone turned at a toe keeps its size) are
   scaled to fill LENGTH_M (an open joint was closed when the wall was built). Each stone is
   the rectangle between its course's beds and its head joints.

What the trace cannot read: the stones' depth (a single leaf, 0.2 m, from walls.csv), the
drawing's own error (the faces' measured widths are printed, to be compared with the
nominal 0.20 m and 0.10 m blocks), and any displacement the drawing does not show.
"""

import struct
import sys
import zlib
from pathlib import Path

#: A pixel is paper when all of its channels exceed this (0-255).
PAPER = 200
#: A pixel darker than PAPER is a joint line when its channels differ by at most this (the
#: cracks are drawn red, the open joints' hatching yellow).
GREY_SPREAD = 40
#: The stones a crack split during the test, read from the drawings by eye: every red or
#: hatched line of the drawings runs along a joint (the open joints and the stepped crack)
#: except the cracks that wander through the stones near a toe. Each entry is (course
#: counted from the base, the first piece's index along the wall counted from 1); the piece
#: and the next one are one stone.
SPLIT_STONES = {"WS175": [(1, 1)], "WS250": [(1, 5), (2, 5), (3, 5), (4, 5)]}
#: A course's end face whose outer edge departs from the line through the other courses'
#: by more than this share of the wall's length is displaced in the drawing (a crushed toe)
#: and left out of the fit of the wall's end.
END_OUTLIER_SHARE = 0.005
#: A region of paper is a stone's face when it covers at least this share of the wall.
MIN_STONE_SHARE = 0.004
#: The walls' nominal length and height, m (walls.csv, the database's `L_mm`, `H_mm`).
LENGTH_M = 1.0
HEIGHT_M = 1.2
#: The drawings traced: specimen unit -> file.
DRAWINGS = {
    "WS100": "crackmap_WS100_Vasconcelos2005.png",
    "WS175": "crackmap_WS175_Vasconcelos2005.png",
    "WS250": "crackmap_WS250_Vasconcelos2005.png",
}
#: SVG user units per metre in the output (millimetres).
UNITS_PER_M = 1000.0


def read_png(path):
    """Width, height and rows of (r, g, b) of an 8-bit RGB or RGBA, non-interlaced PNG."""
    data = Path(path).read_bytes()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        sys.exit(f"{path}: not a PNG")
    pos, idat, header = 8, b"", None
    while pos < len(data):
        (n,) = struct.unpack(">I", data[pos : pos + 4])
        kind = data[pos + 4 : pos + 8]
        body = data[pos + 8 : pos + 8 + n]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    w, h, depth, colour, _, _, interlace = header
    if depth != 8 or colour not in (2, 6) or interlace:
        sys.exit(f"{path}: only 8-bit RGB/RGBA non-interlaced PNGs are read")
    bpp = 3 if colour == 2 else 4
    raw = zlib.decompress(idat)
    stride = w * bpp
    rows, prev, i = [], bytearray(stride), 0
    for _ in range(h):
        f = raw[i]
        line = bytearray(raw[i + 1 : i + 1 + stride])
        i += 1 + stride
        for x in range(stride):
            a = line[x - bpp] if x >= bpp else 0
            b = prev[x]
            c = prev[x - bpp] if x >= bpp else 0
            if f == 1:
                line[x] = (line[x] + a) & 255
            elif f == 2:
                line[x] = (line[x] + b) & 255
            elif f == 3:
                line[x] = (line[x] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(line)
        prev = line
    rgb = [[tuple(row[x * bpp : x * bpp + 3]) for x in range(w)] for row in rows]
    return w, h, rgb


def is_paper(c):
    """Paper: every channel above PAPER."""
    return min(c) > PAPER


def is_hatching(c):
    """The yellow hatching of an open joint: red and green high, blue well below green."""
    return c[0] > 150 and c[1] > 150 and c[2] < c[1] - 40


def is_joint_line(c):
    """A drawn joint: a grey or black pixel (dark, and its channels within GREY_SPREAD)."""
    return min(c) <= PAPER and max(c) - min(c) <= GREY_SPREAD


def regions(w, h, paper):
    """The 4-connected regions of paper not touching the border: lists of (x, y)."""
    seen = [[False] * w for _ in range(h)]
    out = []
    for y0 in range(h):
        for x0 in range(w):
            if not paper[y0][x0] or seen[y0][x0]:
                continue
            stack, pixels, border = [(x0, y0)], [], False
            seen[y0][x0] = True
            while stack:
                x, y = stack.pop()
                pixels.append((x, y))
                if x in (0, w - 1) or y in (0, h - 1):
                    border = True
                for nx, ny in ((x + 1, y), (x - 1, y), (x, y + 1), (x, y - 1)):
                    if 0 <= nx < w and 0 <= ny < h and paper[ny][nx] and not seen[ny][nx]:
                        seen[ny][nx] = True
                        stack.append((nx, ny))
            if not border:
                out.append(pixels)
    return out


def corners(pixels):
    """Top-left, top-right, bottom-right, bottom-left (image axes, y down)."""
    return (
        min(pixels, key=lambda p: p[0] + p[1]),
        max(pixels, key=lambda p: p[0] - p[1]),
        max(pixels, key=lambda p: p[0] + p[1]),
        min(pixels, key=lambda p: p[0] - p[1]),
    )


def rectifier(tl, tr, br, bl):
    """The inverse of the bilinear map from the unit square to the drawn wall: (x, y) ->
    (s, t) in [0, 1]^2, s along the wall, t up, by Newton's method."""

    def forward(s, t):
        u = t  # t = 0 is the bottom edge (bl, br), t = 1 the top (tl, tr)
        x = (1 - s) * (1 - u) * bl[0] + s * (1 - u) * br[0] + s * u * tr[0] + (1 - s) * u * tl[0]
        y = (1 - s) * (1 - u) * bl[1] + s * (1 - u) * br[1] + s * u * tr[1] + (1 - s) * u * tl[1]
        return x, y

    def inverse(x, y):
        s, t = 0.5, 0.5
        for _ in range(50):
            fx, fy = forward(s, t)
            e = 1e-6
            ax, ay = forward(s + e, t)
            bx, by = forward(s, t + e)
            j11, j21 = (ax - fx) / e, (ay - fy) / e
            j12, j22 = (bx - fx) / e, (by - fy) / e
            det = j11 * j22 - j12 * j21
            rx, ry = x - fx, y - fy
            ds = (j22 * rx - j12 * ry) / det
            dt = (-j21 * rx + j11 * ry) / det
            s, t = s + ds, t + dt
            if abs(ds) + abs(dt) < 1e-12:
                break
        return s, t

    return inverse


def fit_x_of_y(points):
    """Least-squares x = a + b y through (x, y) points; returns (a, b)."""
    n = len(points)
    my = sum(y for _, y in points) / n
    mx = sum(x for x, _ in points) / n
    syy = sum((y - my) ** 2 for _, y in points)
    b = sum((x - mx) * (y - my) for x, y in points) / syy if syy > 0 else 0.0
    return mx - b * my, b


def end_line(points, length_px):
    """The wall's end as x = a + b y through the courses' outer edges, the course most out
    of line left out while it departs by more than END_OUTLIER_SHARE of the length."""
    pts = list(points)
    while len(pts) > 3:
        a, b = fit_x_of_y(pts)
        worst = max(pts, key=lambda p: abs(p[0] - a - b * p[1]))
        if abs(worst[0] - a - b * worst[1]) <= END_OUTLIER_SHARE * length_px:
            break
        pts.remove(worst)
    return fit_x_of_y(pts)


def courses_of(faces):
    """Faces (lists of corners) grouped into courses by mid-height, bottom first (image y
    down), each sorted along the wall."""
    faces = sorted(faces, key=lambda f: -(sum(p[1] for p in f) / 4))
    courses, current = [], [faces[0]]
    height = lambda f: max(p[1] for p in f) - min(p[1] for p in f)
    mid = lambda f: sum(p[1] for p in f) / 4
    for f in faces[1:]:
        ref = sum(mid(c) for c in current) / len(current)
        if abs(mid(f) - ref) < 0.5 * max(height(c) for c in current):
            current.append(f)
        else:
            courses.append(current)
            current = [f]
    courses.append(current)
    for c in courses:
        c.sort(key=lambda f: min(p[0] for p in f))
    return courses


def dist(p, q):
    return ((p[0] - q[0]) ** 2 + (p[1] - q[1]) ** 2) ** 0.5


def join_split(courses, unit):
    """Joins the pieces of the stones that a crack split during the test (SPLIT_STONES:
    course, counted from the base, and the pieces' first index along the wall, both from 1):
    each listed piece becomes one face with the next one."""
    for course, first in sorted(SPLIT_STONES.get(unit, []), key=lambda cf: -cf[1]):
        faces = courses[course - 1]
        faces[first - 1 : first + 1] = [faces[first - 1] + faces[first]]
    return courses


def trace(unit, png, out_dir):
    w, h, rgb = read_png(png)
    paper = [[is_paper(c) for c in row] for row in rgb]
    found = regions(w, h, paper)
    all_corners = [c for p in found for c in corners(p)]
    (tlx, tly), _, (brx, bry), _ = corners(all_corners)
    area = abs(brx - tlx) * abs(bry - tly)
    faces = [list(corners(p)) for p in found if len(p) >= MIN_STONE_SHARE * area]
    courses = join_split(courses_of(faces), unit)
    # The wall's ends: lines through the courses' outer edges; its base and top: the lowest
    # and highest corners.
    length_px = max(p[0] for c in courses for f in c for p in f) - min(p[0] for c in courses for f in c for p in f)
    left = end_line([(min(p[0] for p in c[0]), sum(p[1] for p in c[0]) / len(c[0])) for c in courses], length_px)
    right = end_line([(max(p[0] for p in c[-1]), sum(p[1] for p in c[-1]) / len(c[-1])) for c in courses], length_px)
    bottom = courses[0]
    top = courses[-1]
    y_bl = max(p[1] for p in bottom[0])
    y_br = max(p[1] for p in bottom[-1] if p[0] > min(q[0] for q in bottom[-1]))
    y_tl = min(p[1] for p in top[0])
    y_tr = min(p[1] for p in top[-1])
    on = lambda line, y: (line[0] + line[1] * y, y)
    wall = (on(left, y_tl), on(right, y_tr), on(right, y_br), on(left, y_bl))
    inverse = rectifier(*wall)
    boxed = []
    for course in courses:
        row = []
        for f in course:
            # A face's width is the mean of its top and bottom edges' lengths, its bed and
            # top the means of those edges' heights (a stone the test turned, as at a toe,
            # keeps its own size; a stone a crack split is the sum of its pieces).
            pts = [(s * LENGTH_M, t * HEIGHT_M) for s, t in (inverse(*p) for p in f)]
            pieces = [pts[i : i + 4] for i in range(0, len(pts), 4)]
            width = sum((dist(tl, tr) + dist(bl, br)) / 2 for tl, tr, br, bl in pieces)
            bottom = sum(bl[1] + br[1] for _, _, br, bl in pieces) / (2 * len(pieces))
            top = sum(tl[1] + tr[1] for tl, tr, _, _ in pieces) / (2 * len(pieces))
            row.append((width, bottom, top))
        boxed.append(row)
    courses = boxed
    bottoms = [sum(b[1] for b in c) / len(c) for c in courses]
    tops = [sum(b[2] for b in c) / len(c) for c in courses]
    beds = [0.0] + [(tops[k] + bottoms[k + 1]) / 2 for k in range(len(courses) - 1)] + [HEIGHT_M]
    stones, widths = [], []
    for k, course in enumerate(courses):
        faces = [b[0] for b in course]
        heads = [0.0]
        for width in faces:
            heads.append(heads[-1] + width * LENGTH_M / sum(faces))
        for i in range(len(course)):
            stones.append((f"c{k + 1}s{i + 1}", heads[i], heads[i + 1], beds[k], beds[k + 1]))
            widths.append(heads[i + 1] - heads[i])
    mm = UNITS_PER_M
    lines = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        f"<!-- {unit}: the as-built course pattern traced from {Path(png).name} by"
        " trace_crackmaps.py (units: mm; y down as in any SVG). -->",
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{LENGTH_M * mm:.0f}" height="{HEIGHT_M * mm + 60:.0f}">',
        f'  <line id="scale" x1="0" y1="{HEIGHT_M * mm + 40:.0f}" x2="{mm:.0f}" y2="{HEIGHT_M * mm + 40:.0f}"'
        ' data-length-m="1" stroke="black"/>',
    ]
    for name, x0, x1, z0, z1 in stones:
        y0, y1 = (HEIGHT_M - z1) * mm, (HEIGHT_M - z0) * mm
        lines.append(
            f'  <path id="{name}" d="M {x0 * mm:.2f} {y1:.2f} L {x1 * mm:.2f} {y1:.2f} L {x1 * mm:.2f} {y0:.2f}'
            f' L {x0 * mm:.2f} {y0:.2f} Z" fill="none" stroke="black"/>'
        )
    lines.append("</svg>")
    out = Path(out_dir) / f"traced_{unit}.svg"
    out.write_text("\n".join(lines) + "\n")
    per_course = [len(c) for c in courses]
    heights = [beds[k + 1] - beds[k] for k in range(len(courses))]
    print(
        f"{unit}: {len(stones)} stones in {len(courses)} courses {per_course}; course heights "
        f"{', '.join(f'{1000 * x:.1f}' for x in heights)} mm; stone lengths "
        f"{1000 * min(widths):.1f}-{1000 * max(widths):.1f} mm -> {out.name}"
    )


def main():
    here = Path(__file__).resolve().parent
    for unit, name in DRAWINGS.items():
        trace(unit, here.parent / "crackmaps" / name, here)


if __name__ == "__main__":
    main()
