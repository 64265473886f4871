"""Checks DXF files with ezdxf (Debian's python3-ezdxf) for tests/export_fixtures.rs.

Usage: dxf_audit.py FILE=SPLINES,INSUNITS,REFERENCE ...

Each FILE must load, pass ezdxf's audit without errors (fixes only of the one known kind, see
below), have $INSUNITS == INSUNITS, and hold exactly SPLINES SPLINE entities, each of degree 3
with len(knots) == len(control points) + 4.

REFERENCE is a JSON file written by the Rust test: {"accuracy": a, "chord_error": e,
"splines": [[x0, y0, x1, y1, ...], ...]}, one polyline per SPLINE (in order) through points of
the exact LAC chain, within e of it. Every SPLINE is evaluated with ezdxf's own B-spline
evaluator (construction_tool(), a ezdxf.math.BSpline) into a polyline within e of the spline
(per Bezier span of its bezier_decomposition(), steps bounded by the span's second difference;
see spline_polyline), and both ways are measured: each spline point to the reference polyline,
each reference point to the spline polyline. Both must be within a + 2e (the accuracy plus the
two polylines' chord errors: a point within a of the exact chain is within a + e of its
reference polyline, and of the spline's polyline likewise).

ezdxf's audit fixes, on files the `dxf` crate writes, 7 things per file: the TABLE head of each
of the seven symbol tables (VPORT, LTYPE, LAYER, STYLE, APPID, DIMSTYLE, BLOCK_RECORD) has no
handle (group code 5), and ezdxf assigns one ("Fixed invalid table head handle", audit code
INVALID_TABLE_HANDLE). Any other fix is reported as a problem.

Prints one line per file; exits 1 on any failure.
"""

import json
import math
import sys

import ezdxf
from ezdxf.audit import AuditError

# Largest parameter step of the spline polyline, in multiples of the accuracy: the knots are arc
# lengths, so this bounds the spacing of the spline points checked (a straight span would
# otherwise get two points).
MAX_STEP_ACCURACIES = 10.0

# Rounding of the numbers in the file: the `dxf` crate writes 12 decimals (5e-13 absolute); a
# relative 1e-9 of the accuracy covers that and the float arithmetic here.
ROUNDING = 1e-9


def table_head_fix(fix):
    return fix.code == AuditError.INVALID_TABLE_HANDLE and "table head handle" in fix.message


def spline_polyline(bspline, chord_error, max_step):
    """Points of `bspline` (ezdxf's evaluator) within `chord_error` of it: per Bezier span, N
    equal parameter steps where |C''| <= 6 max|P[i+2] - 2 P[i+1] + P[i]| (per unit span
    parameter) bounds the chord error by |C''| / (8 N^2)."""
    knots = bspline.knots()
    spans = sorted(set(knots))
    beziers = list(bspline.bezier_decomposition())
    if len(beziers) != len(spans) - 1:
        raise ValueError(f"{len(beziers)} Bezier spans for {len(spans) - 1} knot spans")
    params = [spans[0]]
    for (t0, t1), ctrl in zip(zip(spans, spans[1:]), beziers):
        second = max((ctrl[i + 2] - 2 * ctrl[i + 1] + ctrl[i]).magnitude for i in range(2))
        n = max(1, math.ceil(math.sqrt(6.0 * second / (8.0 * chord_error))),
                math.ceil((t1 - t0) / max_step))
        params.extend(t0 + (t1 - t0) * j / n for j in range(1, n + 1))
    return [(p.x, p.y) for p in bspline.points(params)]


class Polyline:
    """A polyline with a grid of cells of side 2 * reach, each listing the segments passing
    within reach of it, so that the distance from a point to the polyline is found exactly when
    it is at most `reach` (infinite otherwise)."""

    def __init__(self, points, reach):
        self.points = points
        self.cell = 2.0 * reach
        self.grid = {}
        for k in range(len(points) - 1):
            (ax, ay), (bx, by) = points[k], points[k + 1]
            # Marks every cell+-1 around points at most half a cell apart along the segment:
            # any point within reach (half a cell) of the segment is within 3/4 of a cell of
            # one of them, so in a marked cell.
            n = max(1, math.ceil(math.hypot(bx - ax, by - ay) / (0.5 * self.cell)))
            seen = set()
            for j in range(n + 1):
                x, y = ax + (bx - ax) * j / n, ay + (by - ay) * j / n
                cx, cy = math.floor(x / self.cell), math.floor(y / self.cell)
                for dx in (-1, 0, 1):
                    for dy in (-1, 0, 1):
                        seen.add((cx + dx, cy + dy))
            for c in seen:
                self.grid.setdefault(c, []).append(k)

    def distance(self, q):
        qx, qy = q
        c = (math.floor(qx / self.cell), math.floor(qy / self.cell))
        best = math.inf
        for k in self.grid.get(c, ()):
            (ax, ay), (bx, by) = self.points[k], self.points[k + 1]
            vx, vy = bx - ax, by - ay
            len2 = vx * vx + vy * vy
            t = 0.0 if len2 == 0 else max(0.0, min(1.0, ((qx - ax) * vx + (qy - ay) * vy) / len2))
            best = min(best, math.hypot(qx - ax - t * vx, qy - ay - t * vy))
        return best


def check_geometry(splines, reference, problems):
    """Returns the largest distance found (both ways) over every spline."""
    accuracy, chord = reference["accuracy"], reference["chord_error"]
    bound = (accuracy + 2.0 * chord) * (1.0 + ROUNDING)
    if len(reference["splines"]) != len(splines):
        problems.append(f"{len(reference['splines'])} reference chains for {len(splines)} splines")
        return math.inf, 0
    worst, checked = 0.0, 0
    for i, (spline, flat) in enumerate(zip(splines, reference["splines"])):
        exact = list(zip(flat[0::2], flat[1::2]))
        drawn = spline_polyline(spline.construction_tool(), chord, MAX_STEP_ACCURACIES * accuracy)
        for what, points, other in (("spline", drawn, exact), ("chain", exact, drawn)):
            target = Polyline(other, bound)
            for q in points:
                d = target.distance(q)
                checked += 1
                if d > bound:
                    far = "farther" if math.isinf(d) else f"{d:.3g}"
                    problems.append(f"spline {i}: a {what} point {q} is {far} from the other "
                                    f"(bound {bound:.3g})")
                    return math.inf, checked
                worst = max(worst, d)
    return worst, checked


def audit(path, expected, units, reference_path):
    doc = ezdxf.readfile(path)
    auditor = doc.audit()
    problems = [f"audit error: {e.message}" for e in auditor.errors]
    other_fixes = [f for f in auditor.fixes if not table_head_fix(f)]
    problems += [f"unexpected audit fix: {f.message}" for f in other_fixes]
    head_fixes = len(auditor.fixes) - len(other_fixes)
    if doc.header.get("$INSUNITS") != units:
        problems.append(f"$INSUNITS {doc.header.get('$INSUNITS')}, expected {units}")
    splines = list(doc.modelspace().query("SPLINE"))
    if len(splines) != expected:
        problems.append(f"{len(splines)} splines, expected {expected}")
    for s in splines:
        cps, knots = s.control_point_count(), s.knot_count()
        if s.dxf.degree != 3 or knots != cps + 4:
            problems.append(f"spline degree {s.dxf.degree}, {cps} control points, {knots} knots")
    with open(reference_path) as f:
        reference = json.load(f)
    worst, checked = check_geometry(splines, reference, problems)
    accuracy = reference["accuracy"]
    geometry = "within the accuracy both ways" if not problems else "NOT within the accuracy"
    print(f"{path}: {len(splines)} splines, {len(auditor.errors)} audit errors, "
          f"{head_fixes} fixes (table head handles), $INSUNITS {doc.header.get('$INSUNITS')}; "
          f"ezdxf's evaluation {geometry}: {checked} points, largest distance "
          f"{worst:.4g} = {worst / accuracy:.3f} x accuracy {accuracy:.4g} "
          f"(chord errors {reference['chord_error']:.3g} each)")
    for p in problems:
        print(f"  {p}")
    return not problems


def main(args):
    ok = True
    for arg in args:
        path, _, expected = arg.rpartition("=")
        splines, units, reference = expected.split(",", 2)
        ok = audit(path, int(splines), int(units), reference) and ok
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
