#!/bin/sh
# The CI gate for an engine's shader: run it, check its limits, compare with the committed
# baseline. Usage: gate.sh PXH SHADER_DIR OUT (exit 0 pass, 1 regression, 2 bad input).
# Both gates always run (no stop after the first failure) and both verdicts are printed.
PXH="$1"; DIR="$2"; OUT="$3"
"$PXH" run "$DIR/experiment.toml" --quiet --out "$OUT"
run=$?
# 1: some rows failed (both gates fail them); anything else but 0: nothing to gate.
if [ "$run" -ne 0 ] && [ "$run" -ne 1 ]; then echo "gate: pxh run exited $run"; exit 2; fi
"$PXH" check "$OUT" --thresholds "$DIR/thresholds.toml"
check=$?
"$PXH" compare "$DIR/baseline" "$OUT" --fail-on err_p95=+5%,err_mean=+0.001,fetches_mean=+0,nonfinite=+0
compare=$?
verdict() { case "$1" in 0) echo pass ;; 1) echo FAIL ;; *) echo "bad input (exit $1)" ;; esac; }
echo "gate: pxh check $(verdict $check), pxh compare $(verdict $compare)"
if [ "$check" -ge 2 ] || [ "$compare" -ge 2 ]; then exit 2; fi
if [ "$check" -ne 0 ] || [ "$compare" -ne 0 ]; then exit 1; fi
exit 0
