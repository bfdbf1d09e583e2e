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
if [ "$(id -u)" != 0 ] || ! ip netns add "${tag}probe" 2>/dev/null; then
    echo "multihost-test: SKIPPED (needs root for network namespaces)"
    exit 0
fi
ip netns del "${tag}probe"

hosts=(sim arms rovers)
cleanup() {
    local h
    for h in "${hosts[@]}" all hub; do
        ip netns pids "$tag$h" 2>/dev/null | xargs -r kill -KILL 2>/dev/null
        ip netns del "$tag$h" 2>/dev/null
    done
}
trap cleanup EXIT

# ns NAME CMD...: run in namespace NAME
ns() { local n=$1; shift; ip netns exec "$tag$n" "$@"; }

# One namespace, loopback only.
make_single() {
    ip netns add "${tag}all"
    ns all ip link set lo up
    ns all ip route add 224.0.0.0/4 dev lo
}

# Three namespaces, each with eth0 on a bridge in the hub namespace.
make_lan() {
    local i=1 h
    ip netns add "${tag}hub"
    ns hub ip link add br0 type bridge mcast_snooping 0
    ns hub ip link set br0 up
    for h in "${hosts[@]}"; do
        ip netns add "$tag$h"
        ns "$h" ip link set lo up
        ip link add "${tag}v$i" netns "${tag}hub" type veth peer name eth0 netns "$tag$h"
        ns hub ip link set "${tag}v$i" master br0 up
        ns "$h" ip addr add "10.77.0.$((10 + i))/24" dev eth0
        ns "$h" ip link set eth0 up
        ns "$h" ip route add 224.0.0.0/4 dev eth0
        i=$((i + 1))
    done
}

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
make_single
make_lan
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
