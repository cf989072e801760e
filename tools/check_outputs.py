#!/usr/bin/env python3
"""Check laser files written by actuator-cam.

Usage: check_outputs.py DIR [DIR...]

Walks each directory recursively and checks
  *.dxf  ezdxf.readfile + doc.audit() without errors, $INSUNITS == 4 (mm),
         $MEASUREMENT == 1 (metric), modelspace holds only LWPOLYLINE, CIRCLE, ARC;
  *.svg  well-formed XML, root width/height in "mm", a viewBox "0 0 W H" matching them,
         every <path d> made of absolute M, L, A, Z commands only.
Prints one line per failing file, then `check_outputs: N passed, M failed`.
Exits 1 if any file failed or no file was found. Needs `pip install ezdxf`.
"""

import math
import re
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

SVG_NS = "{http://www.w3.org/2000/svg}"
ALLOWED_DXF_ENTITIES = {"LWPOLYLINE", "CIRCLE", "ARC"}
# Path data: commands M, L, A, Z and numbers, separated by spaces or commas.
PATH_TOKEN = re.compile(r"[A-Za-z]|[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")


def check_dxf(path):
    """Problems found in one DXF file (empty list if none)."""
    import ezdxf  # imported here so an SVG-only check works without it

    try:
        doc = ezdxf.readfile(path)
    except Exception as exc:  # ezdxf raises several types for unreadable files
        return [f"unreadable: {exc}"]
    problems = []
    auditor = doc.audit()
    for error in auditor.errors:
        problems.append(f"audit error: {error.message}")
    insunits = doc.header.get("$INSUNITS")
    if insunits != 4:
        problems.append(f"$INSUNITS is {insunits}, expected 4 (mm)")
    measurement = doc.header.get("$MEASUREMENT")
    if measurement != 1:
        problems.append(f"$MEASUREMENT is {measurement}, expected 1 (metric)")
    kinds = sorted({e.dxftype() for e in doc.modelspace()} - ALLOWED_DXF_ENTITIES)
    if kinds:
        problems.append(f"entities other than LWPOLYLINE/CIRCLE/ARC: {', '.join(kinds)}")
    return problems


def mm_length(value):
    """Number in a length attribute that must end in mm, or None."""
    if value is None or not value.endswith("mm"):
        return None
    try:
        return float(value[:-2])
    except ValueError:
        return None


def check_svg(path):
    """Problems found in one SVG file (empty list if none)."""
    try:
        root = ET.parse(path).getroot()
    except (ET.ParseError, OSError) as exc:
        return [f"not well-formed XML: {exc}"]
    problems = []
    if root.tag != SVG_NS + "svg":
        problems.append(f"root element is {root.tag}, expected svg")
    width = mm_length(root.get("width"))
    height = mm_length(root.get("height"))
    if width is None or height is None:
        problems.append(
            f"width/height must end in mm: {root.get('width')!r} {root.get('height')!r}"
        )
    view_box = root.get("viewBox")
    if view_box is None:
        problems.append("no viewBox")
    else:
        try:
            numbers = [float(v) for v in view_box.replace(",", " ").split()]
        except ValueError:
            numbers = []
        if len(numbers) != 4:
            problems.append(f"viewBox {view_box!r} is not four numbers")
        elif width is not None and height is not None:
            x, y, w, h = numbers
            if x != 0 or y != 0 or not math.isclose(w, width) or not math.isclose(h, height):
                problems.append(
                    f"viewBox {view_box!r} does not match {width}mm x {height}mm "
                    "(one user unit must be 1 mm)"
                )
    for element in root.iter(SVG_NS + "path"):
        d = element.get("d", "")
        tokens = PATH_TOKEN.findall(d)
        leftover = PATH_TOKEN.sub("", d).replace(",", "").strip()
        commands = {t for t in tokens if t.isalpha()}
        bad = sorted(commands - set("MLAZ"))
        if bad or leftover or not tokens or tokens[0] != "M":
            problems.append(f"path d uses other than absolute M/L/A/Z: {d[:60]!r}")
    return problems


def main(argv):
    if len(argv) < 2:
        print(__doc__.strip().splitlines()[2], file=sys.stderr)
        return 2
    files = []
    for directory in argv[1:]:
        base = Path(directory)
        if not base.is_dir():
            print(f"{directory}: not a directory")
            continue
        files += sorted(
            p for p in base.rglob("*") if p.is_file() and p.suffix.lower() in (".dxf", ".svg")
        )
    passed = failed = 0
    for path in files:
        problems = check_dxf(path) if path.suffix.lower() == ".dxf" else check_svg(path)
        if problems:
            failed += 1
            print(f"{path}: {'; '.join(problems)}")
        else:
            passed += 1
    print(f"check_outputs: {passed} passed, {failed} failed")
    return 1 if failed or not files else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
