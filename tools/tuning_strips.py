#!/usr/bin/env python3
"""Writes the strips the anytime rounds' settings are chosen on, apart from the twelve ESICUP
instances they are measured on, in the form `cargo bench -p cam-nest --bench strip_instances`
reads:

    python3 tools/tuning_strips.py DIR        # DIR an absolute path: cargo runs the bench in crates/nest
    NEST_STRIP_INSTANCES=DIR NEST_ITERATIONS=250000 NEST_SEED=2 cargo bench -p cam-nest --bench strip_instances

- `rectilinear.json`: 25 parts with whole-number sides (rectangles, L, U and T shapes), 4
  rotations, on a strip 40.004 wide: shaped like jakobs1 and jakobs2, where a layout gets
  shorter only once the search finds another arrangement.
- `stars.json`: 43 copies of 4 star-shaped polygons with whole-number vertices, one rotation, on
  a strip 40.004 wide: shaped like shapes0 and shapes1.
- `slanted.json`: 25 parts of even whole-number sizes from 6 to 12 (rectangles, L and U shapes,
  triangles, diamonds and blocks with their corners cut), 4 rotations, on a strip 70.007 wide:
  shaped like jakobs2, where slanted edges let parts of rows of equal heights nest.

The fourth strip of the set is ESICUP's blaz1, which sparrow does not ship; jagua-rs has it in its
`assets` (its `orientation` becomes `allowed_orientations`). The parts are drawn from a fixed
stream, so every run writes the same files.
"""

import json
import math
import random
import sys
from pathlib import Path

STREAM = 4242


def instance(name, items, strip_height):
    return {
        "name": name,
        "strip_height": strip_height,
        "items": [
            {
                "id": i,
                "demand": demand,
                "allowed_orientations": orientations,
                "shape": {"type": "simple_polygon", "data": ring + [ring[0]]},
            }
            for i, (ring, demand, orientations) in enumerate(items)
        ],
    }


def rectilinear_part(rng):
    """A rectangle, or an L, U or T cut from it, with whole-number sides."""
    w, h = rng.randint(3, 14), rng.randint(3, 14)
    kind = rng.choice(["rect", "L", "U", "T"])
    if kind == "rect" or w < 5 or h < 5:
        return [[0, 0], [w, 0], [w, h], [0, h]]
    a, b = rng.randint(1, w - 2), rng.randint(1, h - 2)
    if kind == "L":
        return [[0, 0], [w, 0], [w, b], [a, b], [a, h], [0, h]]
    c = rng.randint(a + 1, w - 1)
    if kind == "U":
        return [[0, 0], [w, 0], [w, h], [c, h], [c, b], [a, b], [a, h], [0, h]]
    return [[a, 0], [c, 0], [c, b], [w, b], [w, h], [0, h], [0, b], [a, b]]


def star_part(rng):
    """Vertices at whole-number points on rays at equal angles: star-shaped, so simple."""
    n = rng.randint(5, 8)
    points = []
    for k in range(n):
        angle = 2 * math.pi * k / n
        r = rng.randint(2, 7)
        p = [round(r * math.cos(angle)), round(r * math.sin(angle))]
        if not points or points[-1] != p:
            points.append(p)
    if points[0] == points[-1]:
        points.pop()
    return points


def slanted_part(rng):
    """A part of even whole-number width and height from 6 to 12: a rectilinear one, or one with
    slanted edges (a triangle, a diamond, or a block with its corners cut)."""
    w, h = rng.choice([6, 8, 10, 12]), rng.choice([6, 8, 10, 12])
    kind = rng.choice(["rectilinear", "triangle", "diamond", "chamfer"])
    if kind == "rectilinear":
        a, b = rng.randint(2, w - 2), rng.randint(2, h - 2)
        shape = rng.choice(["rect", "L", "U"])
        if shape == "rect":
            return [[0, 0], [w, 0], [w, h], [0, h]]
        if shape == "L":
            return [[0, 0], [w, 0], [w, b], [a, b], [a, h], [0, h]]
        return [[0, 0], [w, 0], [w, h], [w - 2, h], [w - 2, 2], [2, 2], [2, h], [0, h]]
    if kind == "triangle":
        return [[0, 0], [w, 0], [w // 2, h]]
    if kind == "diamond":
        return [[w // 2, 0], [w, h // 2], [w // 2, h], [0, h // 2]]
    c = 2
    return [[c, 0], [w - c, 0], [w, c], [w, h - c], [w - c, h], [c, h], [0, h - c], [0, c]]


def area(ring):
    n = len(ring)
    twice = sum(ring[i][0] * ring[(i + 1) % n][1] - ring[(i + 1) % n][0] * ring[i][1] for i in range(n))
    return abs(twice) / 2


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: tuning_strips.py DIR")
    out = Path(sys.argv[1])
    out.mkdir(parents=True, exist_ok=True)
    rng = random.Random(STREAM)
    rectilinear = [(rectilinear_part(rng), 1, [0.0, 90.0, 180.0, 270.0]) for _ in range(25)]
    stars = []
    while len(stars) < 4:
        ring = star_part(rng)
        if len(ring) >= 4 and area(ring) > 8 and len({tuple(p) for p in ring}) == len(ring):
            stars.append(ring)
    stars = [(ring, rng.randint(9, 13), [0.0]) for ring in stars]
    # Drawn after the others, so that they stay the files they were.
    slanted = [(slanted_part(rng), 1, [0.0, 90.0, 180.0, 270.0]) for _ in range(25)]
    strips = {
        out / f"{name}.json": instance(name, items, 40.004)
        for name, items in (("rectilinear", rectilinear), ("stars", stars))
    }
    strips[out / "slanted.json"] = instance("slanted", slanted, 70.007)
    for path in strips:
        if path.exists():
            sys.exit(f"{path}: already there; tuning_strips.py writes only new files")
    for path, strip in strips.items():
        path.write_text(json.dumps(strip))
        print(f"wrote {path}")


if __name__ == "__main__":
    main()
