#!/usr/bin/env bash
# flood-measure.sh: what a flood costs the running cell (docs/security.md,
# "Flooding"). Runs tools/tandem-run (role files, tandem-status --loops) and
# a bare LCM subscriber (bench_bare_sub) on a private bus, and floods it
# with tandem-flood, which holds no key:
#   A  junk LCM datagrams, RATE per second, on ARM1_ACTION     (PHASE_S s)
#   B  forgeries of 60 kB with a trailer of the right form, as fast as the
#      socket takes them, on ARM1_ACTION                        (PHASE_S s)
#   C  junk, RATE per second, a new random channel name each    (PHASE_S s)
# Prints each daemon's resident memory (VmRSS) before and after each phase,
# the tandem-status loop lines at the end of each phase (longest cycle,
# overruns, drains over budget, refusals) and the supervisor's transitions
# per phase (the arms go on). Run it in a network namespace of its own, so
# nothing else shares the bus:
#   unshare -n sh -c 'ip link set lo up; ip route add 224.0.0.0/4 dev lo; tools/flood-measure.sh'
# PHASE_S (default 60) and RATE (default 50000) from the environment.
set -u
here=$(cd "$(dirname "$0")/.." && pwd)
bin=${TANDEM_BIN:-$here/build/bin}
phase_s=${PHASE_S:-60}
rate=${RATE:-50000}
out=$(mktemp -d "${TMPDIR:-/tmp}/tandem-flood-XXXXXX")
export XDG_STATE_HOME=$out/state
export LCM_DEFAULT_URL="udpm://239.255.76.67:7667?ttl=0"

rss_of() {  # rss_of LABEL: VmRSS of tandem-run's daemons and of the bare subscriber
    local p name ppid
    printf '%s:' "$1"
    for p in /proc/[0-9]*; do
        ppid=$(awk '{print $4}' "$p/stat" 2>/dev/null) || continue
        [ "$ppid" = "$run" ] || [ "${p#/proc/}" = "$bare" ] || continue
        name=$(cat "$p/comm" 2>/dev/null) || continue
        case $name in tandem-*|bench_bare_sub)
            printf '  %s %s kB' "$name" "$(awk '/^VmRSS/ {print $2}' "$p/status" 2>/dev/null)" ;;
        esac
    done
    echo
}
transitions() { grep -c 'complete t' "$out/run.log" 2>/dev/null || echo 0; }
loops() {  # the last loop line of each daemon so far
    grep '\[status\]   loop' "$out/run.log" | awk '{ last[$3] = $0 } END { for (k in last) print last[k] }' | sort
}

# both run until the phases are over (stopped below)
"$here/tools/tandem-run" --duration "$((3 * phase_s + 600))" --loops >"$out/run.log" 2>&1 &
run=$!
"$bin/bench_bare_sub" "$((3 * phase_s + 600))" ARM1_ACTION >"$out/bare.log" 2>&1 &
bare=$!
sleep 25
rss_of "before"
loops
t_prev=$(transitions)
for phase in A B C; do
    case $phase in
        A) args=(--kind junk --rate "$rate" --channel ARM1_ACTION) ;;
        B) args=(--kind forge --size 60000 --rate 0 --channel ARM1_ACTION) ;;
        C) args=(--kind junk --rate "$rate" --random-channels) ;;
    esac
    echo "== phase $phase: tandem-flood ${args[*]} --duration $phase_s"
    "$bin/tandem-flood" "${args[@]}" --duration "$phase_s"
    sleep 2
    rss_of "after $phase"
    loops
    t_now=$(transitions)
    echo "supervisor transitions completed during phase $phase: $((t_now - t_prev))"
    t_prev=$t_now
done
kill -TERM "$bare"; wait "$bare"
cat "$out/bare.log"
kill -TERM "$run"; wait "$run"   # (a background job ignores SIGINT)
echo "tandem-run exit status $?; its log: $out/run.log"
grep -E 'WARNING|exited' "$out/run.log" | sort | uniq -c | sort -rn | head -12
