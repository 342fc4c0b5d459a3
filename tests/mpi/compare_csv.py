#!/usr/bin/env python3
"""Compares two CSV files of a gradmpm run (points_final.csv, reactions.csv) value by value.

  compare_csv.py A.csv B.csv [--rtol 1e-8]

Same header, same rows, the same non-numeric fields; every numeric column agrees to rtol
relative to the column's largest magnitude (a stress column of 1e4 is not judged by its
near-zero entries), or to 1e-6 of the file's largest magnitude for a column that is zero
up to round-off (a strain of 1e-16 under rollers). A component of a stress or strain
tensor (sxx .. sxz, exx .. exz, and their _g columns) or of a vector (x y z, X Y Z,
ux uy uz, rx ry rz, ux_g ..) is judged by the largest component of the tensor or vector
(frame-independent): a shear stress or a lateral displacement that symmetry makes 1e-5
of the others carries their round-off, not its own. Prints the worst difference; exit 0
when they agree, 1 when not."""
import csv
import re
import sys

TENSOR = re.compile(r"^([se])(xx|yy|zz|xy|yz|xz)(_g)?$")
VECTOR = re.compile(r"^([a-wA-W]?)([xyzXYZ])(_g)?$")


def tensor_of(name):
    """The tensor or vector whose component column `name` is (None: a scalar)."""
    m = TENSOR.match(name)
    if m:
        return ("tensor", m.group(1), m.group(3))
    m = VECTOR.match(name)
    if m:
        return ("vector", m.group(1), m.group(2).isupper(), m.group(3))
    return None


def read(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], rows[1:]


def main():
    args = sys.argv[1:]
    rtol = 1e-8
    if "--rtol" in args:
        i = args.index("--rtol")
        rtol = float(args[i + 1])
        del args[i : i + 2]
    (ha, ra), (hb, rb) = read(args[0]), read(args[1])
    if ha != hb or len(ra) != len(rb):
        print(f"different shape: {len(ra)} rows {ha} vs {len(rb)} rows {hb}")
        return 1
    columns = {}
    for c, name in enumerate(ha):
        try:
            columns[name] = ([float(r[c]) for r in ra], [float(r[c]) for r in rb])
        except ValueError:
            if [r[c] for r in ra] != [r[c] for r in rb]:
                print(f"column {name} differs")
                return 1
    magnitude = {n: max(map(abs, a + b), default=0.0) for n, (a, b) in columns.items()}
    floor = 1e-6 * max(magnitude.values(), default=0.0)
    tensors = {}
    for n in columns:
        if tensor_of(n):
            tensors[tensor_of(n)] = max(tensors.get(tensor_of(n), 0.0), magnitude[n])
    for n in columns:
        if tensor_of(n):
            magnitude[n] = tensors[tensor_of(n)]
    worst, where = 0.0, ""
    for name, (a, b) in columns.items():
        scale = max(magnitude[name], floor)
        for k, (x, y) in enumerate(zip(a, b)):
            d = abs(x - y) / scale if scale > 0 else 0.0
            if d > worst:
                worst, where = d, f"column {name}, row {k + 1}: {x!r} vs {y!r}"
    print(f"largest difference {worst:.3e} of the column's scale ({where or 'identical'}); tolerance {rtol:g}")
    return 0 if worst <= rtol else 1


if __name__ == "__main__":
    sys.exit(main())
