#!/usr/bin/env bash
# --help and docs/TOOLS.md kept in step: every option a tool's --help lists is documented in that tool's section of
# docs/TOOLS.md. The commands are read from `rockwatch --help` (so a new command is checked without editing this), each
# `rockwatch COMMAND --help` (and a command's own subcommands, e.g. `study merge --help`) against the section
# "## `rockwatch COMMAND`", `rockwatch-monitor --help` against "## `rockwatch-monitor`". An option counts as documented
# when its name appears in the section as a whole word (`--b` is not found in `--b-max`). Fails naming every option
# (and section) that is missing.
#   help_in_tools_md.sh ROCKWATCH ROCKWATCH_MONITOR TOOLS_MD
#   help_in_tools_md.sh --self-test ROCKWATCH ROCKWATCH_MONITOR TOOLS_MD
#     runs the check on copies of TOOLS.md with one option's name taken out of a section, and with a section
#     missing: it must fail and name them (so the check can fail), and pass on the file as it is.
set -uo pipefail

# The options named at the start of the option lines of a CLI11 help (two spaces, then "-x,--name TYPE ..."):
# continuation lines of a description are indented further and are not read.
help_options() {
  awk '/^  -/ {
         first = $1
         n = split(first, names, ",")
         for (i = 1; i <= n; ++i) if (names[i] ~ /^--[a-z0-9][a-z0-9-]*$/) print names[i]
       }' | grep -v -x -e '--help' -e '--version' | sort -u
}

# Independent of help_options: how many distinct option lines a help has (their first word), --help/--version aside.
option_lines() {
  grep -E '^  -' | awk '{ print $1 }' | grep -v -E '^(-[a-zA-Z],)?--(help|version)$' | sort -u | wc -l
}

# The subcommands of a command (e.g. `study merge`): the words W its help names as "rockwatch COMMAND W" whose own
# help says "Usage: rockwatch COMMAND W".
subcommands() {  # subcommands ROCKWATCH COMMAND
  local w
  for w in $("$1" "$2" --help 2>/dev/null | grep -o -E "rockwatch $2 [a-z][a-z-]*" | awk '{ print $3 }' | sort -u); do
    if grep -q -F "Usage: rockwatch $2 $w" <<<"$("$1" "$2" "$w" --help 2>/dev/null)"; then echo "$w"; fi
  done
}

# Text of the section "## HEADING" up to the next "## " heading.
section() {  # section TOOLS_MD HEADING
  awk -v heading="$2" '$0 == "## " heading { on = 1; next } on && /^## / { exit } on { print }' "$1"
}

check() {  # check ROCKWATCH MONITOR TOOLS_MD; prints FAIL lines, returns 1 when any
  local rockwatch=$1 monitor=$2 tools_md=$3 failures=0 checked=0
  local commands
  commands=$("$rockwatch" --help | awk '/^Commands:/ { on = 1; next } on && /^  [a-z]/ { print $1; next } { on = 0 }')
  if [ -z "$commands" ]; then
    echo "FAIL: no commands found in \`$rockwatch --help\`"
    return 1
  fi
  # tool|heading|command line of its help
  local entries=()
  local c s
  for c in $commands; do
    entries+=("rockwatch $c|\`rockwatch $c\`|$c")
    for s in $(subcommands "$rockwatch" "$c"); do
      entries+=("rockwatch $c $s|\`rockwatch $c\`|$c $s")
    done
  done
  entries+=("rockwatch-monitor|\`rockwatch-monitor\`|")
  local entry tool heading args text help opt status
  for entry in "${entries[@]}"; do
    IFS='|' read -r tool heading args <<<"$entry"
    text=$(section "$tools_md" "$heading")
    if [ -z "$text" ]; then
      echo "FAIL: docs/TOOLS.md has no section \"## $heading\" (for \`$tool\`)"
      failures=$((failures + 1))
      continue
    fi
    if [ "$tool" = rockwatch-monitor ]; then
      help=$("$monitor" --help 2>&1); status=$?
    else
      # shellcheck disable=SC2086  # the command and its subcommand are separate words
      help=$("$rockwatch" $args --help 2>&1); status=$?
    fi
    if [ "$status" -ne 0 ]; then
      echo "FAIL: \`$tool --help\` exited with $status"
      failures=$((failures + 1))
      continue
    fi
    local options
    options=$(printf '%s\n' "$help" | help_options)
    if [ -z "$options" ]; then
      echo "FAIL: \`$tool --help\` lists no options (its format changed?)"
      failures=$((failures + 1))
      continue
    fi
    # An option is documented when it stands in the section as a whole word of [A-Za-z0-9_-] (not a part of a longer
    # name): one of the section's maximal runs of those characters. One pass over the section, not a grep per option
    # (the self-test runs this check three times: a process per option took it to a quarter of its timeout).
    checked=$((checked + $(wc -l <<<"$options")))
    for opt in $(comm -23 <(printf '%s\n' "$options" | LC_ALL=C sort -u) \
                          <(grep -o -E -e '[A-Za-z0-9_-]+' <<<"$text" | LC_ALL=C sort -u)); do
      echo "FAIL: \`$tool --help\` lists $opt, but docs/TOOLS.md's section \"## $heading\" does not document it"
      failures=$((failures + 1))
    done
  done
  if [ "$failures" -gt 0 ]; then
    echo "$failures missing; $checked options checked"
    return 1
  fi
  echo "OK: $checked options of ${#entries[@]} help texts documented in docs/TOOLS.md"
  return 0
}

self_test() {  # self_test ROCKWATCH MONITOR TOOLS_MD
  local rockwatch=$1 monitor=$2 tools_md=$3 out
  work=$(mktemp -d)
  trap 'rm -rf "$work"' EXIT
  out=$(check "$rockwatch" "$monitor" "$tools_md") || { echo "FAIL: the check fails on TOOLS.md as it is:"; echo "$out"; return 1; }
  # 0. The parser against an independent count (issue 42): in every help text, the distinct first words of the option
  #    lines (a line starting "  -"), less --help/--version, must be as many as the options help_options finds, so
  #    an option the parser cannot read (a name outside its pattern, a line format it misses) fails here. Shown on a
  #    help with such an option added.
  local c h counted listed total=0
  for c in $("$rockwatch" --help | awk '/^Commands:/ { on = 1; next } on && /^  [a-z]/ { print $1; next } { on = 0 }') \
           rockwatch-monitor; do
    if [ "$c" = rockwatch-monitor ]; then h=$("$monitor" --help 2>&1); else h=$("$rockwatch" "$c" --help 2>&1); fi
    counted=$(option_lines <<<"$h")
    listed=$(help_options <<<"$h" | wc -l)
    [ "$counted" -eq "$listed" ] && [ "$counted" -gt 0 ] ||
      { echo "FAIL (self-test): $c --help has $counted option lines, the parser reads $listed options"; return 1; }
    total=$((total + counted))
  done
  h=$(printf '%s\n' "$("$rockwatch" simulate --help)" "  --Not_Read_By-The-Parser X    an option outside its pattern")
  [ "$(option_lines <<<"$h")" -ne "$(help_options <<<"$h" | wc -l)" ] ||
    { echo "FAIL (self-test): the independent count does not see an option the parser misses"; return 1; }
  # 1. An option of `simulate` (the longest name its help lists: no other contains it) taken out of its section:
  #    the check must name it, and nothing else.
  local opt
  opt=$("$rockwatch" simulate --help | help_options | awk '{ print length($0), $0 }' | sort -k1,1nr -k2 | head -1 |
        awk '{ print $2 }')
  [ -n "$opt" ] || { echo "FAIL: no option found in simulate --help"; return 1; }
  awk -v heading='`rockwatch simulate`' -v opt="$opt" '
    $0 == "## " heading { on = 1; print; next }
    on && /^## / { on = 0 }
    on { gsub(opt, "--removed-by-the-self-test") }
    { print }' "$tools_md" >"$work/no_option.md"
  if out=$(check "$rockwatch" "$monitor" "$work/no_option.md"); then
    echo "FAIL (self-test): $opt removed from simulate's section, but the check passed"; return 1
  fi
  grep -q -F -- "lists $opt," <<<"$out" && grep -q -x -F -e "1 missing" <<<"$(sed -n 's/;.*//p' <<<"$out")" ||
    { echo "FAIL (self-test): the failure does not name $opt alone:"; echo "$out"; return 1; }
  # 2. The monitor's section missing: the check must say so.
  awk '$0 == "## `rockwatch-monitor`" { skip = 1; next } skip && /^## / { skip = 0 } !skip { print }' \
    "$tools_md" >"$work/no_section.md"
  if out=$(check "$rockwatch" "$monitor" "$work/no_section.md"); then
    echo "FAIL (self-test): the monitor's section removed, but the check passed"; return 1
  fi
  grep -q -F -- 'no section "## `rockwatch-monitor`"' <<<"$out" ||
    { echo "FAIL (self-test): the failure does not name the missing section:"; echo "$out"; return 1; }
  echo "OK (self-test): the parser reads all $total option lines of the help texts; the check names an undocumented" \
       "option ($opt) and a missing section, and passes on TOOLS.md"
}

if [ "${1-}" = --self-test ]; then
  shift
  [ $# -eq 3 ] || { echo "usage: $0 --self-test ROCKWATCH ROCKWATCH_MONITOR TOOLS_MD" >&2; exit 2; }
  self_test "$@"
  exit $?
fi
[ $# -eq 3 ] || { echo "usage: $0 ROCKWATCH ROCKWATCH_MONITOR TOOLS_MD" >&2; exit 2; }
check "$@"
