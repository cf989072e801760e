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
    instance = spyrrow.StripPackingInstance(batch["name"], strip_height=width, items=items)
    config = spyrrow.StripPackingConfig(
        early_termination=True,
        min_items_separation=sep,
        total_computation_time=seconds,
        num_workers=workers,
        seed=seed,
    )
    started, cpu_started = time.time(), cpu_seconds()
    solution = instance.solve(config)
    elapsed, cpu = time.time() - started, cpu_seconds() - cpu_started
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
    args = parser.parse_args()
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
