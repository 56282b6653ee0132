#!/usr/bin/env bash
# pxh's perspective and level rows against an independent computation from the contract
# (scripts/independent_check.py, numpy): runs tests/data/independent_check/perspective_levels.toml
# (parallax, steep, pom; lod base and level; distance 1.5 and 4; theta 30, 60, 80; CPU and
# GLSL), then the check, which must pass within 2% on every compared cell (after the check's
# own pieces pass its selftest: closed forms, brute force). Then the check must
# fail on a doctored copy of the results: six cells moved by 2.5% (one per compared column)
# must be the six failures, and a seventh moved by 1.5% must pass.
#   tests/truth/independent_check_test.sh PXH_BINARY WORK_DIR
# Run from the source root (ctest does: the independent_check test). The CPU rows are required;
# the GLSL rows are required as soon as one of them ran (status ok): a GLSL backend that cannot
# draw a perspective view fails all of them in pxh, and the check lists them as not checked.
set -uo pipefail
pxh=$(realpath -e -- "${1:?usage: independent_check_test.sh PXH_BINARY WORK_DIR}") || exit 1
work=${2:?usage: independent_check_test.sh PXH_BINARY WORK_DIR}
py=/usr/bin/python3
fail() {
  echo "independent_check_test: FAILED: $*" >&2
  exit 1
}
"$py" -c "import numpy" 2>/dev/null || fail "$py has no numpy (./run.sh installs python3-numpy)"
rm -rf "$work" && mkdir -p "$work" || fail "cannot make $work"
"$py" scripts/independent_check.py selftest >"$work/selftest.log" 2>&1 ||
  fail "the check's own pieces: $(grep -v '^ok' "$work/selftest.log")"

rc=0
"$pxh" run tests/data/independent_check/perspective_levels.toml --quiet --out "$work/run" \
  >"$work/run.log" 2>&1 || rc=$?
# exit 1 is a run with failed rows (the GLSL rows where the backend cannot draw the view); the
# check names them and requires every CPU row
[ "$rc" -le 1 ] && [ -f "$work/run/results.csv" ] ||
  fail "pxh run exited $rc: $(tail -3 "$work/run.log")"

# GLSL is required as soon as it drew one of these rows (then a failed GLSL row fails the test)
require=(--require-backend cpu)
glsl_ok=$("$py" -c 'import csv, sys
rows = csv.DictReader(open(sys.argv[1]))
print(any(r["backend"] == "glsl" and r["status"] == "ok" for r in rows))' \
  "$work/run/results.csv") || fail "cannot read $work/run/results.csv"
[ "$glsl_ok" = True ] && require+=(--require-backend glsl)
echo "independent_check_test: required backends: ${require[*]}"
"$py" scripts/independent_check.py check "$work/run" "${require[@]}" >"$work/check.log" 2>&1
rc=$?
cat "$work/check.log"
[ "$rc" -eq 0 ] || fail "the check exited $rc on pxh's own rows"

# The check must be able to fail: a doctored copy.
mkdir -p "$work/doctored" && cp "$work/run/run.json" "$work/doctored/" ||
  fail "cannot copy the run"
doctor() { "$py" - "$work/run/results.csv" "$work/doctored/results.csv"; }
doctor <<'EOF' || fail "cannot doctor the results"
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1], newline="")))
edits = [  # (method, params prefix, lod, theta, distance, resolution, column, factor)
    ("parallax", "", "base", "80", "1.5", "64", "err_mean", 1.025),
    ("steep", "layers=16", "level", "60", "4", "160", "err_p50", 0.975),
    ("pom", "layers=32", "level", "80", "1.5", "160", "fetches_mean", 1.025),
    ("pom", "layers=adaptive", "level", "30", "4", "64", "err_px_mean", 1.025),
    ("parallax", "", "level", "80", "4", "160", "samples_outside", 1.025),
    ("steep", "layers=16", "base", "30", "1.5", "160", "lod_mean", 1.025),
    ("steep", "layers=16", "base", "60", "1.5", "64", "err_mean", 1.015),  # within 2%: must pass
]
for method, params, lod, theta, dist, res, col, factor in edits:
    hit = [r for r in rows if r["method"] == method and r["params"].startswith(params) and
           r["lod"] == lod and r["theta_deg"] == theta and r["distance"] == dist and
           r["resolution"] == res and r["backend"] == "cpu"]
    if len(hit) != 1:
        sys.exit(f"{len(hit)} rows match {method} {params} {lod} {theta} {dist} {res}")
    hit[0][col] = repr(float(hit[0][col]) * factor)
with open(sys.argv[2], "w", newline="") as f:
    w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
    w.writeheader()
    w.writerows(rows)
EOF
rc=0
"$py" scripts/independent_check.py check "$work/doctored" --require-backend cpu --quiet \
  >"$work/doctored.log" 2>&1 || rc=$?
[ "$rc" -eq 1 ] ||
  fail "the check exited $rc on the doctored results, expected 1: $(tail -3 "$work/doctored.log")"
grep -q "FAIL: 6 cell(s) off by more than 2%" "$work/doctored.log" ||
  fail "the doctored results: not the six doctored cells: $(grep FAIL "$work/doctored.log")"
for col in err_mean err_p50 fetches_mean err_px_mean samples_outside lod_mean; do
  grep -q "^FAIL .*: $col pxh" "$work/doctored.log" || fail "the doctored $col was not caught"
done
echo "independent_check_test: pxh's rows pass; a doctored copy fails on exactly its six 2.5% cells"
