#!/usr/bin/env python3
"""Reference for the nesting figures: nests the benchmark batches with an external, strong
irregular strip packer and writes its strip density next to ours. Run by hand, not in CI:

    cargo bench -p cam-nest --bench nest_engine   # writes target/nest-bench/batches.json
    python3 -m venv /tmp/nestref && /tmp/nestref/bin/pip install spyrrow==0.9.0
    /tmp/nestref/bin/python tools/nest_reference.py [--seconds 30] [--workers 2]
    cargo bench -p cam-nest --bench nest_engine   # now prints the reference column

The packer is `spyrrow`, the Python binding of sparrow (Gardeyn & Wauters, state-of-the-art
irregular strip packing, built on jagua-rs). Strip packing: fixed strip width (our sheet width,
150 mm), length minimised, the same parts, rotations (0/180 deg) and minimum separation (between
parts and to the strip edges). sparrow's strip runs along x with a fixed y extent, ours along y
with a fixed x extent, so every outline is turned by 90 deg before it is handed over, which keeps
each part's orientation to the strip. Density = part area / (strip width x used length), used
length = furthest part point + separation: the same definition as
`NestSolution::used_length_utilization` on a strip.

With `--measure` it reads `target/nest-bench/measure.json` (written by
`cargo bench -p cam-nest --bench nest_measure`: the measuring set with our density and wall time,
and `ours_at_5s`, our best layout as of 5 s of wall time in the same run) and nests each batch for
5 s (beside ours at 5 s), for our CPU time of those 5 s, for our full wall time and for our full
CPU time, rounded to whole seconds (spyrrow takes whole seconds, at least 1; an equal-CPU budget
is our CPU time over sparrow's CPU-to-wall ratio in its 5 s run; equal budgets run once), printing
the densities and CPU times side by side and the four mean gaps:

    cargo bench -p cam-nest --bench nest_measure
    /tmp/nestref/bin/python tools/nest_reference.py --measure
    NEST_MEASURE_SEEDS=9100 cargo bench -p cam-nest --bench nest_measure   # the fresh set
    /tmp/nestref/bin/python tools/nest_reference.py --measure target/nest-bench/measure-9100.json

With `--esicup` it reads the figures of `cargo bench -p cam-nest --bench strip_instances` (written to
`target/nest-bench/esicup-<budget>.json`; the ESICUP instances, our density, wall and CPU time per instance)
and nests each instance with sparrow at the same time budget, straight from the instance's own JSON (sparrow's
form: no turning, the instance's orientations, separation 0). It prints the load, both densities side by side,
sparrow's published 20-minute densities (the instance folder's README, Gardeyn & Wauters 2025, Table 2) as the
ceiling, the mean gap and the instances won:

    NEST_TIME_S=30 cargo bench -p cam-nest --bench strip_instances
    /tmp/nestref/bin/python tools/nest_reference.py --esicup target/nest-bench/esicup-30.0s.json

sparrow stops on wall-clock time (seeded, but not reproducible across machines); that is why
this is a hand-run reference and not a test.
"""

import argparse
import json
import math
import resource
import sys
import time
from pathlib import Path

import spyrrow


def area(ring):
    return abs(
        sum(
            ring[i][0] * ring[(i + 1) % len(ring)][1]
            - ring[(i + 1) % len(ring)][0] * ring[i][1]
            for i in range(len(ring))
        )
        / 2.0
    )


def cpu_seconds():
    """User + system CPU seconds of this process (sparrow's workers are its threads)."""
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


def sparrow(name, height, items, seconds, workers, seed, early_termination, separation=None):
    """One sparrow run on a strip `height` high: its solution, wall seconds and CPU seconds."""
    instance = spyrrow.StripPackingInstance(name, strip_height=height, items=items)
    extra = {} if separation is None else {"min_items_separation": separation}
    config = spyrrow.StripPackingConfig(
        early_termination=early_termination,
        total_computation_time=seconds,
        num_workers=workers,
        seed=seed,
        **extra,
    )
    started, cpu_started = time.time(), cpu_seconds()
    solution = instance.solve(config)
    return solution, time.time() - started, cpu_seconds() - cpu_started


def solve(batch, seconds, workers, seed):
    width = batch["strip_width_mm"]
    sep = batch["separation_mm"]
    shapes = {}
    items = []
    for index, item in enumerate(batch["items"]):
        if item["demand"] == 0:
            continue
        # Our x (across the strip) becomes sparrow's y (its fixed strip height).
        ring = [(-y, x) for x, y in item["outline"]]
        shapes[str(index)] = ring
        items.append(
            spyrrow.Item(
                str(index),
                ring,
                demand=item["demand"],
                allowed_orientations=[float(r) for r in item["rotations_deg"]],
            )
        )
    solution, elapsed, cpu = sparrow(
        batch["name"], width, items, seconds, workers, seed, early_termination=True, separation=sep
    )
    xs, ys, part_area = [], [], 0.0
    for placed in solution.placed_items:
        c, s = math.cos(math.radians(placed.rotation)), math.sin(math.radians(placed.rotation))
        tx, ty = placed.translation
        ring = shapes[placed.id]
        part_area += area(ring)
        for x, y in ring:
            xs.append(c * x - s * y + tx)
            ys.append(s * x + c * y + ty)
    demanded = sum(i["demand"] for i in batch["items"])
    if len(solution.placed_items) != demanded:
        sys.exit(f"{batch['name']}: {len(solution.placed_items)} of {demanded} parts placed")
    # The edge gap holds as for our nester (sparrow keeps the separation to the strip edges).
    edge = min(min(xs), min(ys), width - max(ys))
    if edge < sep - 1e-3:
        sys.exit(f"{batch['name']}: a part is {edge:.4f} mm from the strip edge (needs {sep})")
    length = max(xs) + sep
    return {
        "density": part_area / (width * length),
        "length_mm": length,
        "sparrow_density": solution.density,
        "seconds": elapsed,
        "cpu_seconds": cpu,
        "time_budget_s": seconds,
        "workers": workers,
        "seed": seed,
        "packer": f"spyrrow {getattr(spyrrow, '__version__', '0.9.0')}",
    }


def published(folder):
    """Sparrow's published expected densities by instance name, from the folder's README table."""
    readme = Path(folder) / "README.md"
    if not readme.exists():
        return {}
    found = {}
    for line in readme.read_text().splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) == 2:
            try:
                found[cells[0].lower()] = float(cells[1]) / 100.0
            except ValueError:
                pass
    return found


def solve_instance(path, seconds, workers, seed):
    """Sparrow on an instance in its own JSON form; density = part area / (strip height x length)."""
    instance = json.loads(Path(path).read_text())
    items, part_area, shapes = [], 0.0, {}
    for index, item in enumerate(instance["items"]):
        shape = item["shape"]
        ring = shape["data"] if shape["type"] == "simple_polygon" else shape["data"]["outer"]
        ring = [tuple(p) for p in ring]
        shapes[str(index)] = ring
        part_area += area(ring) * item["demand"]
        orientations = item.get("allowed_orientations")
        items.append(
            spyrrow.Item(
                str(index),
                ring,
                demand=item["demand"],
                allowed_orientations=None if orientations is None else [float(r) for r in orientations],
            )
        )
    height = instance["strip_height"]
    # The whole budget, as the engine it is compared with uses its whole time budget.
    solution, elapsed, cpu = sparrow(
        instance["name"], height, items, seconds, workers, seed, early_termination=False
    )
    xs = []
    for placed in solution.placed_items:
        c, s = math.cos(math.radians(placed.rotation)), math.sin(math.radians(placed.rotation))
        tx, ty = placed.translation
        for x, y in shapes[placed.id]:
            xs.append(c * x - s * y + tx)
    demanded = sum(i["demand"] for i in instance["items"])
    if len(solution.placed_items) != demanded:
        sys.exit(f"{instance['name']}: {len(solution.placed_items)} of {demanded} parts placed")
    length = max(xs) - min(0.0, min(xs))
    return {"density": part_area / (height * length), "seconds": elapsed, "cpu_seconds": cpu}


def load_average():
    with open("/proc/loadavg") as f:
        return " ".join(f.read().split()[:3])


def esicup(path, workers, seed):
    """Our figures from the strip_instances bench beside sparrow's at the same time budget."""
    rows = json.loads(Path(path).read_text())
    budget = rows[0]["time_budget_s"] if rows else None
    if budget is None:
        sys.exit(f"{path}: no time budget (run the bench with NEST_TIME_S)")
    seconds = max(1, round(budget))
    ceiling = published(Path(rows[0]["instance"]).parent)
    print(f"ESICUP at {seconds} s, {workers} workers, seed {seed}; load average {load_average()} (1, 5, 15 min)")
    print(
        f"{'instance':<10} {'parts':>5} {'ours %':>7} {'wall s':>6} {'CPU s':>6} "
        f"{'sparrow %':>9} {'wall s':>6} {'CPU s':>6} {'gap':>6} {'20 min %':>8}"
    )
    gaps, won = [], 0
    for row in rows:
        theirs = solve_instance(row["instance"], seconds, workers, seed)
        gap = row["density"] - theirs["density"]
        gaps.append(gap)
        won += gap > 0
        top = ceiling.get(row["name"].lower())
        print(
            f"{row['name']:<10} {row['parts']:>5} {100 * row['density']:>7.2f} {row['wall_s']:>6.2f} "
            f"{row['cpu_s']:>6.2f} {100 * theirs['density']:>9.2f} {theirs['seconds']:>6.2f} "
            f"{theirs['cpu_seconds']:>6.2f} {100 * gap:>+6.2f} {'-' if top is None else f'{100 * top:.2f}':>8}",
            flush=True,
        )
    n = len(rows)
    ours = sum(r["density"] for r in rows) / n
    print(
        f"mean: ours {100 * ours:.2f} %, sparrow {100 * (ours - sum(gaps) / n):.2f} %, "
        f"gap {100 * sum(gaps) / n:+.2f} points; ours ahead on {won} of {n}; load average {load_average()}"
    )


def measure(path, workers, seed):
    """Our figures from the measuring bench beside sparrow's: ours as of 5 s of wall time (the last
    layout the engine reported within 5 s, `ours_at_5s`) beside sparrow after 5 s (equal wall) and
    beside sparrow given our CPU time of those 5 s (equal CPU); then our full run beside sparrow at
    our wall time and at our CPU time. Sparrow's wall budget for an equal CPU time is that CPU time
    over the CPU-to-wall ratio of its 5 s run."""
    batches = json.loads(Path(path).read_text())
    print(
        f"{'batch':<14} {'parts':>5} {'ours5 %':>7} {'at s':>5} {'cpu s':>6} {'sp 5s %':>8} {'cpu s':>6} "
        f"{'sp =c5 %':>8} {'c5 s':>4} | {'ours %':>7} {'ours s':>7} {'cpu s':>6} "
        f"{'sp =t %':>8} {'t s':>4} {'sp =c %':>8} {'c s':>4}"
    )
    rows = []
    runs = {}

    def sparrow(batch, seconds):
        # One run per batch and budget: the equal-time budgets often round to the same seconds.
        key = (batch["name"], seconds)
        if key not in runs:
            runs[key] = solve(batch, seconds, workers, seed)
        return runs[key]

    for batch in batches:
        ours = batch["ours"]
        at5 = batch.get("ours_at_5s")
        if at5 is None:
            sys.exit(f"{path}: no ours_at_5s (written by an older nest_measure); run the bench again")
        if at5["wall_limit_s"] != 5:
            sys.exit(f"{path}: ours_at_5s is as of {at5['wall_limit_s']} s, sparrow runs 5 s")
        five = sparrow(batch, 5)
        ratio = five["cpu_seconds"] / five["seconds"]
        # No layout within 5 s: density 0, and sparrow's 5 s stand at equal CPU too.
        at5_cpu = at5.get("cpu_seconds")
        equal_cpu5 = 5 if at5_cpu is None else max(1, round(at5_cpu / ratio))
        cpu5 = sparrow(batch, equal_cpu5)
        equal = max(1, round(ours["seconds"]))
        same = sparrow(batch, equal)
        ours_cpu = ours.get("cpu_seconds", ours["seconds"])
        equal_cpu = max(1, round(ours_cpu / ratio))
        cpu = sparrow(batch, equal_cpu)
        parts = sum(i["demand"] for i in batch["items"])
        rows.append(
            (at5["density"], five["density"], cpu5["density"], ours["density"], ours["seconds"],
             same["density"], cpu["density"])
        )
        known = at5["known_at_seconds"]
        print(
            f"{batch['name']:<14} {parts:>5} {100 * at5['density']:>7.2f} "
            f"{'-' if known is None else f'{known:.2f}':>5} "
            f"{'-' if at5_cpu is None else f'{at5_cpu:.2f}':>6} "
            f"{100 * five['density']:>8.2f} {five['cpu_seconds']:>6.2f} "
            f"{100 * cpu5['density']:>8.2f} {equal_cpu5:>4} | "
            f"{100 * ours['density']:>7.2f} {ours['seconds']:>7.2f} {ours_cpu:>6.2f} "
            f"{100 * same['density']:>8.2f} {equal:>4} {100 * cpu['density']:>8.2f} {equal_cpu:>4}",
            flush=True,
        )
    n = len(rows)
    mean = [sum(r[k] for r in rows) / n for k in range(7)]
    print(
        f"{'mean':<14} {'':>5} {100 * mean[0]:>7.2f} {'':>5} {'':>6} {100 * mean[1]:>8.2f} {'':>6} "
        f"{100 * mean[2]:>8.2f} {'':>4} | {100 * mean[3]:>7.2f} {mean[4]:>7.2f} {'':>6} "
        f"{100 * mean[5]:>8.2f} {'':>4} {100 * mean[6]:>8.2f}"
    )
    gap = lambda a, b: f"{100 * (a - b):+.2f} points"
    print(f"at 5 s wall:           ours {100 * mean[0]:.2f} %, sparrow {100 * mean[1]:.2f} % ({gap(mean[0], mean[1])})")
    print(f"at ours' 5 s CPU:      ours {100 * mean[0]:.2f} %, sparrow {100 * mean[2]:.2f} % ({gap(mean[0], mean[2])})")
    print(f"at our full wall time: ours {100 * mean[3]:.2f} %, sparrow {100 * mean[5]:.2f} % ({gap(mean[3], mean[5])})")
    print(f"at our full CPU time:  ours {100 * mean[3]:.2f} %, sparrow {100 * mean[6]:.2f} % ({gap(mean[3], mean[6])})")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--batches", default="target/nest-bench/batches.json")
    parser.add_argument("--out", default="target/nest-bench/reference.json")
    parser.add_argument("--seconds", type=int, default=30, help="time budget per batch")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--measure", nargs="?", const="target/nest-bench/measure.json",
                        help="our figures from the measuring bench beside sparrow's")
    parser.add_argument("--esicup", help="our strip_instances figures beside sparrow's at their budget")
    args = parser.parse_args()
    if args.esicup:
        esicup(args.esicup, args.workers, args.seed)
        return
    if args.measure:
        measure(args.measure, args.workers, args.seed)
        return
    batches = json.loads(Path(args.batches).read_text())
    results = {}
    for batch in batches:
        result = solve(batch, args.seconds, args.workers, args.seed)
        results[batch["name"]] = result
        print(
            f"{batch['name']:<12} strip length {result['length_mm']:7.2f} mm, "
            f"density {100 * result['density']:.1f} % ({result['seconds']:.0f} s)",
            flush=True,
        )
    mean = sum(r["density"] for r in results.values()) / len(results)
    print(f"mean density {100 * mean:.1f} %")
    Path(args.out).write_text(json.dumps(results, indent=2) + "\n")


if __name__ == "__main__":
    main()
