#!/usr/bin/env bash
# ctest ctest_summary_self_test: scripts/ctest-summary.py on a JUnit file of every status ctest writes (issue 42): a
# run, a suite that skipped a case inside it, a skip (SKIP_RETURN_CODE), a release-only entry (registered disabled under
# the sanitizers, tests/CMakeLists.txt) and a failure. The skip must be counted as skipped (CI fails on it), the
# release-only one named apart and not counted as skipped.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cat >"$work/junit.xml" <<'XML'
<?xml version="1.0" encoding="UTF-8"?>
<testsuite name="t" tests="5">
 <testcase name="ran" time="1" status="run"><system-out>OK</system-out></testcase>
 <testcase name="inside" time="1" status="run"><system-out>SKIPPED: chromium not found</system-out></testcase>
 <testcase name="skipped_one" time="0" status="notrun"><system-out>Skipped</system-out></testcase>
 <testcase name="release_one" time="0" status="disabled"><system-out>Disabled</system-out></testcase>
 <testcase name="failed_one" time="2" status="fail"><system-out>boom</system-out></testcase>
</testsuite>
XML
got=$(/usr/bin/python3 "$root/scripts/ctest-summary.py" debug "$work/junit.xml")
want="debug: 3 run (2 passed, 1 failed), 1 skipped: skipped_one; 1 skipped inside a suite: inside (chromium not found); 1 release-only, run by the release build: release_one"
if [ "$got" != "$want" ]; then
  printf 'ctest_summary_self_test: FAILED\n got:  %s\n want: %s\n' "$got" "$want" >&2
  exit 1
fi
# Without the skip, the line says "0 skipped" (what scripts/test.sh looks for under CI=true), with the release-only one.
sed -i '/skipped_one/d' "$work/junit.xml"
got=$(/usr/bin/python3 "$root/scripts/ctest-summary.py" debug "$work/junit.xml")
case "$got" in
  *", 0 skipped;"*release_one*) ;;
  *) printf 'ctest_summary_self_test: FAILED: %s\n' "$got" >&2; exit 1 ;;
esac
echo "ctest_summary_self_test: ok"
