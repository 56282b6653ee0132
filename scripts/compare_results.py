#!/usr/bin/env python3
"""Cell-by-cell comparison of two results.csv files (the layout change's identity check).

    compare_results.py BEFORE.csv AFTER.csv

Rows are compared in order; every column present in both files is compared as text, except the
timing columns (time* but time_unit, gpu_ms*, precompute_ms, and the columns time* replaced:
ns_per_sample*, ms_per_frame*), which are measured anew on every run. When BEFORE has the old timing columns and
AFTER time and time_unit, they are listed as renamed, and each row's unit is checked instead of
its value: a row with a time in ns_per_sample before has time_unit ns/sample after, one in
ms_per_frame ms/frame, an untimed one none. Columns only in AFTER are listed as added; any other
column only in BEFORE is a difference. Exit 0 when identical, 1 otherwise (the first
differences are printed)."""
import csv
import sys

TIMING_PREFIXES = ("time", "gpu_ms", "precompute_ms", "ns_per_sample", "ms_per_frame")
# The per-backend timing columns before time/time_unit, and the unit each became.
RENAMED = {"ns_per_sample": "ns/sample", "ms_per_frame": "ms/frame"}
SUFFIXES = ("", "_min", "_max", "_repeats")


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
    ib = {c: i for i, c in enumerate(hb)}
    ia = {c: i for i, c in enumerate(ha)}
    renamed = [old + s for old in RENAMED for s in SUFFIXES
               if old + s in ib and old + s not in ia and "time" + s in ia]
    if renamed and "time_unit" not in ia:
        renamed = []
    added = [c for c in ha if c not in hb]
    missing = [c for c in hb if c not in ha and c not in renamed]
    timing = [c for c in hb if c.startswith(TIMING_PREFIXES) and c != "time_unit"]
    compared = [c for c in hb if c in ha and c not in timing]
    diffs = []
    if len(rb) != len(ra):
        diffs.append(f"row count {len(rb)} -> {len(ra)}")
    for k, (b, a) in enumerate(zip(rb, ra)):
        for c in compared:
            if b[ib[c]] != a[ia[c]]:
                diffs.append(f"row {k + 2} column {c}: {b[ib[c]]!r} -> {a[ia[c]]!r}")
        if renamed:
            want = [u for old, u in RENAMED.items() if old in ib and b[ib[old]] != ""]
            want = want[0] if len(want) == 1 else ""
            if a[ia["time_unit"]] != want or (a[ia["time"]] == "") != (want == ""):
                diffs.append(f"row {k + 2}: timed in {want or 'nothing'} before, time_unit "
                             f"{a[ia['time_unit']]!r} time {a[ia['time']]!r} after")
    cells = min(len(rb), len(ra)) * len(compared)
    print(f"{sys.argv[1]} vs {sys.argv[2]}: {len(ra)} rows, {len(compared)} columns compared "
          f"({cells} cells), timing columns skipped: {', '.join(timing) or 'none'}; "
          f"renamed: {', '.join(renamed) + ' -> time* + time_unit' if renamed else 'none'}; "
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
