#!/usr/bin/env bash
# The project's dependency rules, checked on the #include lines of every source file (docs/ARCHITECTURE.md, "Rules").
#
#   tests/tools/dependency_rules.sh [ROOT]          check the tree at ROOT (default: this repository); exit 1 on a breach
#   tests/tools/dependency_rules.sh --self-test     the checker must reject a tree with one breach of each rule
#
# A rule is "files under FOLDER may include, of the project's own headers, only these prefixes". The project's
# headers are those included with quotes; system headers (<...>) are checked separately where a layer forbids a
# library (liblcm outside the host programs, CLI11 / JSON in core and firmware).
set -euo pipefail

check_tree() {
  local root=$1 failures=0

  # breach FILE LINE TEXT RULE
  breach() { echo "dependency rule broken: $1:$2: $3  ($4)" >&2; failures=$((failures + 1)); }

  # rule NAME FOLDER ALLOWED_QUOTED_REGEX [FORBIDDEN_SYSTEM_REGEX]
  # Every quoted include in FOLDER must match ALLOWED (an extended regex on the included path); no <...> include may
  # match FORBIDDEN.
  rule() {
    local name=$1 folder=$2 allowed=$3 forbidden=${4:-}
    [ -d "$root/$folder" ] || { echo "dependency rules: folder $folder missing (the layout changed: update the rules)" >&2; failures=$((failures + 1)); return; }
    while IFS= read -r hit; do
      local file=${hit%%:*} rest=${hit#*:}
      local line=${rest%%:*} text=${rest#*:}
      local inc
      if [[ $text =~ ^[[:space:]]*#[[:space:]]*include[[:space:]]*\"([^\"]+)\" ]]; then
        inc=${BASH_REMATCH[1]}
        # A file's own folder (same directory, by bare name) is always allowed.
        if [[ $inc != */* ]] && [ -e "$(dirname "$file")/$inc" ]; then continue; fi
        # A relative include ("../x/y.hpp") of an existing file inside the same rule's folder stays in its layer.
        if [[ $inc == ../* ]] && [ -e "$(dirname "$file")/$inc" ]; then
          local resolved
          resolved=$(realpath -m "$(dirname "$file")/$inc")
          if [[ $resolved == "$(realpath -m "$root/$folder")"/* ]]; then continue; fi
        fi
        if ! [[ $inc =~ $allowed ]]; then breach "${file#"$root"/}" "$line" "$text" "$name"; fi
      elif [[ -n $forbidden && $text =~ ^[[:space:]]*#[[:space:]]*include[[:space:]]*\<([^\>]+)\> ]]; then
        inc=${BASH_REMATCH[1]}
        if [[ $inc =~ $forbidden ]]; then breach "${file#"$root"/}" "$line" "$text" "$name"; fi
      fi
    done < <(grep -rn --include='*.hpp' --include='*.cpp' --include='*.h' -E '^[[:space:]]*#[[:space:]]*include' "$root/$folder" || true)
  }

  local lcm_types='rockwatch/[a-z_]+_t\.hpp$'
  rule "core uses Eigen only"              core                 '^rockwatch/core/' '^(lcm/|CLI/|nlohmann/)'
  rule "firmware uses core and the LCM types only" firmware   "^rockwatch/(core|firmware)/|$lcm_types" '^(lcm/lcm|CLI/|nlohmann/)'
  rule "sim uses core only"                sim                  '^rockwatch/(core|sim)/' '^(lcm/|CLI/)'
  rule "the record readers use nothing of ours" host_tools/records '^rockwatch/records/' '^(lcm/|CLI/)'
  rule "options use core, sim and the records' text scanning" host_tools/options '^rockwatch/(core|sim|options|records)/'
  rule "process spawning uses nothing of ours" host_tools/process '^rockwatch/process/'
  rule "the monitor program never includes the rockwatch tool" host_tools/monitor \
       "^rockwatch/(core|firmware|sim|options|process)/|^monitor/|$lcm_types"

  # The rockwatch tool: a command includes common/ and its own folder, never another command's folder.
  local cli=host_tools/rockwatch
  if [ -d "$root/$cli" ]; then
    local libs="^rockwatch/(core|sim|records|options|process|firmware)/|$lcm_types"
    rule "rockwatch: common code includes no command" "$cli/common" "$libs|^common/"
    local dir cmd
    for dir in "$root/$cli"/*/; do
      cmd=$(basename "$dir")
      [ "$cmd" = common ] && continue
      rule "rockwatch: command $cmd includes only common/ and $cmd/" "$cli/$cmd" "$libs|^common/|^$cmd/"
    done
  else
    echo "dependency rules: folder $cli missing" >&2; failures=$((failures + 1))
  fi

  if [ "$failures" -ne 0 ]; then
    echo "dependency rules: $failures breach(es) in $root" >&2
    return 1
  fi
  echo "dependency rules: all rules hold in $root"
}

self_test() {
  local tmp
  tmp=$(mktemp -d)
  trap 'rm -rf "$tmp"' RETURN
  local folders=(core/include/rockwatch/core firmware/src sim/src host_tools/records/src host_tools/options
                 host_tools/process host_tools/monitor host_tools/rockwatch/common host_tools/rockwatch/study
                 host_tools/rockwatch/generate)
  local f
  for f in "${folders[@]}"; do mkdir -p "$tmp/$f"; echo '#include <cstdint>' > "$tmp/$f/ok.hpp"; done
  check_tree "$tmp" >/dev/null || { echo "self-test: a clean tree was rejected" >&2; return 1; }
  # One breach per rule; each must be caught on its own.
  local breaches=(
    'core/include/rockwatch/core/bad.hpp|#include "rockwatch/sim/analysis.hpp"'
    'core/include/rockwatch/core/bad.hpp|#include <lcm/lcm-cpp.hpp>'
    'firmware/src/bad.cpp|#include "rockwatch/sim/double_wall_engine.hpp"'
    'firmware/src/bad.cpp|#include <lcm/lcm.h>'
    'sim/src/bad.cpp|#include "rockwatch/firmware/wall_engine.hpp"'
    'host_tools/records/src/bad.cpp|#include "rockwatch/core/wall.hpp"'
    'host_tools/monitor/bad.cpp|#include "common/process/text_report.hpp"'
    'host_tools/rockwatch/study/bad.cpp|#include "generate/generate_request.hpp"'
    'host_tools/rockwatch/common/bad.cpp|#include "study/plan/study_plan.hpp"'
  )
  local b file text
  for b in "${breaches[@]}"; do
    file=${b%%|*}; text=${b#*|}
    echo "$text" > "$tmp/$file"
    if check_tree "$tmp" >/dev/null 2>&1; then
      echo "self-test: breach not caught: $file: $text" >&2; return 1
    fi
    rm "$tmp/$file"
  done
  echo "dependency rules self-test: ${#breaches[@]} breaches caught, the clean tree accepted"
}

if [ "${1:-}" = --self-test ]; then
  self_test
else
  check_tree "$(cd "${1:-$(dirname "$0")/../..}" && pwd)"
fi
