#!/bin/sh
# The CI gate for an engine's shader: run it, check its limits, compare with the committed
# baseline. Usage: gate.sh PXH SHADER_DIR OUT [camera | camera-quick]
# (exit 0 pass, 1 regression, 2 bad input). Both gates always run (no stop after the first
# failure). Every step writes its verdict beside OUT as JUnit XML and JSON for a CI system's
# test report, whatever happens: OUT.run.xml/.json (the run: a shader that does not compile
# fails here, with the compiler's FILE:LINE), OUT.check.xml/.json and OUT.compare.xml/.json
# (the two gates, when the run produced results). The log is short: each step's verdict line
# and its first failures; the whole outputs are in OUT.run.log, OUT.check.txt, OUT.compare.txt.
# The gate's verdict is the last line, printed once.
#   (none)        experiment.toml, thresholds.toml, baseline/: the orthographic grid
#   camera        camera.toml, camera_thresholds.toml, camera_baseline/: a perspective camera
#   camera-quick  the same image at --samples 32, against camera_baseline_quick/
PXH="$1"; DIR="$2"; OUT="$3"; MODE="${4:-}"
# What compare gates: every column the baseline has (a gated column it lacks fails the gate);
# screen-pixel errors (err_px_*) only through a camera, where the rows have them.
FAIL_ON=err_p95=+5%,err_mean=+0.001,fetches_mean=+0,nonfinite=+0
case "$MODE" in
  "") EXP=experiment.toml; TH=thresholds.toml; BASE=baseline; OPTS="" ;;
  camera) EXP=camera.toml; TH=camera_thresholds.toml; BASE=camera_baseline; OPTS=""
    FAIL_ON=err_p95=+5%,err_px_p95=+5%,err_mean=+0.001,fetches_mean=+0,nonfinite=+0 ;;
  camera-quick) EXP=camera.toml; TH=camera_thresholds.toml; BASE=camera_baseline_quick; OPTS="--samples 32"
    FAIL_ON=err_p95=+5%,err_px_p95=+5%,err_mean=+0.001,fetches_mean=+0,nonfinite=+0 ;;
  *) echo "gate: unknown mode '$MODE' (camera | camera-quick)"; exit 2 ;;
esac
SHOWN=8  # failures shown per step in the log (the rest are in the files)

# This gate's own files from an earlier run (never anything else: each is named after OUT).
for f in run.xml run.json run.log check.xml check.json check.txt compare.xml compare.json compare.txt; do
  rm -f "$OUT.$f"
done

xml_esc() { sed -e 's/&/\&amp;/g' -e 's/</\&lt;/g' -e 's/>/\&gt;/g' -e 's/"/\&quot;/g' -e "s/'/\&apos;/g"; }
json_esc() { tr -d '\000-\010\013-\037' | sed -e 's/\\/\\\\/g' -e 's/"/\\"/g' -e 's/	/\\t/g'; }
# verdict_files BASE TOOL CASE EXIT MESSAGE DETAILS: BASE.xml and BASE.json with one testcase,
# failed (MESSAGE, and DETAILS: a file whose lines are listed) unless EXIT is 0.
verdict_files() {
  vb="$1"; vt="$2"; vc="$3"; ve="$4"; vm="$5"; vd="$6"
  if [ "$ve" -eq 0 ]; then nf=0; else nf=1; fi
  {
    echo '<?xml version="1.0" encoding="UTF-8"?>'
    echo "<!-- pxh verdict: $vt (examples/shader_gate/gate.sh) -->"
    echo "<testsuites name=\"$vt\" tests=\"1\" failures=\"$nf\" errors=\"0\">"
    echo "  <testsuite name=\"$(printf '%s' "$vt $DIR/$EXP" | xml_esc)\" tests=\"1\" failures=\"$nf\" errors=\"0\" skipped=\"0\">"
    if [ "$nf" -eq 0 ]; then
      echo "    <testcase classname=\"pxh.gate\" name=\"$(printf '%s' "$vc" | xml_esc)\"/>"
    else
      echo "    <testcase classname=\"pxh.gate\" name=\"$(printf '%s' "$vc" | xml_esc)\">"
      printf '      <failure message="%s" type="error">' "$(printf '%s' "$vm" | xml_esc)"
      if [ -n "$vd" ] && [ -f "$vd" ]; then xml_esc < "$vd"; fi
      echo "</failure>"
      echo "    </testcase>"
    fi
    echo "  </testsuite>"
    echo "</testsuites>"
  } > "$vb.xml"
  {
    echo "{"
    echo "  \"format\": \"pxh verdict 1\","
    echo "  \"tool\": \"$vt\","
    echo "  \"subject\": \"$(printf '%s' "$DIR/$EXP" | json_esc)\","
    if [ "$nf" -eq 0 ]; then echo "  \"passed\": true,"; else echo "  \"passed\": false,"; fi
    echo "  \"exit_code\": $ve,"
    echo "  \"summary\": \"$(printf '%s' "$vm" | json_esc)\","
    echo "  \"failures\": $nf,"
    echo "  \"cases\": ["
    echo "    {"
    echo "      \"name\": \"$(printf '%s' "$vc" | json_esc)\","
    echo "      \"group\": \"pxh.gate\","
    if [ "$nf" -eq 0 ]; then echo "      \"passed\": true"; else
      echo "      \"passed\": false,"
      echo "      \"message\": \"$(printf '%s' "$vm" | json_esc)\","
      printf '      "details": ['
      if [ -n "$vd" ] && [ -f "$vd" ]; then
        json_esc < "$vd" | sed -e 's/^/"/' -e 's/$/"/' | paste -sd, - | tr -d '\n'
      fi
      echo "]"
    fi
    echo "    }"
    echo "  ]"
    echo "}"
  } > "$vb.json"
}
# The reason a pxh command gave for exit 2: its "pxh: error:" line (else its last line).
reason() {
  r=$(grep '^pxh: error: ' "$1" | tail -n 1 | sed 's/^pxh: error: //')
  if [ -z "$r" ]; then r=$(grep -v '^[[:space:]]*$' "$1" | tail -n 1); fi
  printf '%s' "$r"
}

# shellcheck disable=SC2086
"$PXH" run "$DIR/$EXP" --quiet --out "$OUT" $OPTS > "$OUT.run.log" 2>&1
run=$?
# 1: some rows failed (both gates fail them); anything else but 0: nothing to gate.
if [ "$run" -ne 0 ] && [ "$run" -ne 1 ]; then
  why=$(reason "$OUT.run.log")
  grep '^pxh: error: ' "$OUT.run.log" | sed 's/^pxh: error: //' > "$OUT.run.details"
  verdict_files "$OUT.run" "pxh run" "pxh run $DIR/$EXP" "$run" "pxh run exited $run: $why" "$OUT.run.details"
  rm -f "$OUT.run.details"
  echo "gate: pxh run exited $run: $why"
  echo "gate: bad input (exit 2): nothing to gate; see $OUT.run.log, $OUT.run.xml"
  exit 2
fi
verdict_files "$OUT.run" "pxh run" "pxh run $DIR/$EXP" 0 "" ""
echo "gate: pxh run: $(grep -v '^[[:space:]]*$' "$OUT.run.log" | tail -n 1)"

"$PXH" check "$OUT" --thresholds "$DIR/$TH" --junit "$OUT.check.xml" --json "$OUT.check.json" > "$OUT.check.txt" 2>&1
check=$?
"$PXH" compare "$DIR/$BASE" "$OUT" --fail-on "$FAIL_ON" \
  --junit "$OUT.compare.xml" --json "$OUT.compare.json" > "$OUT.compare.txt" 2>&1
compare=$?
# A gate that could not judge (exit 2) and wrote no verdict: its reason in the files all the same.
for g in check compare; do
  eval "rc=\$$g"
  if [ "$rc" -ge 2 ] && [ ! -f "$OUT.$g.xml" ]; then
    verdict_files "$OUT.$g" "pxh $g" "pxh $g" "$rc" "pxh $g exited $rc: $(reason "$OUT.$g.txt")" ""
  fi
done

verdict() { case "$1" in 0) echo pass ;; 1) echo FAIL ;; *) echo "bad input (exit $1)" ;; esac; }
# pxh check: its count line, then each failed limit (its table line, spaces squeezed) with its
# first row; the whole table is in OUT.check.txt.
if [ "$check" -ge 2 ]; then echo "gate: pxh check exited $check: $(reason "$OUT.check.txt")"
else echo "gate: pxh check: $(grep -E '^[0-9]+ passed, [0-9]+ failed$' "$OUT.check.txt" | tail -n 1)"; fi
awk -v max="$SHOWN" '
  /^[0-9]+ .* FAIL/ { n++; want = n <= max; if (want) { gsub(/  +/, "  "); print "  " $0 }; next }
  want && /^  / { print "    " substr($0, 3); want = 0; next }
  { want = 0 }
  END { if (n > max) print "  ... and " n - max " more failed limit(s)" }' "$OUT.check.txt"
# pxh compare: its verdict line, then its first regressions (the rest in OUT.compare.txt).
if [ "$compare" -ge 2 ]; then echo "gate: pxh compare exited $compare: $(reason "$OUT.compare.txt")"
else echo "gate: $(head -n 1 "$OUT.compare.txt")"; fi
sed -n '/^Regressions beyond --fail-on/,/^$/p' "$OUT.compare.txt" | sed '1d;/^$/d' | head -n "$SHOWN"
echo "gate: all of it in $OUT.check.txt and $OUT.compare.txt; JUnit and JSON in $OUT.run.xml, $OUT.check.xml, $OUT.compare.xml (and .json)"
echo "gate: pxh check $(verdict $check), pxh compare $(verdict $compare)"
if [ "$check" -ge 2 ] || [ "$compare" -ge 2 ]; then exit 2; fi
if [ "$check" -ne 0 ] || [ "$compare" -ne 0 ]; then exit 1; fi
exit 0
