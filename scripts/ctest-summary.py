#!/usr/bin/env python3
"""ctest-summary.py LABEL JUNIT_XML...: one line of what a preset's ctest runs ran and skipped (scripts/test.sh, issue 42).

Reads the JUnit files of `ctest --output-junit` (several when a preset's tests ran in more than one ctest call): a test is run (status "run" or "fail"), release-only
("disabled": tests/CMakeLists.txt's rockwatch_release_only, registered DISABLED under the sanitizers because the
release build runs them; named, not counted as skipped) or skipped ("notrun": ctest's SKIP_RETURN_CODE, or not run
at all). A test that ran but printed "SKIPPED: <what>" (a test case of a suite skipped
inside it, tests/support/ci_skip.hpp) is named too. Prints e.g.
  release: 212 run (210 passed, 2 failed), 1 skipped: test_python_module; skipped inside: PythonPlot.X
  debug: 40 run (40 passed, 0 failed), 0 skipped; 7 release-only, run by the release build: embedded_build, ...
"""
import sys
import xml.etree.ElementTree as ET

label, paths = sys.argv[1], sys.argv[2:]
cases = []
for path in paths:
    try:
        cases += list(ET.parse(path).getroot().iter("testcase"))
    except (OSError, ET.ParseError) as e:
        print(f"{label}: no ctest results ({e})")
        sys.exit(0)
run, failed, skipped, inside, release_only = 0, [], [], [], []
for c in cases:
    name, status = c.get("name"), c.get("status")
    if status in ("run", "fail"):
        run += 1
        if status == "fail":
            failed.append(name)
        out = c.findtext("system-out") or ""
        inside += [f"{name} ({line.strip()[len('SKIPPED: '):][:80]})" for line in out.splitlines()
                   if line.strip().startswith("SKIPPED: ")]
    elif status == "disabled":
        release_only.append(name)
    else:
        skipped.append(name)
line = f"{label}: {run} run ({run - len(failed)} passed, {len(failed)} failed), {len(skipped)} skipped"
if skipped:
    line += ": " + ", ".join(skipped)
if inside:
    line += f"; {len(inside)} skipped inside a suite: " + "; ".join(inside)
if release_only:
    line += f"; {len(release_only)} release-only, run by the release build: " + ", ".join(sorted(release_only))
print(line)
