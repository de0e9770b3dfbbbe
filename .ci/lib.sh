# Sourced by .ci/run and .ci/extended: the environment both run in, the real-data folder, the step
# timer (each step's time printed as the next starts, the table of them all at exit, passed or failed)
# and the README's marked commands. Not a program of its own.
cd "$(dirname "${BASH_SOURCE[0]}")/.."
export CI=1 DT_WERROR=1   # -Werror for every build
export CTEST_PARALLEL_LEVEL=${CTEST_PARALLEL_LEVEL:-2}

# The real-data tests read ../shared/data beside the source tree. A clone made elsewhere (a temporary
# folder) has none beside it: take the one beside the repository it was cloned from, when that exists.
if [ -z "${DT_SHARED_DATA:-}" ] && [ ! -d ../shared/data ]; then
    origin=$(git remote get-url origin 2>/dev/null || true)
    origin=${origin#file://}
    if [ -n "$origin" ] && [ -d "$origin/../shared/data" ]; then
        export DT_SHARED_DATA=$(cd "$origin/../shared/data" && pwd)
    fi
fi
echo "${0#./}: shared RGB-D data: ${DT_SHARED_DATA:-$(cd .. && pwd)/shared/data}"
export DT_REQUIRE_SHARED_DATA=1   # the real-data tests fail instead of skipping when the data is missing

ci_start=$SECONDS
step_name=""
step_start=$SECONDS
step_times=()
step_done() {
    [ -n "$step_name" ] || return 0
    step_times+=("$(printf '%6d s  %s' $((SECONDS - step_start)) "$step_name")")
    step_name=""
}
step() {
    step_done
    step_name=$1
    step_start=$SECONDS
    printf '\n=== %s (%s, %d s into %s) ===\n' "$1" "$(date -u +%H:%M:%S)" $((SECONDS - ci_start)) "${0#./}"
}
step_table() {
    local rc=$?
    step_done
    printf '\n=== %s step times (exit %d, %d s in all) ===\n' "${0#./}" "$rc" $((SECONDS - ci_start))
    printf '%s\n' "${step_times[@]}"
}
trap step_table EXIT
trap 'exit 130' INT   # a stopped run's table says so (the EXIT trap then sees 130 or 143, not 0)
trap 'exit 143' TERM

# The README marks a command with <!-- NAME --> followed by a ```sh block; prints the block.
readme_command() {
    awk -v marker="<!-- $1 -->" '
        $0 == marker { found = 1; next }
        found && /^```/ { if (inblock) exit; inblock = 1; next }
        found && inblock { print }
    ' README.md
}
