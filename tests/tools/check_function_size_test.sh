#!/usr/bin/env bash
# The function-size check fails where it should: a new long function, a listed one grown, a listed one gone
# short; and passes on a listed one at its length. A throwaway tree with a generated 130-line function.
# Usage: check_function_size_test.sh PYTHON CHECKER
set -euo pipefail
python=$1
checker=$2
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
mkdir -p "$dir/src/static_core" "$dir/src/tests/tools" "$dir/build"
{
  echo "int long_function(int x) {"
  for i in $(seq 1 128); do echo "  x += $i;"; done
  echo "  return x;"
  echo "}"
  echo "int short_function(int x) { return x + 1; }"
} >"$dir/src/static_core/long.cpp"
printf '[{"directory": "%s", "command": "c++ -std=c++20 -c %s", "file": "%s"}]\n' "$dir/build" \
  "$dir/src/static_core/long.cpp" "$dir/src/static_core/long.cpp" >"$dir/build/compile_commands.json"
exceptions="$dir/src/tests/tools/function_size_exceptions.txt"
expect() {  # expect STATUS WHAT: the checker's exit status on the exceptions file as it is now
  local status=0
  "$python" "$checker" "$dir/src" "$dir/build" "$dir/src/static_core/long.cpp" >"$dir/out" 2>&1 || status=$?
  if [ "$status" != "$1" ]; then
    echo "check_function_size_test: $2: exit $status, expected $1" >&2
    cat "$dir/out" >&2
    exit 1
  fi
}
: >"$exceptions"
expect 1 "a long function not listed"
grep -q "long_function() is 130 lines" "$dir/out" || { echo "check_function_size_test: no length reported" >&2; cat "$dir/out" >&2; exit 1; }
echo "static_core/long.cpp long_function 130" >"$exceptions"
expect 0 "a listed function at its length"
echo "static_core/long.cpp long_function 125" >"$exceptions"
expect 1 "a listed function that grew"
printf 'static_core/long.cpp long_function 130\nstatic_core/long.cpp short_function 130\n' >"$exceptions"
expect 1 "a listed function no longer long"
printf 'static_core/long.cpp long_function 130\nstatic_core/gone.cpp gone 130\n' >"$exceptions"
expect 1 "a listed file that is gone"
echo "check_function_size_test: ok"
