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
tmp="$(mktemp)"
wrap_dir=""
trap 'rm -f "$tmp"; [ -z "$wrap_dir" ] || rm -rf "$wrap_dir"' EXIT
# A cross-built program (ROCKWATCH_MANPAGE_EMULATOR, e.g. qemu-aarch64: packaging/CMakeLists.txt) runs through a
# wrapper of the same name, so help2man and the page name it as itself.
if [ -n "${ROCKWATCH_MANPAGE_EMULATOR:-}" ]; then
  wrap_dir="$(mktemp -d)"
  printf '#!/bin/sh\nexec %s %q "$@"\n' "$ROCKWATCH_MANPAGE_EMULATOR" "$(cd "$(dirname "$prog")" && pwd)/$name" \
    >"$wrap_dir/$name"
  chmod +x "$wrap_dir/$name"
  prog="$wrap_dir/$name"
fi
# The whole --help first: `--help | head -n 1` under pipefail fails when head closes the pipe before a long help is
# written (SIGPIPE: the build failed on a fresh clone).
help_text="$("$prog" --help)"
first_line="${help_text%%$'\n'*}"
summary="$(sed -e "s/^$name [0-9.]*: //" -e 's/[.:]$//' <<<"$first_line" | cut -c1-120)"
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
