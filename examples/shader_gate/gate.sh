#!/bin/sh
# The CI gate for an engine's shader: run it, check its limits, compare with the committed
# baseline. Usage: gate.sh PXH SHADER_DIR OUT (exit 0 pass, 1 regression, 2 bad input).
set -e
PXH="$1"; DIR="$2"; OUT="$3"
"$PXH" run "$DIR/experiment.toml" --quiet --out "$OUT"
"$PXH" check "$OUT" --thresholds "$DIR/thresholds.toml"
"$PXH" compare "$DIR/baseline" "$OUT" --fail-on err_p95=+5%,err_mean=+0.001,fetches_mean=+0
