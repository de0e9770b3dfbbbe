#!/usr/bin/env bash
# tests/mutation/run.sh --check-baseline BUILD: a build tree's ctest run serves --baseline-from only when
# it passed and ran after the last change to a tracked file other than the docs. Three cost files
# written here, each against the repository's own tracked files (their times only: nothing in the
# source tree is touched): one newer than all of them (exit 0), one older than all of them (exit 1,
# naming a changed file), one whose run had a failure (exit 1, naming the test).
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
run="$root/tests/mutation/run.sh"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "check_baseline_test: $*" >&2; exit 1; }

write_costs() { # BUILD [FAILED-TEST]
    mkdir -p "$1/Testing/Temporary"
    { echo "haptics_finger_test 1 4.4"; echo "---"; [ -z "${2:-}" ] || echo "$2"; } \
        > "$1/Testing/Temporary/CTestCostData.txt"
}
times=$(cd "$root" && git ls-files -z -- . ':(exclude)docs' ':(exclude)*.md' | xargs -0 stat -c %Y | sort -n)
newest=$(tail -1 <<< "$times")
oldest=$(head -1 <<< "$times")

write_costs "$work/fresh"
touch -d "@$((newest + 60))" "$work/fresh/Testing/Temporary/CTestCostData.txt"
"$run" --check-baseline "$work/fresh" 2> "$work/fresh.err" ||
    fail "a passed run newer than every tracked file does not serve: $(cat "$work/fresh.err")"

write_costs "$work/old"
touch -d "@$((oldest - 1))" "$work/old/Testing/Temporary/CTestCostData.txt"
if "$run" --check-baseline "$work/old" 2> "$work/old.err"; then
    fail "a run older than every tracked file serves"
fi
grep -q "changed after" "$work/old.err" || fail "a stale run's message names no changed file: $(cat "$work/old.err")"

write_costs "$work/failed" haptics_finger_test
touch -d "@$((newest + 60))" "$work/failed/Testing/Temporary/CTestCostData.txt"
if "$run" --check-baseline "$work/failed" 2> "$work/failed.err"; then
    fail "a run with a failed test serves"
fi
grep -q "haptics_finger_test" "$work/failed.err" || fail "a failed run's message names no test: $(cat "$work/failed.err")"
echo "check_baseline_test: fresh, stale and failed runs told apart"
