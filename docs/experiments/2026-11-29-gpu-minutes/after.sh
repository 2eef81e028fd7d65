#!/usr/bin/env bash
# NEXT.md, here after a loan: the run that came back replaces runs/gpu-minutes/r, a copy named by its training minutes
# is kept and evaluated zero-shot on the validation suite. From the repository root:
#   bash docs/experiments/2026-11-29-gpu-minutes/after.sh FILES_AT      # the folder `run` put the call's files in
set -euo pipefail
files=${1:?usage: after.sh FILES_AT}
here=docs/experiments/2026-11-29-gpu-minutes
kinetix=${KINETIX:-.venv/bin/kinetix}
[ -f "$files/run.tar.gz" ] || { echo "$files/run.tar.gz: missing (the call did not finish its run)" >&2; exit 2; }
rm -rf /tmp/after-r && mkdir -p /tmp/after-r && tar -xzf "$files/run.tar.gz" -C /tmp/after-r
minutes=$(sed -n 's/^  minutes: //p' /tmp/after-r/r/config.yaml)
copy=runs/gpu-minutes/r@$minutes
rm -rf runs/gpu-minutes/r.new && mv /tmp/after-r/r runs/gpu-minutes/r.new
rm -rf runs/gpu-minutes/r && mv runs/gpu-minutes/r.new runs/gpu-minutes/r
rm -rf "$copy" && cp -r runs/gpu-minutes/r "$copy"
mkdir -p "$here/loan-$minutes" && cp "$files"/*.txt "$files"/*.log "$files"/*.json "$here/loan-$minutes/" 2>/dev/null || true
gzip -nc runs/gpu-minutes/r/metrics.jsonl >"$here/loan-$minutes/metrics.jsonl.gz"
tail -1 runs/gpu-minutes/r/metrics.jsonl | python3 -c "import json, sys; m = json.load(sys.stdin); \
print(f'{m[\"update\"]} updates, {m[\"steps\"]:,} env steps, training minutes {sys.argv[1]}')" "$minutes" \
  | tee "$here/loan-$minutes/run.txt"
$kinetix validation run "$copy" --finetune-seeds '' --json "$here/validation-$minutes.json" \
  >"$here/validation-$minutes.log" 2>&1
tail -5 "$here/validation-$minutes.log"
