#!/usr/bin/env bash
# A man page (gzip'd roff) from a program's --help: help2man when installed (scripts/install-deps.sh), else a plain
# page with the --help text verbatim.
#   packaging/manpage.sh PROGRAM VERSION OUT.1.gz
set -euo pipefail
if [ $# -ne 3 ]; then echo "manpage.sh: usage: manpage.sh PROGRAM VERSION OUT.1.gz" >&2; exit 2; fi
prog="$1" version="$2" out="$3"
name="$(basename "$prog")"
[ -x "$prog" ] || { echo "manpage.sh: $prog is not an executable" >&2; exit 2; }
mkdir -p "$(dirname "$out")"
# The whole --help first: `--help | head -n 1` under pipefail fails when head closes the pipe before a long help is
# written (SIGPIPE: the build failed on a fresh clone).
help_text="$("$prog" --help)"
first_line="${help_text%%$'\n'*}"
summary="$(sed -e "s/^$name [0-9.]*: //" -e 's/[.:]$//' <<<"$first_line" | cut -c1-120)"
tmp="$(mktemp)"
trap 'rm -f "$tmp"' EXIT
if command -v help2man >/dev/null 2>&1; then
  help2man --no-info --no-discard-stderr --version-string="$version" --name="$summary" \
    --source="rockwatch $version" --section=1 --output="$tmp" "$prog"
else
  {
    echo ".TH \"$(echo "$name" | tr a-z A-Z)\" 1 \"\" \"rockwatch $version\" \"User Commands\""
    echo ".SH NAME"
    echo "$name \\- $summary"
    echo ".SH DESCRIPTION"
    echo ".nf"
    sed -e 's/\\/\\e/g' -e 's/^\./\\\&./' -e "s/^'/\\\\\&'/" <<<"$help_text"
    echo ".fi"
  } >"$tmp"
fi
gzip -9n <"$tmp" >"$out"
