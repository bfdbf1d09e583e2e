#!/usr/bin/env bash
# make fuzz: one libFuzzer target per message type (fuzz/fuzz_msg.c built
# with clang, -fsanitize=fuzzer,address,undefined), each run for
# FUZZ_SECONDS seconds from the seed corpus in fuzz/corpus/TYPE and the
# valid messages fuzz/seed_gen.c writes from the current types (both copied
# under build/fuzz, so new inputs do not land in the repository), and one
# target for the secure bus's receive check (fuzz/fuzz_auth.c, seeds in
# fuzz/corpus/auth) and one for the PNML reader of tasks (fuzz/fuzz_pnml.c,
# seeds in fuzz/corpus/pnml). Fails on the first crash, leak or sanitizer report
# (libFuzzer exits non-zero and leaves the input as build/fuzz/crash-*).
# Usage: tools/fuzz.sh SECONDS [TYPE...]   (default: every lcmtypes/*.lcm, auth and pnml)
set -euo pipefail
cd "$(dirname "$0")/.."
secs=${1:-10}; shift || true
out=build/fuzz; gen=build/gen/c
command -v clang >/dev/null || { echo "fuzz: clang is missing (apt-get install clang)"; exit 2; }
mkdir -p "$out/obj"
san="-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined"
core_inc=$(for d in include/tandem/*/; do printf -- '-I%s ' "${d%/}"; done)
cflags="-std=c99 -O1 -g -D_POSIX_C_SOURCE=200809L $(pkg-config --cflags lcm yaml-0.1 libxml-2.0) $core_inc -I$gen -Ibuild/gen -Isrc/daemons/common -Isrc/platform/posix"
# the receive path's code, instrumented once for every target
objs=()
for f in $gen/*.c src/daemons/common/*.c src/platform/posix/*.c src/core/*/*.c; do
    o=$out/obj/$(echo "$f" | tr / _ | sed 's/\.c$/.o/')
    [ "$o" -nt "$f" ] || clang $cflags $san -c "$f" -o "$o"
    objs+=("$o")
done
# seeds that match the types as they are now (a committed seed of a type
# that has since grown fields is rejected by the wire check at once)
clang -std=c99 -D_POSIX_C_SOURCE=200809L $(pkg-config --cflags lcm) $core_inc -I$gen -Isrc/daemons/common \
    fuzz/seed_gen.c src/daemons/common/wire.c $gen/*.c $(pkg-config --libs lcm) -o "$out/seed_gen"
mkdir -p "$out/corpus" && "$out/seed_gen" "$out/corpus" >/dev/null
types=("$@")
[ ${#types[@]} -gt 0 ] || types=($(ls lcmtypes/*.lcm | xargs -n1 basename | sed 's/\.lcm$//') auth pnml)
for t in "${types[@]}"; do
    bin=$out/fuzz_$t
    if [ "$t" = auth ]; then
        for f in src/daemons/common/auth.c src/daemons/common/auth_acl.c; do
            o=$out/obj/$(echo "$f" | tr / _ | sed 's/\.c$/.o/')
            [ "$o" -nt "$f" ] || clang $cflags $san -c "$f" -o "$o"
        done
        clang $cflags -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined fuzz/fuzz_auth.c \
            $out/obj/src_daemons_common_auth.o $out/obj/src_daemons_common_auth_acl.o -lsodium -o "$bin"
    elif [ "$t" = pnml ]; then
        # the PNML reader of tandem-netc and tandem-supervisor --task (fuzz/fuzz_pnml.c)
        clang $cflags -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined fuzz/fuzz_pnml.c \
            "${objs[@]}" $(pkg-config --libs lcm yaml-0.1 libxml-2.0) -lsodium -lm -o "$bin"
    else
        extra=""
        [ "$t" = action_row_t ] && extra=-DFUZZ_ACTION_ROW
        [ "$t" = arm_joint_ref_t ] && extra=-DFUZZ_JOINT_REF
        clang $cflags -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined \
            -DFUZZ_TYPE=tandem_$t "-DFUZZ_HEADER=\"tandem_$t.h\"" $extra fuzz/fuzz_msg.c "${objs[@]}" $(pkg-config --libs lcm yaml-0.1 libxml-2.0) -lsodium -lm -o "$bin"
    fi
    corpus=$out/corpus/$t; mkdir -p "$corpus"
    [ -d fuzz/corpus/$t ] && cp -n fuzz/corpus/$t/* "$corpus/" 2>/dev/null || true
    log=$out/fuzz_$t.log
    if ! ASAN_OPTIONS=detect_leaks=1:allocator_may_return_null=1 "$bin" -max_total_time="$secs" \
            -artifact_prefix="$out/" -print_final_stats=1 "$corpus" >"$log" 2>&1; then
        tail -40 "$log"; echo "fuzz: $t FAILED (log $log)"; exit 1
    fi
    execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo 0)
    cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 | grep -o '[0-9]*' || echo 0)
    printf '  ok   fuzz_%-24s %9d execs %7d/s  cov %d\n' "$t" "$execs" $((execs / secs)) "$cov"
done
