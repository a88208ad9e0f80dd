#!/usr/bin/env bash
# Undefined-symbol audit of object files and static libraries: lists every undefined symbol of each object and
# fails (exit 1) when any is a heap, exception or stdio function:
#   heap        malloc calloc realloc free aligned_alloc posix_memalign memalign valloc pvalloc (and newlib's
#               reentrant _malloc_r … forms); operator new/delete in any form (_Znw* _Zna* _Zdl* _Zda*)
#   exceptions  __cxa_throw __cxa_allocate_exception __cxa_begin_catch __cxa_end_catch __cxa_rethrow
#               _Unwind_Resume; libstdc++'s std::__throw_* helpers
#   stdio       printf puts fopen fwrite … (the printf/scanf families incl. _chk and newlib's i* forms, put/get
#               char/string functions, FILE handling, perror, stdin/stdout/stderr)
#
#   tests/tools/symbol_audit.sh [--nm NM] FILE...     (NM default: nm; use arm-none-eabi-nm for ARM objects)
# Exit status: 0 clean, 1 forbidden symbols found, 2 usage or nm failure.
set -euo pipefail

nm_tool="nm"
if [[ ${1:-} == --nm ]]; then
  nm_tool=$2
  shift 2
fi
if [[ $# -eq 0 ]]; then
  sed -n '2,12p' "$0" | sed 's/^# \{0,1\}//' >&2
  exit 2
fi
command -v "$nm_tool" >/dev/null || { echo "symbol_audit: $nm_tool not found" >&2; exit 2; }
demangle="cat"
command -v c++filt >/dev/null && demangle=c++filt

heap='_?_?(malloc|calloc|realloc|free|aligned_alloc|posix_memalign|memalign|valloc|pvalloc|reallocarray)(_r)?|'
heap+='_Zn[wa].*|_Zd[la].*'
exceptions='__cxa_(throw|allocate_exception|begin_catch|end_catch|rethrow|free_exception)|_Unwind_Resume|'
exceptions+='_ZSt[0-9]+__throw_.*'
stdio_names='v?(f|s|sn|as|d)?i?printf|v?(f|s)?i?scanf|_?_?(v?(f|s|sn)?printf|v?(f|s)?scanf)_chk|_[a-z_]*printf_r|'
stdio_names+='puts|fputs|putchar|fputc|putc|getchar|fgetc|getc|fgets|gets|ungetc|'
stdio_names+='fopen|fopen64|freopen|fdopen|fclose|fflush|fwrite|fread|fseek|ftell|rewind|setvbuf|setbuf|perror|'
stdio_names+='_IO_.*|stdin|stdout|stderr'
forbidden="^(${heap}|${exceptions}|${stdio_names})\$"

status=0
for file in "$@"; do
  [[ -f $file ]] || { echo "symbol_audit: $file not found" >&2; exit 2; }
  # "nm -u" prints "file:" (or "obj:" inside archives) headers, then "U name" lines.
  if ! listing=$("$nm_tool" -u "$file" 2>&1); then
    echo "symbol_audit: $nm_tool -u $file failed: $listing" >&2
    exit 2
  fi
  echo "== $file ($nm_tool -u)"
  current=$file
  bad_in_file=0
  while IFS= read -r line; do
    [[ -z $line ]] && continue
    if [[ $line == *: ]]; then
      current=${line%:}
      echo "  [$current]"
      continue
    fi
    sym=$(awk '{ print $NF }' <<<"$line")
    pretty=$(echo "$sym" | $demangle)
    if [[ $sym =~ $forbidden ]]; then
      echo "    FORBIDDEN  $sym  ($pretty)"
      bad_in_file=1
    else
      if [[ $pretty != "$sym" ]]; then echo "    $sym  ($pretty)"; else echo "    $sym"; fi
    fi
  done <<<"$listing"
  if [[ $bad_in_file -eq 1 ]]; then
    echo "symbol_audit: FAIL: $file references heap, exception or stdio functions" >&2
    status=1
  fi
done
[[ $status -eq 0 ]] && echo "symbol_audit: ok: no heap, exception or stdio references"
exit $status
