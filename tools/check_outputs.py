#!/usr/bin/env python3
"""Check laser files written by actuator-cam.

Usage: check_outputs.py DIR [DIR...]

Walks each directory recursively and checks
  *.dxf  ezdxf.readfile + doc.audit() without errors, $INSUNITS == 4 (mm),
         $MEASUREMENT == 1 (metric), modelspace holds only LWPOLYLINE, CIRCLE, ARC;
  *.svg  well-formed XML, root width/height in "mm", a viewBox "0 0 W H" matching them,
         every <path d> made of absolute M, L, A, Z commands only.
Cross-layer checks (issue 16):
  *.svg  a laser file's page is its stock sheet (metadata width_mm, height_mm), and every drawn point
         (path end points; arcs by their end points and radius) lies on the page or no farther off it
         than the file's <desc> states ("Shapes reach X mm past the sheet edge"; a picture, with no
         stock, within its page);
         no path on the REFERENCE layer uses the stroke colour of the CUT layer or pure red;
  *.dxf  $LIMMIN at the origin and $LIMMAX the page of the SVG of the same name (one origin);
         $EXTMIN/$EXTMAX set (not both the origin) and every entity inside them; the REFERENCE
         layer's colour is not the CUT layer's nor ACI 1 (red), and it is not plotted;
  report.json (cut-sheet)  the mold stack is not above the laminate, and within the template's
         tolerance below it (or the report carries its warning); the press fit of the laminate and of
         the extension, computed from the layer thicknesses and the films, within the tolerance (or
         warned) and as the report states it; each mold-K file's stock is film K of the stack; each
         clamp layer's files (one per panel or per run of identical panels, `mold-1-1to6_…`, titled
         with the run and its sheet count) cover the report's panels once each.
  nest-report.json  every strip of roll stock (sheets[].roll): its DXF entities lie within the roll
         width and the reported length, the highest cut outline ends within 2 mm below that length
         (the separation and the 0.1 mm rounding), the SVG page is the roll width by that length, and
         the rolls[] row's length is that sheet's; with a price, cost = length / 1000 x price_per_m,
         and the cut sheets compared cost sheets x price_per_sheet.
  passive-*.svg  no label lies in a bonded zone: every open path (a label stroke: outlines are
         closed, holes are arcs) stays clear of every bonded zone, the metadata guides of kind
         bonded-zone; labelled sheets must mark one zone per part (CUT outline), and with a
         cut-sheet report.json beside them each zone spans the design's PZT length along the part axis
         (piezo_length_mm less pzt_edge_margin_mm), so a zone is the plate the design says.
  report.json with a "linkage" (cut-sheet --drive)  every panel of linkage-*.dxf files beside it:
         the carbon layers' flexure gap slots are the same; the film covers each gap by the reported
         margin (no film window reaches into it); an adhesive window holds each gap whole, as long as the
         report's unbonded length of that joint (the model's flexure); every cut-out,
         every web between cut-outs in a row, every release-outline edge and every hole is at least two
         kerfs; the pin holes are the same on every layer; the drawn areas (kerf taken off) times each
         layer's mass per area give the reported linkage mass to 1e-6.
  nest-report.json with "linkages"  the same checks on each linkage's coupon files (<prefix>N-<layer>-1),
         the nested coupons' shapes; and two carbon, two adhesive and one film coupon per linkage placed.
Prints one line per failing file, then `check_outputs: N passed, M failed`.
Exits 1 if any file failed or no file was found. Needs `pip install ezdxf`.
"""

import json
import math
import re
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

SVG_NS = "{http://www.w3.org/2000/svg}"
INKSCAPE_LABEL = "{http://www.inkscape.org/namespaces/inkscape}label"
ALLOWED_DXF_ENTITIES = {"LWPOLYLINE", "CIRCLE", "ARC"}
# Path data: commands M, L, A, Z and numbers, separated by spaces or commas.
PATH_TOKEN = re.compile(r"[A-Za-z]|[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")


EPS = 1e-6


def dxf_points(entity):
    """Extreme points of one entity (vertices; circles and arcs by centre +- radius)."""
    kind = entity.dxftype()
    if kind == "LWPOLYLINE":
        return [(x, y) for x, y, *_ in entity.get_points()]
    c, r = entity.dxf.center, entity.dxf.radius
    if kind == "CIRCLE":
        return [(c.x - r, c.y - r), (c.x + r, c.y + r)]
    # ARC: its end points and the axis points its counter-clockwise sweep passes.
    start, end = entity.dxf.start_angle, entity.dxf.end_angle
    sweep = (end - start) % 360 or 360
    points = [(c.x + r * math.cos(math.radians(a)), c.y + r * math.sin(math.radians(a)))
              for a in (start, start + sweep)]
    for axis, (dx, dy) in zip((0, 90, 180, 270), ((1, 0), (0, 1), (-1, 0), (0, -1))):
        if (axis - start) % 360 <= sweep:
            points.append((c.x + r * dx, c.y + r * dy))
    return points


def check_dxf_cross_layer(doc):
    """Extents and reference-layer problems of one DXF document."""
    problems = []
    lo, hi = doc.header.get("$EXTMIN"), doc.header.get("$EXTMAX")
    entities = list(doc.modelspace())
    if lo is None or hi is None or (tuple(lo)[:2] == (0, 0) and tuple(hi)[:2] == (0, 0)):
        if entities:
            problems.append("$EXTMIN/$EXTMAX not set")
    else:
        outside = sum(
            1
            for e in entities
            for x, y in dxf_points(e)
            if not (lo[0] - EPS <= x <= hi[0] + EPS and lo[1] - EPS <= y <= hi[1] + EPS)
        )
        if outside:
            problems.append(f"{outside} drawn point(s) outside $EXTMIN/$EXTMAX")
    layers = {layer.dxf.name: layer for layer in doc.layers}
    if "REFERENCE" in layers:
        ref = layers["REFERENCE"]
        cut_colour = layers["CUT"].color if "CUT" in layers else 1
        if abs(ref.color) in (1, abs(cut_colour)):
            problems.append(f"REFERENCE layer in a cut colour (ACI {ref.color})")
        if ref.dxf.get("plot", 1) != 0:
            problems.append("REFERENCE layer is plotted")
    return problems


def segment_hits_convex(a, b, ring):
    """Whether segment a-b passes through the interior of the convex ring (either orientation),
    by Cyrus-Beck clipping; touching the boundary does not count."""
    n = len(ring)
    area = sum(ring[i][0] * ring[(i + 1) % n][1] - ring[(i + 1) % n][0] * ring[i][1] for i in range(n))
    sign = 1.0 if area > 0 else -1.0
    t0, t1 = 0.0, 1.0
    d = (b[0] - a[0], b[1] - a[1])
    for i in range(n):
        p, q = ring[i], ring[(i + 1) % n]
        e = (q[0] - p[0], q[1] - p[1])
        length = math.hypot(*e) or 1.0
        # Inward distance of a point from this edge, shrunk by EPS so touching is outside.
        inside_a = sign * (e[0] * (a[1] - p[1]) - e[1] * (a[0] - p[0])) / length - EPS
        slope = sign * (e[0] * d[1] - e[1] * d[0]) / length
        if abs(slope) < 1e-15:
            if inside_a < 0:
                return False
            continue
        t = -inside_a / slope
        if slope > 0:
            t0 = max(t0, t)
        else:
            t1 = min(t1, t)
        if t0 >= t1:
            return False
    return t1 - t0 > 1e-9


GUIDE = "{urn:actuator-cam:guide}guide"


def polyline_of(d):
    """The points of a path made of M and L commands, and whether it is closed (ends in Z)."""
    tokens = PATH_TOKEN.findall(d)
    points, i = [], 0
    while i < len(tokens):
        if tokens[i] in ("M", "L"):
            points.append((float(tokens[i + 1]), float(tokens[i + 2])))
            i += 3
        else:
            i += 1
    return points, d.strip().endswith("Z")


def check_bonded_zones(path, root):
    """Labels against bonded zones on one passive sheet (see the module doc). The zones are guides in
    the SVG metadata, never paths: a path inside a part would be cut by laser software that ignores
    layer locks."""
    problems = []
    zones = [polyline_of(g.get("d", ""))[0] for g in root.iter(GUIDE) if g.get("kind") == "bonded-zone"]
    strokes, boxes = [], []
    for group in root.iter(SVG_NS + "g"):
        for p in group.iter(SVG_NS + "path"):
            d = p.get("d", "")
            if "A" in d:
                continue  # holes
            points, closed = polyline_of(d)
            if group.get(INKSCAPE_LABEL) == "CUT" and closed:
                xs, ys = [x for x, _ in points], [y for _, y in points]
                boxes.append((min(xs), min(ys), max(xs), max(ys)))
            elif not closed:
                strokes.append(points)
    outlines = len(boxes)
    # A part's label lies on the part; the sheet's stock label lies clear of every part, and says
    # nothing about bonded zones.
    labels = [
        s for s in strokes
        if s and any(b[0] <= s[0][0] <= b[2] and b[1] <= s[0][1] <= b[3] for b in boxes)
    ]
    if not labels:
        return problems
    # Extra parts from drawings (a nest batch's [[part]]) are cut outlines with no PZT bonded on them:
    # the nest report beside the sheet says how many of the sheet's parts are actuators' passive parts.
    nest_report = path.parent / "nest-report.json"
    if nest_report.exists():
        stem = path.stem
        for sheet in json.loads(nest_report.read_text()).get("sheets", []):
            if sheet.get("file_stem") == stem:
                outlines = sum(1 for p in sheet.get("parts", []) if p.get("part") == "passive")
    if len(zones) != outlines:
        problems.append(f"{len(labels)} label strokes but {len(zones)} bonded zones marked for {outlines} parts")
    crossing = sum(
        1
        for stroke in labels
        if any(segment_hits_convex(a, b, z) for a, b in zip(stroke, stroke[1:]) for z in zones)
    )
    if crossing:
        problems.append(f"{crossing} label stroke(s) lie in a bonded zone")
    report = path.parent / "report.json"
    if report.exists():

        r = json.loads(report.read_text())
        want = r["design"]["piezo_length_mm"] - r.get("pzt_edge_margin_mm", 0.0)
        for z in zones:
            # Parts turn by 0 or 180 degrees on a passive sheet: the axis runs along y.
            span = max(y for _, y in z) - min(y for _, y in z)
            if abs(span - want) > 1e-3:
                problems.append(f"a bonded zone spans {span:.4f} mm, not the PZT length {want:.4f} mm")
                break
    return problems


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
    problems += check_dxf_cross_layer(doc)
    problems += check_dxf_origin(Path(path), doc)
    return problems


def check_dxf_origin(path, doc):
    """One origin (docs/cam.md §3): the drawing limits are the sheet from (0, 0), and the SVG of the
    same name, when there is one, has that sheet as its page."""
    lo, hi = doc.header.get("$LIMMIN"), doc.header.get("$LIMMAX")
    if lo is None or hi is None or abs(lo[0]) > EPS or abs(lo[1]) > EPS:
        return [f"$LIMMIN {lo}: the sheet's corner must be the origin"]
    svg = path.with_suffix(".svg")
    if not svg.exists():
        return []
    root = ET.parse(svg).getroot()
    page = (mm_length(root.get("width")), mm_length(root.get("height")))
    if None in page or abs(page[0] - hi[0]) > 1e-5 or abs(page[1] - hi[1]) > 1e-5:
        return [f"$LIMMAX {tuple(hi)[:2]} is not the page {page} of {svg.name}"]
    return []


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
    page = None
    if view_box is not None and width is not None and height is not None:
        try:
            page = [float(v) for v in view_box.replace(",", " ").split()]
        except ValueError:
            page = None
    cut_strokes = {"#FF0000"}
    for group in root.iter(SVG_NS + "g"):
        if group.get(INKSCAPE_LABEL) == "CUT":
            cut_strokes |= {p.get("stroke", "").upper() for p in group.iter(SVG_NS + "path")}
    for group in root.iter(SVG_NS + "g"):
        if group.get(INKSCAPE_LABEL) == "REFERENCE":
            for p in group.iter(SVG_NS + "path"):
                if p.get("stroke", "").upper() in cut_strokes:
                    problems.append(f"reference geometry in a cut colour {p.get('stroke')}")
                    break
    stock = root.find(f"{SVG_NS}metadata/{{urn:actuator-cam:stock}}stock")
    overhang = 0.0
    if stock is not None and page is not None:
        sheet = (float(stock.get("width_mm")), float(stock.get("height_mm")))
        if abs(sheet[0] - page[2]) > EPS or abs(sheet[1] - page[3]) > EPS:
            problems.append(f"page {page[2]} x {page[3]} mm is not the {sheet[0]} x {sheet[1]} mm sheet")
        desc = root.find(SVG_NS + "desc")
        stated = re.search(r"Shapes reach ([0-9.]+) mm past the sheet edge", desc.text or "") if desc is not None else None
        overhang = float(stated.group(1)) if stated else 0.0
    off_page = 0
    for element in root.iter(SVG_NS + "path"):
        d = element.get("d", "")
        if page is not None:
            off_page += path_points_off_page(d, page, overhang)
        tokens = PATH_TOKEN.findall(d)
        leftover = PATH_TOKEN.sub("", d).replace(",", "").strip()
        commands = {t for t in tokens if t.isalpha()}
        bad = sorted(commands - set("MLAZ"))
        if bad or leftover or not tokens or tokens[0] != "M":
            problems.append(f"path d uses other than absolute M/L/A/Z: {d[:60]!r}")
    if off_page:
        problems.append(f"{off_page} drawn point(s) off the page by more than {overhang} mm")
    if Path(path).name.startswith("passive-"):
        problems += check_bonded_zones(Path(path), root)
    return problems


def path_points_off_page(d, page, overhang=0.0):
    """Number of points of one path off the page grown by `overhang` on every side: the end point of
    every command, and for an arc its end point moved out by the radius (a conservative box for the
    arcs the writer emits: at most half circles)."""
    x0, y0, w, h = page
    x0, y0, w, h = x0 - overhang, y0 - overhang, w + 2 * overhang, h + 2 * overhang
    tokens = PATH_TOKEN.findall(d)
    count = 0
    i = 0
    while i < len(tokens):
        cmd = tokens[i]
        i += 1
        try:
            if cmd in ("M", "L"):
                pts, r = [(float(tokens[i]), float(tokens[i + 1]))], 0.0
                i += 2
            elif cmd == "A":
                r = float(tokens[i])
                pts = [(float(tokens[i + 5]), float(tokens[i + 6]))]
                i += 7
            else:
                continue
        except (IndexError, ValueError):
            return count
        for x, y in pts:
            if not (x0 - EPS <= x - r and x + r <= x0 + w + EPS
                    and y0 - EPS <= y - r and y + r <= y0 + h + EPS):
                count += 1
    return count


def check_report(path):
    """Problems of one cut-sheet report.json: the mold stack against the laminate."""

    try:
        report = json.loads(Path(path).read_text())
    except (OSError, ValueError) as exc:
        return [f"unreadable: {exc}"]
    mold = report.get("mold")
    if mold is None:
        return ["no mold section"]
    problems = []
    diff_um = (mold["laminate_height_mm"] - mold["mold_height_mm"]) * 1e3
    if diff_um < -1e-3:
        problems.append(f"mold {mold['mold_height_mm']} mm stands above the laminate {mold['laminate_height_mm']} mm")
    if abs(sum(mold["films_mm"]) - mold["mold_height_mm"]) > 1e-6:
        problems.append("mold height is not the sum of its films")
    if diff_um > mold["tolerance_um"] + 1e-3 and not mold.get("warning"):
        problems.append(f"mold {diff_um:.1f} um below the laminate, beyond {mold['tolerance_um']} um, without a warning")
    problems += check_press_fit(Path(path).parent, report)
    problems += check_panel_runs(Path(path).parent, report)
    if "linkage" in report:
        problems += check_linkage(Path(path), report["linkage"])
    return problems


def check_panel_runs(folder, report):
    """Every clamp layer's files cover panels 1..clamp_panels once each: `<layer>-P_` for one panel,
    `<layer>-AtoB_` for a run of identical panels, whose SVG title names the run and its sheet count."""
    problems = []
    panels = report.get("clamp_panels", 0)
    for layer in report.get("stacking_order", []):
        covered = []
        for svg in folder.glob(f"{layer}-*_*.svg"):
            m = re.fullmatch(re.escape(layer) + r"-(\d+)(?:to(\d+))?_.*\.svg", svg.name)
            if not m:
                continue
            first = int(m.group(1))
            last = int(m.group(2) or first)
            covered += range(first, last + 1)
            if last > first:
                title = ET.parse(svg).getroot().find(SVG_NS + "title")
                want = f"panels {first}-{last}: cut {last - first + 1} sheets"
                if title is None or want not in (title.text or ""):
                    problems.append(f"{svg.name}: its title does not say {want!r}")
        if sorted(covered) != list(range(1, panels + 1)):
            problems.append(f"the {layer} files cover panels {sorted(covered)[:8]}..., not 1-{panels} once each")
    return problems


def check_press_fit(folder, report):
    """The press fit of every part region, computed here from the layer thicknesses and the mold films
    (not read from the report's own press_fit rows), and each mold file's stock against its film.

    The laminate is the lower PZT plate, the core (passive plies, plus a Pyralux bond layer on each side
    in method 1) and the upper plate. The films holding the lower plate, the core and the upper plate
    ("holds") stack up to three band tops. Over the PZT zone the laminate stands proud of the whole mold
    by laminate - mold. Over the extension only the passive plies run on, lying on the lower plate's bond
    layer (method 1's Pyralux is cut to the plate, so it ends with it): their underside is at t_p + bond,
    with a void of t_p + bond - lower top under them, and they stand t_p + bond + passive - core top proud.
    Each must be within the tolerance, or the report must warn."""
    mold = report["mold"]
    thickness = {row["layer"]: row["thickness_mm"] for row in report["layers"]}
    t_p = thickness["pzt"]
    # The passive core: one stack row, or one row per ply when the plies are cut one by one.
    passive = sum(t for layer, t in thickness.items() if layer.startswith("passive"))
    bond = thickness.get("pyralux", 0.0)
    core = passive + 2.0 * bond
    tops, height = {}, 0.0
    for film, holds in zip(mold["films_mm"], mold["holds"]):
        height += film
        tops[holds] = height
    lower = tops.get("lower plate", 0.0)
    core_top = tops.get("core", lower)
    regions = {
        "laminate": (0.0, 2.0 * t_p + core - height),
        "extension": (t_p + bond - lower, t_p + bond + passive - core_top),
    }
    tolerance = mold["tolerance_um"] * 1e-3
    problems = []
    for region, (void, proud) in regions.items():
        if (void > tolerance + 1e-9 or proud > tolerance + 1e-9 or void < -1e-9 or proud < -1e-9) \
                and not mold.get("warning"):
            problems.append(f"{region}: {void * 1e3:.1f} um void under it, {proud * 1e3:.1f} um proud, "
                            f"beyond {mold['tolerance_um']} um without a warning")
        stated = [f for f in mold.get("press_fit", []) if f["region"] == region]
        if stated and (abs(stated[0]["void_below_um"] - void * 1e3) > 0.06
                       or abs(stated[0]["proud_um"] - proud * 1e3) > 0.06):
            problems.append(f"{region}: the report's press fit {stated[0]} is not the films' "
                            f"({void * 1e3:.1f} um void, {proud * 1e3:.1f} um proud)")
    # Each mold sheet is cut from the film the stack needs: its file's stock says so.
    for k, film in enumerate(mold["films_mm"], start=1):
        for svg in folder.glob(f"mold-{k}-*.svg"):
            stock = re.search(r'<stock [^>]*thickness_mm="([^"]+)"', svg.read_text())
            if not stock or abs(float(stock.group(1)) - film) > 1e-9:
                problems.append(f"{svg.name}: stock {stock and stock.group(1)} mm, the stack needs {film} mm")
    return problems


# How far below the reported strip length the highest cut outline may end: the separation (kerf +
# spacing) above the last part plus the 0.1 mm rounding of the length. The examples' separation is
# under 1 mm; 2 mm still catches a length that does not match the drawing.
STRIP_SLACK_MM = 2.0


def closed_rings_and_circles(path):
    """Closed LWPOLYLINE rings and CIRCLEs (centre, radius) of a DXF file, in file order."""
    import ezdxf

    doc = ezdxf.readfile(path)
    rings, circles = [], []
    for e in doc.modelspace():
        if e.dxftype() == "LWPOLYLINE" and e.closed:
            rings.append([(x, y) for x, y, *_ in e.get_points()])
        elif e.dxftype() == "CIRCLE":
            c = e.dxf.center
            circles.append(((c.x, c.y), e.dxf.radius))
    return rings, circles


def shoelace(ring):
    return abs(sum(ring[i - 1][0] * ring[i][1] - ring[i][0] * ring[i - 1][1] for i in range(len(ring)))) / 2.0


def clip_x(ring, a, b):
    """The part of a ring between x = a and x = b."""
    def clip(ring, keep, x):
        out = []
        for i in range(len(ring)):
            p, q = ring[i], ring[(i + 1) % len(ring)]
            def cross():
                t = (x - p[0]) / (q[0] - p[0])
                return (x, p[1] + t * (q[1] - p[1]))
            if keep(p) and keep(q):
                out.append(q)
            elif keep(p):
                out.append(cross())
            elif keep(q):
                out += [cross(), q]
        return out
    ring = clip(ring, lambda p: p[0] >= a, a)
    return clip(ring, lambda p: p[0] <= b, b) if ring else []


def unkerf_outline(ring, d):
    """A rectilinear ring offset outwards by d, brought back: each edge moved in by d (axis-aligned)."""
    n = len(ring)
    area2 = sum(ring[i - 1][0] * ring[i][1] - ring[i][0] * ring[i - 1][1] for i in range(n))
    ccw = area2 > 0
    lines = []
    for i in range(n):
        p, q = ring[i], ring[(i + 1) % n]
        if abs(p[1] - q[1]) < 1e-12:  # horizontal: inward is +y for a CCW bottom edge
            inward = (1 if q[0] > p[0] else -1) * (1 if ccw else -1)
            lines.append(("h", p[1] + inward * d))
        else:
            inward = (-1 if q[1] > p[1] else 1) * (1 if ccw else -1)
            lines.append(("v", p[0] + inward * d))
    out = []
    for i in range(n):
        a, b = lines[i - 1], lines[i]
        out.append((b[1], a[1]) if b[0] == "v" else (a[1], b[1]))
    return out


def check_linkage(report_path, linkage, prefix="linkage-"):
    """Cross-layer problems of the linkage panels written beside a cut-sheet report, or of a nest's
    linkage coupon (files `<prefix>N-<layer>-1`)."""
    problems = []
    folder = report_path.parent
    kerf, margin = linkage["kerf_mm"], linkage["film_margin_mm"]
    two = 2 * kerf - 1e-9
    sigmas = [l["areal_density_mg_per_mm2"] for l in linkage["layers"]]
    names = [l["layer"] for l in linkage["layers"]]
    for panel in range(1, linkage["panels"] + 1):
        tag = f"{prefix}* panel {panel}"
        def sheet(stem):
            """The DXF of sheet `stem`, whatever stock its name carries after `_`."""
            found = sorted(folder.glob(f"{stem}_*.dxf")) or [folder / f"{stem}.dxf"]
            return found[0]

        files = [sheet(f"{prefix}{n}-{panel}") for n in names]
        release = sheet(f"{prefix}{len(names) + 1}-release-{panel}")
        if not all(f.exists() for f in files + [release]):
            problems.append(f"{tag}: DXF files missing")
            continue
        layers = [closed_rings_and_circles(f) for f in files]
        cut_outs = []
        for rings, _ in layers:
            rings = sorted(rings, key=shoelace, reverse=True)[1:]  # the largest is the panel outline
            bands = []
            for r in rings:
                xs, ys = [p[0] for p in r], [p[1] for p in r]
                bands.append((min(xs) - kerf / 2, max(xs) + kerf / 2, min(ys) - kerf / 2, max(ys) + kerf / 2))
            cut_outs.append(sorted(bands, key=lambda b: (round(b[2], 9), b[0])))
        carbon = [i for i, n in enumerate(names) if n.endswith("carbon")]
        adhesive = [i for i, n in enumerate(names) if n.endswith("adhesive")]
        film = [i for i, n in enumerate(names) if n.endswith("film")][0]
        gaps = cut_outs[carbon[0]]
        if len(gaps) != len(cut_outs[carbon[1]]) or any(
            abs(x - y) > 1e-9 for a, b in zip(gaps, cut_outs[carbon[1]]) for x, y in zip(a, b)
        ):
            problems.append(f"{tag}: the flexure gaps do not line up across the carbon layers")
        for g in gaps:
            lo, hi = g[0] - margin, g[1] + margin
            if any(w[2] < g[3] and w[3] > g[2] and w[0] < hi - 1e-9 and w[1] > lo + 1e-9 for w in cut_outs[film]):
                problems.append(f"{tag}: the film does not cover the gap at x = {g[0]:.4f} by {margin} mm")
            # The model's flexure is the film left unbonded (docs/physics.md §16.6): the adhesive window
            # over the gap, as long as the report's unbonded length of the joint with this gap.
            unbonded = [f["unbonded_um"] / 1e3 for f in linkage["flexures"]
                        if abs(f["length_um"] / 1e3 - (g[1] - g[0])) < 1e-6]
            if not unbonded:
                problems.append(f"{tag}: the gap at x = {g[0]:.4f} is no flexure of the report")
            for a in adhesive:
                held = [w for w in cut_outs[a]
                        if w[0] <= g[0] + 1e-9 and w[1] >= g[1] - 1e-9 and w[2] <= g[2] + 1e-9 and w[3] >= g[3] - 1e-9]
                if not held:
                    problems.append(f"{tag}: adhesive over the gap at x = {g[0]:.4f} in {names[a]}")
                elif not any(abs(held[0][1] - held[0][0] - u) < 1e-6 for u in unbonded):
                    problems.append(
                        f"{tag}: the film is unbonded over {held[0][1] - held[0][0]:.4f} mm at x = {g[0]:.4f}"
                        f" in {names[a]}, the model's flexure {unbonded} mm")
        for n, bands in zip(names, cut_outs):
            for b in bands:
                if b[1] - b[0] < two or b[3] - b[2] < two:
                    problems.append(f"{tag}: a cut-out of {n} is under two kerfs")
            for b0, b1 in zip(bands, bands[1:]):
                if abs(b0[2] - b1[2]) < 1e-9 and b1[0] - b0[1] < two:
                    problems.append(f"{tag}: a web of {n} is under two kerfs")
        pins = sorted(layers[0][1])
        for n, (_, circles) in zip(names, layers):
            if sorted(circles) != pins:
                problems.append(f"{tag}: the pin holes of {n} differ from {names[0]}'s")
        rel_rings, rel_circles = closed_rings_and_circles(release)
        holes = [(c, r + kerf / 2) for c, r in rel_circles if (c, r) not in pins]
        if len(rel_circles) != len(holes) + len(pins):
            problems.append(f"{tag}: the release cut's pin holes differ from the layers'")
        for _, r in holes:
            if 2 * r < two:
                problems.append(f"{tag}: a mounting hole is under two kerfs")
        for ring in rel_rings:
            outline = unkerf_outline(ring, kerf / 2)
            for i in range(len(outline)):
                p, q = outline[i - 1], outline[i]
                if math.hypot(q[0] - p[0], q[1] - p[1]) < two:
                    problems.append(f"{tag}: a release-outline edge is under two kerfs")
            xs, ys = [p[0] for p in outline], [p[1] for p in outline]
            box = (min(xs), max(xs), min(ys), max(ys))
            mass = 0.0
            for sigma, bands in zip(sigmas, cut_outs):
                area = shoelace(outline)
                for b in bands:
                    if b[0] < box[1] and b[1] > box[0] and b[2] < box[3] and b[3] > box[2]:
                        if b[2] > box[2] or b[3] < box[3]:
                            problems.append(f"{tag}: a cut-out stops inside a linkage")
                        part = clip_x(outline, b[0], b[1])
                        area -= shoelace(part) if len(part) > 2 else 0.0
                for c, r in holes:
                    here = box[0] < c[0] < box[1] and box[2] < c[1] < box[3]
                    if here and not any(b[0] <= c[0] <= b[1] and b[2] <= c[1] <= b[3] for b in bands):
                        area -= math.pi * r * r
                mass += sigma * area
            if abs(mass - linkage["mass_mg"]) > 1e-6 * linkage["mass_mg"]:
                problems.append(f"{tag}: drawn areas give {mass:.9f} mg, the report {linkage['mass_mg']:.9f} mg")
    return problems


def check_nest_report(path):
    """Problems of one nest-report.json: each roll strip against its drawing, and its cost."""

    try:
        report = json.loads(Path(path).read_text())
    except (OSError, ValueError) as exc:
        return [f"unreadable: {exc}"]
    problems = []
    strips = {s["file_stem"]: s for s in report.get("sheets", []) if s.get("roll")}
    rolls = {r["file_stem"]: r for r in report.get("rolls", [])}
    if set(rolls) != set(strips):
        problems.append(f"rolls[] lists {sorted(rolls)}, the sheets' strips are {sorted(strips)}")
    for stem, sheet in strips.items():
        width, length = sheet["width_mm"], sheet["height_mm"]
        dxf_path = path.parent / f"{stem}.dxf"
        if dxf_path.exists():
            import ezdxf  # as in check_dxf: an SVG-only run works without it

            doc = ezdxf.readfile(dxf_path)
            points = [p for e in doc.modelspace() for p in dxf_points(e)]
            outside = [p for p in points
                       if not (-EPS <= p[0] <= width + EPS and -EPS <= p[1] <= length + EPS)]
            if outside:
                problems.append(f"{stem}: {len(outside)} point(s) outside the {width} mm roll by {length} mm")
            cut_tops = [y for e in doc.modelspace() if e.dxf.layer == "CUT" and e.dxftype() == "LWPOLYLINE"
                        for _, y, *_ in e.get_points()]
            if not cut_tops:
                problems.append(f"{stem}: no cut outline")
            elif length - max(cut_tops) > STRIP_SLACK_MM:
                problems.append(f"{stem}: reported length {length} mm, but the parts end at {max(cut_tops):.3f} mm")
        svg_path = path.parent / f"{stem}.svg"
        if svg_path.exists():
            root = ET.parse(svg_path).getroot()
            page = (mm_length(root.get("width", "")), mm_length(root.get("height", "")))
            if page[0] is None or page[1] is None or abs(page[0] - width) > 1e-6 or abs(page[1] - length) > 1e-6:
                problems.append(f"{stem}.svg: page {page}, the strip is {width} x {length} mm")
        roll = rolls.get(stem)
        if roll is None:
            continue
        if abs(roll["length_mm"] - length) > 1e-9 or abs(roll["width_mm"] - width) > 1e-9:
            problems.append(f"{stem}: rolls[] says {roll['width_mm']} x {roll['length_mm']} mm, the sheet {width} x {length}")
        price = roll.get("price_per_m")
        if price is not None and abs(roll["cost"] - length / 1000.0 * price) > 1e-9:
            problems.append(f"{stem}: roll cost {roll['cost']} is not {length} mm at {price}/m")
        alt = roll.get("on_sheets")
        if alt and alt.get("price_per_sheet") is not None and abs(alt["cost"] - alt["sheets"] * alt["price_per_sheet"]) > 1e-9:
            problems.append(f"{stem}: the compared sheets' cost {alt['cost']} is not {alt['sheets']} x {alt['price_per_sheet']}")
    for linkage in report.get("linkages", []):
        # The coupon's files across their layers, as a cut sheet's panels; then every coupon nested:
        # two carbon, two adhesive and one film per linkage on the sheets.
        problems += check_linkage(Path(path), linkage, linkage["prefix"])
        placed = {}
        for sheet in report.get("sheets", []):
            for part in sheet["parts"]:
                placed[part["design"]] = placed.get(part["design"], 0) + 1
        for layer, per in (("carbon", 2), ("adhesive", 2), ("film", 1)):
            name = f"{linkage['design']}-linkage-{layer}"
            want = per * linkage["quantity"]
            if placed.get(name, 0) != want:
                problems.append(f"{name}: {placed.get(name, 0)} coupon(s) on the sheets, {want} wanted")
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
            p for p in base.rglob("*")
            if p.is_file()
            and (p.suffix.lower() in (".dxf", ".svg") or p.name in ("report.json", "nest-report.json"))
        )
    passed = failed = 0
    for path in files:
        if path.name == "report.json":
            problems = check_report(path)
        elif path.name == "nest-report.json":
            problems = check_nest_report(path)
        elif path.suffix.lower() == ".dxf":
            problems = check_dxf(path)
        else:
            problems = check_svg(path)
        if problems:
            failed += 1
            print(f"{path}: {'; '.join(problems)}")
        else:
            passed += 1
    print(f"check_outputs: {passed} passed, {failed} failed")
    return 1 if failed or not files else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
