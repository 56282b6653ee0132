#!/usr/bin/env python3
"""Cell-by-cell comparison of two results.csv files (the layout change's identity check).

    compare_results.py BEFORE.csv AFTER.csv

Rows are compared in order; every column present in both files is compared as text, except the
timing columns (ns_per_sample*, ms_per_frame*, gpu_ms*, precompute_ms), which are measured anew
on every run. Columns only in AFTER are listed as added; a column only in BEFORE is a difference.
Exit 0 when identical, 1 otherwise (the first differences are printed)."""
import csv
import sys

TIMING_PREFIXES = ("ns_per_sample", "ms_per_frame", "gpu_ms", "precompute_ms")


def read(path):
    with open(path, newline="") as f:
        r = csv.reader(f)
        header = next(r)
        return header, list(r)


def main():
    if len(sys.argv) != 3:
        print(__doc__.strip().splitlines()[2].strip(), file=sys.stderr)
        return 2
    hb, rb = read(sys.argv[1])
    ha, ra = read(sys.argv[2])
    added = [c for c in ha if c not in hb]
    missing = [c for c in hb if c not in ha]
    timing = [c for c in hb if c.startswith(TIMING_PREFIXES)]
    compared = [c for c in hb if c in ha and c not in timing]
    ib = {c: i for i, c in enumerate(hb)}
    ia = {c: i for i, c in enumerate(ha)}
    diffs = []
    if len(rb) != len(ra):
        diffs.append(f"row count {len(rb)} -> {len(ra)}")
    for k, (b, a) in enumerate(zip(rb, ra)):
        for c in compared:
            if b[ib[c]] != a[ia[c]]:
                diffs.append(f"row {k + 2} column {c}: {b[ib[c]]!r} -> {a[ia[c]]!r}")
    cells = min(len(rb), len(ra)) * len(compared)
    print(f"{sys.argv[1]} vs {sys.argv[2]}: {len(ra)} rows, {len(compared)} columns compared "
          f"({cells} cells), timing columns skipped: {', '.join(timing) or 'none'}; "
          f"added: {', '.join(added) or 'none'}; missing: {', '.join(missing) or 'none'}")
    for d in diffs[:20]:
        print("  DIFF " + d)
    if len(diffs) > 20:
        print(f"  ... {len(diffs) - 20} more")
    ok = not diffs and not missing
    print("IDENTICAL" if ok else f"DIFFERENT ({len(diffs)} differing cells)")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
