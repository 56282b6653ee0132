#!/usr/bin/env bash
# The installed tree works on its own: installs BUILD into PREFIX (cmake --install), runs the
# accuracy experiment with PREFIX/bin/pxh, draws its report (the plot script is found in
# PREFIX/share/pxh, not in the sources), then checks that a missing script is one clear line
# and a non-zero exit. Run from the source root (ctest does: the installed_report test).
#   scripts/install_test.sh BUILD PREFIX
set -euo pipefail
build="$1" prefix="$2"
fail() { echo "install_test: $*" >&2; exit 1; }
rm -rf "$prefix"
cmake --install "$build" --prefix "$prefix" >/dev/null
pxh="$prefix/bin/pxh"
[ -x "$pxh" ] || fail "no $pxh after cmake --install"
[ -f "$prefix/share/pxh/plot_report.py" ] || fail "no $prefix/share/pxh/plot_report.py"
"$pxh" run results/experiments/accuracy.toml --quiet --out "$prefix/run" >/dev/null
"$pxh" report "$prefix/run" >"$prefix/report.log" || fail "pxh report failed: $(tail -3 "$prefix/report.log")"
pngs=$(find "$prefix/run/report" -name '*.png' | wc -l)
pdfs=$(find "$prefix/run/report" -name '*.pdf' | wc -l)
[ "$pngs" -gt 0 ] && [ "$pngs" -eq "$pdfs" ] || fail "expected PNG and PDF figures (pxh report's default formats), got $pngs PNG, $pdfs PDF"
# Without the script: one line naming where it was looked for, exit status 1, tables written.
rm "$prefix/share/pxh/plot_report.py"
rc=0
"$pxh" report "$prefix/run" >/dev/null 2>"$prefix/missing.err" || rc=$?
[ "$rc" -eq 1 ] || fail "missing script: exit status $rc, expected 1"
[ "$(wc -l <"$prefix/missing.err")" -eq 1 ] || fail "missing script: not one line: $(cat "$prefix/missing.err")"
grep -q "plot_report.py not found: looked for .*share/pxh/plot_report.py" "$prefix/missing.err" ||
    fail "missing script: unexpected message: $(cat "$prefix/missing.err")"
echo "install_test: $pngs figures from $pxh; a missing script is refused in one line"
