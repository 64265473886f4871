"""Audits DXF files with ezdxf (Debian's python3-ezdxf) for tests/export_fixtures.rs.

Usage: dxf_audit.py FILE=SPLINES,INSUNITS ...  Each FILE must load, pass ezdxf's audit without
errors, have $INSUNITS == INSUNITS, and hold exactly SPLINES SPLINE entities, each of degree 3
with len(knots) == len(control points) + 4. Prints one line per file; exits 1 on any failure.
"""

import sys

import ezdxf


def audit(path, expected, units):
    doc = ezdxf.readfile(path)
    auditor = doc.audit()
    problems = [f"audit error: {e.message}" for e in auditor.errors]
    if doc.header.get("$INSUNITS") != units:
        problems.append(f"$INSUNITS {doc.header.get('$INSUNITS')}, expected {units}")
    splines = doc.modelspace().query("SPLINE")
    if len(splines) != expected:
        problems.append(f"{len(splines)} splines, expected {expected}")
    for s in splines:
        cps, knots = s.control_point_count(), s.knot_count()
        if s.dxf.degree != 3 or knots != cps + 4:
            problems.append(f"spline degree {s.dxf.degree}, {cps} control points, {knots} knots")
    print(f"{path}: {len(splines)} splines, {len(auditor.errors)} audit errors, "
          f"{len(auditor.fixes)} fixes, $INSUNITS {doc.header.get('$INSUNITS')}")
    for p in problems:
        print(f"  {p}")
    return not problems


def main(args):
    ok = True
    for arg in args:
        path, _, expected = arg.rpartition("=")
        splines, units = expected.split(",")
        ok = audit(path, int(splines), int(units)) and ok
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
