#!/usr/bin/env bash
# A program given bad input must exit with the expected code and print exactly one line on stderr that matches a
# pattern (naming the option or file), nothing that merely fails. Usage: one_line_error.sh CODE REGEX -- COMMAND...
set -uo pipefail
code="$1"; pattern="$2"; shift 3
err="$(mktemp)"
trap 'rm -f "$err"' EXIT
"$@" >/dev/null 2>"$err"
got=$?
lines=$(grep -c '' "$err")
if [ "$got" -ne "$code" ] || [ "$lines" -ne 1 ] || ! grep -Eq -e "$pattern" "$err"; then
  echo "expected exit $code and one line matching /$pattern/ on stderr; got exit $got and $lines line(s):"
  cat "$err"
  exit 1
fi
echo "ok: exit $got, $(cat "$err")"
