#!/usr/bin/env bash
# Runs test binaries, prints one line per program and a summary; exits
# non-zero if any failed. Usage: run-tests.sh unit|integration BIN tests...
# TEST_RUNNER, if set, is put before each test (an emulator for a cross build).
set -u
kind=$1; bin=$2; shift 2
export TANDEM_BIN=$bin
# the sanitizer build's leak check ignores what tools/lsan.supp names (a
# library's own leaks, each with its reason); other builds do not read it
here=$(cd "$(dirname "$0")" && pwd)
export LSAN_OPTIONS="suppressions=$here/lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
pass=0; fail=0; failed=()
for t in "$@"; do
    log=$(mktemp)
    start=$(date +%s%N)
    # TEST_RUNNER unquoted on purpose: a command and its options
    if ${TEST_RUNNER:-} "$t" >"$log" 2>&1; then
        pass=$((pass + 1)); status=ok
    else
        fail=$((fail + 1)); status=FAIL; failed+=("$t")
        cat "$log"
    fi
    ms=$(( ($(date +%s%N) - start) / 1000000 ))
    printf '  %-4s %-40s %4d.%03ds\n' "$status" "$(basename "$t")" $((ms / 1000)) $((ms % 1000))
    rm -f "$log"
done
echo "$kind tests ($bin): $pass passed, $fail failed"
[ $fail -eq 0 ]
