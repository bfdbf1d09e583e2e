#!/usr/bin/env bash
# make bench: prints the benchmark figures (nothing is asserted).
set -u
bin=${1:-build/bin}
here=$(cd "$(dirname "$0")/.." && pwd)
cd "$here"
export LCM_DEFAULT_URL="udpm://239.255.76.67:$((30000 + $$ % 10000))?ttl=0"
export G_SLICE=always-malloc   # as tandem-run starts the daemons (docs/security.md §5)
# a bus key for the daemons of this run alone (README "Security")
keydir=$(mktemp -d)
trap 'rm -rf "$keydir"' EXIT
"$bin/tandem-keygen" "$keydir/bus.key" >/dev/null || exit 1
export TANDEM_KEY_FILE=$keydir/bus.key
ms_now() { echo $(( $(date +%s%N) / 1000000 )); }

echo "== 1. round trip state -> controller -> command over LCM, with and without authentication (per-role keys) =="
"$bin/bench_roundtrip" 10000 "$bin"   # (the round trips alone: bench_roundtrip roundtrip N BIN_DIR REPS)
if command -v valgrind >/dev/null; then
    echo "  instructions per message, sign + check of ARM1_STATE, ARM1_COMMAND and SIM_CLOCK"
    echo "  (callgrind: (2000 messages - 1000 messages) / 1000 / 3 sizes, set-up cancels):"
    out=$(valgrind --tool=callgrind --callgrind-out-file=/dev/null "$bin/bench_roundtrip" auth 2000 2>&1 | awk '/Collected/ {print $4}')
    base=$(valgrind --tool=callgrind --callgrind-out-file=/dev/null "$bin/bench_roundtrip" auth 1000 2>&1 | awk '/Collected/ {print $4}')
    [ -n "$out" ] && [ -n "$base" ] && printf '    %d per message (sign with a tag per reader + check one tag)\n' $(( (out - base) / 1000 / 3 ))
    out=$(valgrind --tool=callgrind --callgrind-out-file=/dev/null "$bin/bench_roundtrip" ed25519 200 2>&1 | awk '/Collected/ {print $4}')
    base=$(valgrind --tool=callgrind --callgrind-out-file=/dev/null "$bin/bench_roundtrip" ed25519 100 2>&1 | awk '/Collected/ {print $4}')
    [ -n "$out" ] && [ -n "$base" ] && printf '    %d per message with Ed25519 instead (crypto_sign + crypto_sign_verify)\n' $(( (out - base) / 100 / 3 ))
fi

echo; echo "== 2. lockstep speed: tandem-sim (PUMA pair) with one 1 kHz controller =="
steps=20000
"$bin/tandem-arm" --arm 1 --lockstep >/dev/null 2>&1 & arm=$!
t0=$(ms_now)
"$bin/tandem-sim" --lockstep --expect 1 --steps $steps >/dev/null 2>&1
t1=$(ms_now)
kill $arm 2>/dev/null; wait $arm 2>/dev/null
echo "  $steps steps in $((t1 - t0)) ms: $(( steps * 1000 / (t1 - t0 > 0 ? t1 - t0 : 1) )) steps per wall second ($(( steps / (t1 - t0 > 0 ? t1 - t0 : 1) ))x real time)"

echo; echo "== 3. real-time loop wake-up latency, 1 ms period, 10000 loops, beside cyclictest =="
for prio in 0 80; do
    label="normal scheduling"; [ $prio -gt 0 ] && label="SCHED_FIFO $prio"
    echo "  -- $label --"
    "$bin/bench_rtloop" 1000 10000 $prio | sed 's/^/  /'
    if command -v cyclictest >/dev/null; then
        pargs=(); [ $prio -gt 0 ] && pargs=(-p $prio)
        cyclictest -t1 -i 1000 -l 10000 -q -h 5000 "${pargs[@]}" 2>/dev/null | awk '
            /^[0-9]/ { n[$1 + 0] = $2; total += $2 }
            /# Max Latencies/ { max = $4 }
            END { c = 0; p50 = -1; p99 = -1
                  for (i = 0; i <= 5000; i++) { c += n[i]
                      if (p50 < 0 && c >= 0.5 * total) p50 = i
                      if (p99 < 0 && c >= 0.99 * total) p99 = i }
                  printf "  cyclictest period 1000 us, %d loops: latency p50 %d us  p99 %d us  max %d us\n", total, p50, p99, max + 0 }'
    else
        echo "  cyclictest not installed (Debian package rt-tests)"
    fi
done

echo; echo "== 4. arm core vs Orocos KDL (same PUMA 560 chain, same run) =="
if [ -x "$bin/bench_kdl" ]; then "$bin/bench_kdl" 200000; else echo "  bench_kdl not built (needs liborocos-kdl-dev)"; fi
if command -v valgrind >/dev/null && [ -x "$bin/bench_arm" ]; then
    echo "  instructions per call (callgrind: (2000 calls - 1000 calls) / 1000, so set-up cancels):"
    for r in fk jac ik rne mass; do
        out=$(valgrind --tool=callgrind --callgrind-out-file=/dev/null "$bin/bench_arm" $r 2000 2>&1 | awk '/Collected/ {print $4}')
        base=$(valgrind --tool=callgrind --callgrind-out-file=/dev/null "$bin/bench_arm" $r 1000 2>&1 | awk '/Collected/ {print $4}')
        [ -n "$out" ] && [ -n "$base" ] && printf '    %-5s %8d\n' $r $(( (out - base) / 1000 ))
    done
fi

echo; echo "== 4b. arm core vs Pinocchio (PyPI pin; same PUMA 560, same samples, same run) =="
if [ -x "$bin/bench_pinocchio" ]; then "$bin/bench_pinocchio" 200000; else echo "  bench_pinocchio not built (needs pip install pin)"; fi

echo; echo "== 5. one TDSD step vs Orocos KDL velocity IK (wdls, pinv), same PUMA 560 chain, same run =="
if [ -x "$bin/bench_tdsd_kdl" ]; then
    "$bin/bench_tdsd_kdl" 100000 | sed 's/^/  /'
    if command -v valgrind >/dev/null; then
        echo "  instructions per call (callgrind: (2000 calls - 1000 calls) / 1000):"
        for r in tdsd tdsd_jac wdls pinv; do
            out=$(valgrind --tool=callgrind --callgrind-out-file=/dev/null "$bin/bench_tdsd_kdl" 2000 $r 2>&1 | awk '/Collected/ {print $4}')
            base=$(valgrind --tool=callgrind --callgrind-out-file=/dev/null "$bin/bench_tdsd_kdl" 1000 $r 2>&1 | awk '/Collected/ {print $4}')
            [ -n "$out" ] && [ -n "$base" ] && printf '    %-9s %8d\n' $r $(( (out - base) / 1000 ))
        done
    fi
else
    echo "  bench_tdsd_kdl not built (needs liborocos-kdl-dev)"
fi

for extra in "$bin"/bench_carry "$bin"/bench_tdsd; do
    [ -x "$extra" ] || continue
    echo; echo "== $(basename "$extra") =="
    "$extra"
done

echo; echo "== sonar ray cast: a 100 m x 100 m map of 2000 boxes against the built-in worlds =="
"$bin/bench_sonar_map" 2000000 | sed 's/^/  /'

echo; echo "== bench_fleet: the simulator alone, 100 to 3000 robots, one core (taskset -c 0) =="
if command -v taskset >/dev/null; then taskset -c 0 "$bin/bench_fleet" 1
else echo "  (taskset not found: not pinned)"; "$bin/bench_fleet" 1; fi

echo; echo "== fleet, whole system: T teams of 10 in lockstep, one process of all rovers, one core (taskset -c 0) =="
echo "  CPU of every process (simulator, rover host, scenario; no plots) by difference of a 2 s and a 6 s run (start-up cancels);"
echo "  --rover-far ode: every robot in the ODE solver; kinematic: robots clear of everything moved by their wheels"
pin=(); command -v taskset >/dev/null && pin=(taskset -c 0)
k1000=
fleet_cpu() { # teams sim_seconds far -> CPU seconds (user + system) of the run and its children
    local TIMEFORMAT='%U %S'
    { time TANDEM_NO_PLOTS=1 "${pin[@]}" "$bin/tandem-scenario" formation --teams "$1" --robots-per-team 10 \
        --procs single --rover-far "$3" --max-time "$2" --out "$keydir/fleet" >/dev/null 2>&1; } 2>&1 |
        awk '{ print $1 + $2 }'
}
for row in "10 ode" "30 ode" "100 ode" "10 kinematic" "30 kinematic" "100 kinematic" "300 kinematic"; do
    set -- $row
    a=$(fleet_cpu "$1" 2 "$2"); b=$(fleet_cpu "$1" 6 "$2")
    # the 1,000-robot kinematic row is the hosts row's baseline (same run)
    [ "$row" = "100 kinematic" ] && k1000=$(awk -v a="$a" -v b="$b" 'BEGIN { d = b - a; if (d > 0) printf "%.4f", d / 4e6 * 1e6 }')
    awk -v n=$(($1 * 10)) -v far="$2" -v a="$a" -v b="$b" 'BEGIN {
        d = b - a; if (d <= 0) d = 1e-9
        printf "  %5d robots, %-9s: %.2f us CPU per robot-step, %.2f sim-s per CPU-s (runs of 2 s: %.1f s CPU, 6 s: %.1f s)\n",
               n, far, d / (n * 4000) * 1e6, 4 / d, a, b }'
done

echo; echo "== fleet over hosts: 1,000 teams of 10 on 4 rover hosts, each its own network namespace (root; TEAMS=, HOSTS=) =="
echo "  CPU of every process (simulator and scenario in one namespace, a host in each other, on a bridge)"
echo "  by difference of a 1 s and a 3 s run; against the one-process rows above (they share this machine's cores)"
hosts_cpu() { # sim_seconds -> CPU seconds of the whole run, or nothing (skipped, failed)
    ONE=0 TEAMS=${TEAMS:-1000} HOSTS=${HOSTS:-4} MAX_TIME=$1 TANDEM_BIN=$bin tools/fleet-hosts.sh 2>&1 |
        sed -n 's/.* simulated: CPU \([0-9.]*\) s.*/\1/p' | head -n 1
}
a=$(hosts_cpu 1)
if [ -z "$a" ]; then
    echo "  skipped (tools/fleet-hosts.sh: needs root for network namespaces, or the run failed)"
else
    b=$(hosts_cpu 3)
    awk -v n=$((${TEAMS:-1000} * 10)) -v h=${HOSTS:-4} -v a="$a" -v b="${b:-0}" -v k="${k1000:-0}" 'BEGIN {
        d = b - a; if (d <= 0) d = 1e-9
        us = d / (n * 2000) * 1e6
        printf "  %5d robots on %d hosts: %.2f us CPU per robot-step, %.3f sim-s per CPU-s (runs of 1 s: %.1f s CPU, 3 s: %.1f s)\n",
               n, h, us, 2 / d, a, b
        if (k > 0) printf "  against 1,000 robots in one process above: %.2fx (the target: at most 1.5x)\n", us / k }'
fi

echo; echo "== bench_rovers: Pioneer team, all processes pinned to one core (taskset -c 0) =="
if command -v taskset >/dev/null; then taskset -c 0 "$bin/bench_rovers" 20 "$bin"
else echo "  (taskset not found: not pinned)"; "$bin/bench_rovers" 20 "$bin"; fi
