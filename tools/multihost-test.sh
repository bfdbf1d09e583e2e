#!/usr/bin/env bash
# make multihost-test: the whole cell on three "machines" gives the same
# lockstep run as on one.
#
# Three network namespaces stand for three hosts on one LAN: the
# simulator, the arm cell (tandem-arm 1 and 2, tandem-supervisor) and the
# rover team (tandem-rover 1..3), each with its own interface on a bridge
# (in a fourth namespace, so the machine's own network is not touched).
# LCM runs on UDP multicast with ttl=1, as it would across a switch. The
# same cell then runs in one namespace on loopback (ttl=0). The simulator
# prints its state hash at the last step: the two must be equal.
#
# Needs root (ip netns); prints SKIPPED and exits 0 otherwise.
set -u
here=$(cd "$(dirname "$0")/.." && pwd)
bin=${TANDEM_BIN:-$here/build/bin}
steps=${MULTIHOST_STEPS:-15000}
tag=tmh$$
out=$(mktemp -d)
. "$here/tools/netns-lan.sh"
netns_root_or_skip multihost-test

hosts=(sim arms rovers)
trap 'netns_cleanup "${hosts[@]}" all hub' EXIT

# run_cell URL NS_SIM NS_ARMS NS_ROVERS LOGDIR: the cell, until the
# simulator stops at $steps; prints its state hash.
run_cell() {
    local url=$1 nsim=$2 narms=$3 nrov=$4 dir=$5 k pids=() sim_pid
    mkdir -p "$dir"
    export LCM_DEFAULT_URL=$url
    ns "$nsim" "$bin/tandem-sim" --lockstep --expect 6 --steps "$steps" --timeout-ms 60000 \
        --seed 2 --workpieces 2 --rovers 3 --world obstacles >"$dir/sim.out" 2>"$dir/sim.err" &
    sim_pid=$!
    ns "$narms" "$bin/tandem-arm" --arm 1 --lockstep >"$dir/arm1.log" 2>&1 & pids+=($!)
    ns "$narms" "$bin/tandem-arm" --arm 2 --lockstep >"$dir/arm2.log" 2>&1 & pids+=($!)
    ns "$narms" "$bin/tandem-supervisor" --lockstep >"$dir/supervisor.log" 2>&1 & pids+=($!)
    for k in 1 2 3; do
        ns "$nrov" "$bin/tandem-rover" --id $k --robots 3 --world obstacles --lockstep \
            >"$dir/rover$k.log" 2>&1 & pids+=($!)
    done
    for _ in $(seq 1 600); do kill -0 $sim_pid 2>/dev/null || break; sleep 0.5; done
    kill -TERM "${pids[@]}" $sim_pid 2>/dev/null
    wait 2>/dev/null
    sed -n 's/.*stopped at step \([0-9]*\) state_hash=\([0-9a-f]*\).*/\1 \2/p' "$dir/sim.out"
}

# one bus key for the whole cell, as make run would make (tandem-keygen)
export TANDEM_KEY_FILE=$out/bus.key
"$bin/tandem-keygen" "$TANDEM_KEY_FILE" >/dev/null || { echo "multihost-test: cannot make a bus key"; exit 1; }
netns_loopback all          # one host, loopback only
netns_lan 10.77.0 "${hosts[@]}" # three hosts on a bridge
t0=$SECONDS
one=$(run_cell "udpm://239.255.76.67:7667?ttl=0" all all all "$out/one")
t1=$SECONDS
three=$(run_cell "udpm://239.255.76.67:7667?ttl=1" sim arms rovers "$out/three")
t2=$SECONDS
echo "multihost-test: one host    (loopback, ttl=0):          step+hash ${one:-none} ($((t1 - t0)) s)"
echo "multihost-test: three hosts (bridge, udpm ttl=1):       step+hash ${three:-none} ($((t2 - t1)) s)"
grep -h "joined\|dropped" "$out/three/sim.err" | sed 's/^/multihost-test:   /'
if [ -z "$one" ] || [ "$one" != "$three" ] || [ "${one%% *}" != "$steps" ]; then
    echo "multihost-test: FAILED (logs in $out)"
    exit 1
fi
rm -rf "$out"
echo "multihost-test: passed: the same lockstep state at step $steps on one host and on three"
