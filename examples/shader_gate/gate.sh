#!/bin/sh
# The CI gate for an engine's shader: run it, check its limits, compare with the committed
# baseline. Usage: gate.sh PXH SHADER_DIR OUT [camera | camera-quick]
# (exit 0 pass, 1 regression, 2 bad input). Both gates always run (no stop after the first
# failure) and both verdicts are printed, and written beside OUT as JUnit XML and JSON
# (OUT.check.xml/.json, OUT.compare.xml/.json) for a CI system's test report.
#   (none)        experiment.toml, thresholds.toml, baseline/: the orthographic grid
#   camera        camera.toml, camera_thresholds.toml, camera_baseline/: a perspective camera
#   camera-quick  the same image at --samples 32, against camera_baseline_quick/
PXH="$1"; DIR="$2"; OUT="$3"; MODE="${4:-}"
case "$MODE" in
  "") EXP=experiment.toml; TH=thresholds.toml; BASE=baseline; OPTS="" ;;
  camera) EXP=camera.toml; TH=camera_thresholds.toml; BASE=camera_baseline; OPTS="" ;;
  camera-quick) EXP=camera.toml; TH=camera_thresholds.toml; BASE=camera_baseline_quick; OPTS="--samples 32" ;;
  *) echo "gate: unknown mode '$MODE' (camera | camera-quick)"; exit 2 ;;
esac
# shellcheck disable=SC2086
"$PXH" run "$DIR/$EXP" --quiet --out "$OUT" $OPTS
run=$?
# 1: some rows failed (both gates fail them); anything else but 0: nothing to gate.
if [ "$run" -ne 0 ] && [ "$run" -ne 1 ]; then echo "gate: pxh run exited $run"; exit 2; fi
"$PXH" check "$OUT" --thresholds "$DIR/$TH" --junit "$OUT.check.xml" --json "$OUT.check.json"
check=$?
"$PXH" compare "$DIR/$BASE" "$OUT" --fail-on err_p95=+5%,err_mean=+0.001,fetches_mean=+0,nonfinite=+0 \
  --junit "$OUT.compare.xml" --json "$OUT.compare.json"
compare=$?
verdict() { case "$1" in 0) echo pass ;; 1) echo FAIL ;; *) echo "bad input (exit $1)" ;; esac; }
echo "gate: pxh check $(verdict $check), pxh compare $(verdict $compare)"
if [ "$check" -ge 2 ] || [ "$compare" -ge 2 ]; then exit 2; fi
if [ "$check" -ne 0 ] || [ "$compare" -ne 0 ]; then exit 1; fi
exit 0
