#!/usr/bin/env bash
# The mutation check: breaks the product's safety- and feel-critical code one behaviour at a time and
# runs the tests that should notice. A mutant the tests do not notice "survives": a behaviour nothing
# guards. Exit 0 when every mutant is killed; 1 when one survives, a mutant is stale (its text is no
# longer in its file), does not compile, or the tests fail before any mutation; 2 for bad usage.
#
# Usage: tests/mutation/run.sh [--only NAME]... [--list] [--keep-going]
#   --only NAME    run only the named mutant(s)
#   --list         print the mutants and what each breaks, run nothing
#
# Mutants are listed in tests/mutation/mutants/*.txt, one block each:
#   [name]
#   file = path/from/the/repository/root
#   find = exact text, one line, found exactly once in that file
#   replace = what it becomes
#   tests = ctest names, each optionally with a gtest filter: haptics_scenario_test[*Cut*]
#   build = build targets (optional; default: the test names)
#   breaks = what a viewer would feel, one line
#
# How: the working tree (tracked and untracked files git does not ignore) is copied to a scratch
# tree, build/mutation/tree beside the source's own build trees, configured with the host preset and
# the same options as build/host. With ccache installed (toolchain/install-deps.sh) every copy of the
# tree shares its objects (toolchain/modules/DtCcache.cmake), so after the README's build the scratch
# tree compiles only what a mutant changes. Each mutant is applied to the scratch copy, the targets its
# tests need are rebuilt, its tests run (ctest, GTEST_FILTER for a filter), and the file is restored.
# The tests first run once unmutated: they must pass, or a kill means nothing.
set -uo pipefail

root=$(cd "$(dirname "$0")/../.." && pwd)
list_dir="$root/tests/mutation/mutants"
scratch="${DT_MUTATION_DIR:-$root/build/mutation}/tree"
build="$scratch/build/host"
only=()
list_only=0

die() { echo "mutation: $*" >&2; exit 2; }
while [ $# -gt 0 ]; do
    case "$1" in
        --only) [ $# -ge 2 ] || die "--only needs a mutant name"; only+=("$2"); shift 2 ;;
        --list) list_only=1; shift ;;
        -h|--help) sed -n '2,10p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
        *) die "unknown option '$1' (see --help)" ;;
    esac
done

# ---- read the mutant lists ------------------------------------------------------------------------
names=(); files=(); finds=(); replaces=(); tests=(); builds=(); breaks=(); origins=()
add_mutant() {
    [ -n "$m_name" ] || return 0
    for key in file find replace tests breaks; do
        local var="m_$key"
        [ -n "${!var}" ] || die "$origin: mutant [$m_name] has no '$key ='"
    done
    for n in "${names[@]}"; do [ "$n" != "$m_name" ] || die "$origin: mutant [$m_name] is listed twice"; done
    names+=("$m_name"); files+=("$m_file"); finds+=("$m_find"); replaces+=("$m_replace")
    tests+=("$m_tests"); builds+=("$m_build"); breaks+=("$m_breaks"); origins+=("$origin")
}
shopt -s nullglob
lists=("$list_dir"/*.txt)
shopt -u nullglob
set -f   # test filters such as name[*Cut*] are words, not file patterns
[ ${#lists[@]} -gt 0 ] || die "no mutant lists in $list_dir"
for list in "${lists[@]}"; do
    m_name=""; lineno=0
    while IFS= read -r line || [ -n "$line" ]; do
        lineno=$((lineno + 1))
        origin="${list#"$root"/}:$lineno"
        case "$line" in ''|'#'*) continue ;; esac
        if [[ "$line" =~ ^\[([A-Za-z0-9_.-]+)\]$ ]]; then
            add_mutant
            m_name=${BASH_REMATCH[1]}; m_file=""; m_find=""; m_replace=""; m_tests=""; m_build=""; m_breaks=""
        elif [[ "$line" =~ ^(file|find|replace|tests|build|breaks)\ =\ ?(.*)$ ]]; then
            [ -n "$m_name" ] || die "$origin: '${BASH_REMATCH[1]} =' before any [name]"
            printf -v "m_${BASH_REMATCH[1]}" '%s' "${BASH_REMATCH[2]}"
        else
            die "$origin: cannot read '$line' (expected [name] or key = value)"
        fi
    done < "$list"
    add_mutant
done

selected=()
for i in "${!names[@]}"; do
    if [ ${#only[@]} -eq 0 ]; then selected+=("$i"); continue; fi
    for o in "${only[@]}"; do [ "$o" != "${names[$i]}" ] || selected+=("$i"); done
done
[ ${#selected[@]} -gt 0 ] || die "no mutant named ${only[*]}"

if [ "$list_only" -eq 1 ]; then
    for i in "${selected[@]}"; do
        printf '%-34s %s\n%-34s breaks: %s\n' "${names[$i]}" "${files[$i]}" "" "${breaks[$i]}"
    done
    exit 0
fi

# ---- the scratch tree -----------------------------------------------------------------------------
step() { printf '\n=== mutation: %s (%s) ===\n' "$1" "$(date -u +%H:%M:%S)"; }
mkdir -p "$scratch"
# One run at a time per scratch tree (a second run waits).
exec 9> "$scratch/../run.lock"
flock 9

step "copy the working tree to $scratch"
# Tracked and untracked-but-not-ignored files, with their times (unchanged files are not rebuilt).
(cd "$root" && git ls-files -z --cached --others --exclude-standard | xargs -0 -r ls -d 2>/dev/null |
    tar -cf - --no-recursion -T -) | tar -xf - -C "$scratch" || { echo "mutation: copy failed" >&2; exit 1; }

# Files a mutant changed in an earlier run that stopped before its rebuild: the copy above gave them
# back their original times, older than the mutant's objects, so make them newer.
if [ -f "$scratch/.mutated" ]; then
    while IFS= read -r path; do [ ! -f "$scratch/$path" ] || touch "$scratch/$path"; done < "$scratch/.mutated"
fi

cache_value() { sed -n "s/^$1:[A-Z]*=//p" "$root/build/host/CMakeCache.txt" 2>/dev/null; }
configure=(cmake --preset host -S "$scratch" -Wno-dev)
for var in DT_WERROR DT_SHARED_DATA; do
    value=$(cache_value "$var")
    [ -z "$value" ] || configure+=("-D$var=$value")
done
(cd "$scratch" && "${configure[@]}") > "$scratch/configure.log" 2>&1 ||
    { tail -20 "$scratch/configure.log"; echo "mutation: configure failed" >&2; exit 1; }
command -v ccache > /dev/null || echo "mutation: ccache is not installed: the scratch tree compiles from scratch"

# tests "a b[filter]" → the build targets (the names, or build =)
targets_of() {
    local i=$1 t
    if [ -n "${builds[$i]}" ]; then echo "${builds[$i]}"; return; fi
    for t in ${tests[$i]}; do printf '%s ' "${t%%\[*}"; done
}
# Runs one "name[filter]" test in the scratch build; returns its ctest status.
run_test() {
    local spec=$1 name=${1%%\[*} filter=""
    [ "$spec" = "$name" ] || { filter=${spec#*\[}; filter=${filter%\]}; }
    if [ -n "$filter" ]; then
        GTEST_FILTER=$filter ctest --test-dir "$build" -R "^${name}\$" --timeout 600 > "$log" 2>&1
    else
        ctest --test-dir "$build" -R "^${name}\$" --timeout 600 > "$log" 2>&1
    fi
    local rc=$?
    # a test name that matches nothing is a broken list, not a pass
    grep -q "No tests were found" "$log" && { echo "mutation: no test named $name" >&2; return 2; }
    return $rc
}

all_targets=(); all_tests=()
for i in "${selected[@]}"; do
    for t in $(targets_of "$i"); do all_targets+=("$t"); done
    for t in ${tests[$i]}; do all_tests+=("$t"); done
done
mapfile -t all_targets < <(printf '%s\n' "${all_targets[@]}" | sort -u)
mapfile -t all_tests < <(printf '%s\n' "${all_tests[@]}" | sort -u)

step "build ${#all_targets[@]} targets unmutated"
log="$scratch/last.log"
cmake --build "$build" --target "${all_targets[@]}" > "$log" 2>&1 ||
    { tail -30 "$log"; echo "mutation: the unmutated tree does not build" >&2; exit 1; }

rm -f "$scratch/.mutated"   # the build above recompiled whatever a stopped run left mutated

step "run ${#all_tests[@]} tests unmutated (they must pass)"
for t in "${all_tests[@]}"; do
    if ! run_test "$t"; then
        tail -30 "$log"; echo "mutation: $t fails before any mutation" >&2; exit 1
    fi
done

# ---- the mutants ----------------------------------------------------------------------------------
killed=0; survived=(); broken=()
for i in "${selected[@]}"; do
    n=${names[$i]}; f="$scratch/${files[$i]}"
    step "[$n] ${files[$i]}"
    if [ ! -f "$f" ]; then broken+=("$n (no file ${files[$i]})"); continue; fi
    backup="$scratch/.mutation-original"
    cp -p "$f" "$backup"
    echo "${files[$i]}" >> "$scratch/.mutated"
    # Exact text, found exactly once (perl: literal match, no regex).
    if ! FIND=${finds[$i]} REPLACE=${replaces[$i]} perl -0777 -i -pe '
            BEGIN { $f = $ENV{FIND}; $r = $ENV{REPLACE}; }
            $c = () = /\Q$f\E/g;
            if ($c != 1) { print STDERR "found $c times\n"; exit 3; }
            s/\Q$f\E/$r/;' "$f"; then
        cp -p "$backup" "$f"
        broken+=("$n (its text is not found exactly once in ${files[$i]}: stale)"); continue
    fi
    touch "$f"
    if ! cmake --build "$build" --target $(targets_of "$i") > "$log" 2>&1; then
        cp "$backup" "$f"; touch "$f"
        grep -m3 "error" "$log" >&2
        broken+=("$n (does not compile)"); continue
    fi
    by=""
    for t in ${tests[$i]}; do
        run_test "$t"; rc=$?
        if [ "$rc" -eq 2 ]; then by="?"; break; fi
        if [ "$rc" -ne 0 ]; then by=$t; break; fi
    done
    cp "$backup" "$f"; touch "$f"   # restored (newer than the mutant's objects: rebuilt next time)
    if [ "$by" = "?" ]; then
        broken+=("$n (a test it names does not exist)")
    elif [ -n "$by" ]; then
        killed=$((killed + 1)); echo "killed by $by"
    else
        survived+=("$n: ${breaks[$i]}"); echo "SURVIVED: ${breaks[$i]}"
    fi
done
rm -f "$scratch/.mutation-original"
# Leave the scratch build as the unmutated tree (the restored files compile from the cache).
if [ -f "$scratch/.mutated" ]; then
    cmake --build "$build" --target "${all_targets[@]}" > "$log" 2>&1 && rm -f "$scratch/.mutated"
fi

echo
echo "mutation: ${killed} killed, ${#survived[@]} survived, ${#broken[@]} broken (of ${#selected[@]})"
for s in "${survived[@]}"; do echo "  survived: $s"; done
for b in "${broken[@]}"; do echo "  broken:   $b"; done
[ ${#survived[@]} -eq 0 ] && [ ${#broken[@]} -eq 0 ]
