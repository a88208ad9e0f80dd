#!/usr/bin/env bash
# The main job. Until the LCM monitor lands (issue 7), it runs the verified engine on a real record:
# the paper's wall under El Centro 1940 (180 component) scaled to PGA 0.25 g, and prints the result.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/build.sh release
record=tests/data/records/RSN6_IMPVALL.I_I-ELC180-hor1.AT2
echo
echo "== rockwatch simulate --record $record --scale-pga 0.25"
build/release/host_tools/rockwatch simulate --record "$record" --scale-pga 0.25
echo
echo "== the same as JSON"
build/release/host_tools/rockwatch simulate --record "$record" --scale-pga 0.25 --json
