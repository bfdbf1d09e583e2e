#!/usr/bin/env bash
# make fleet-hosts: a fleet's robots on H rover hosts, each its own
# network namespace (a machine of its own on one LAN), against the same
# run in one process: the truth must be byte for byte the same.
#
# The simulator and tandem-scenario run in one namespace, each rover host
# (tandem-rover --id A-B, whole teams) in another, every namespace with its
# own interface on a bridge (in a hub namespace, so the machine's own
# network is not touched), LCM on UDP multicast with ttl=1 as across a
# switch. The one-process run is in a namespace of its own on loopback.
# Both runs print their CPU time (every process: the scenario waits for
# its children, wherever their network is) and their cost per robot-step
# (CPU over robots x steps, start-up included: make bench gives it by
# difference).
#
#   TEAMS=30 HOSTS=4 MAX_TIME=8 SEED=1 tools/fleet-hosts.sh
#   ONE=0 TEAMS=1000 MAX_TIME=1 tools/fleet-hosts.sh     # 10,000 robots, hosts only
#
# Needs root (ip netns); prints SKIPPED and exits 0 otherwise. Exit 1 when
# a run fails to finish or the two truths differ.
set -u
here=$(cd "$(dirname "$0")/.." && pwd)
bin=${TANDEM_BIN:-$here/build/bin}
teams=${TEAMS:-30}
hosts=${HOSTS:-4}
max_time=${MAX_TIME:-8}
seed=${SEED:-1}
one_too=${ONE:-1}
tag=tfh$$
out=$(mktemp -d)
. "$here/tools/netns-lan.sh"
netns_root_or_skip fleet-hosts

names=(sim)
for h in $(seq 1 "$hosts"); do names+=("h$h"); done
trap 'netns_cleanup "${names[@]}" all hub' EXIT
netns_loopback all             # the one-process run
netns_lan 10.78.0 "${names[@]}" # the simulator's namespace and one per host

# run NS URL DIR [ARGS...]: one formation run of the fleet; prints
# "cpu_s wall_s" (every process of the run)
run() {
    local n=$1 url=$2 dir=$3
    shift 3
    TANDEM_NO_PLOTS=1 /usr/bin/time -f "%U %S %e" -o "$dir.time" \
        ip netns exec "$tag$n" "$bin/tandem-scenario" formation --teams "$teams" \
        --robots-per-team 10 --procs single --rover-far kinematic --max-time "$max_time" \
        --seed "$seed" --lcm-url "$url" --out "$dir" "$@" >"$dir.log" 2>&1
    tail -n 1 "$dir.time" | awk '{ printf "%.1f %.1f\n", $1 + $2, $3 }'
}

robots=$((teams * 10))
steps=$(awk -v t="$max_time" 'BEGIN { printf "%d", t * 1000 }')
report() { # WHAT CPU WALL
    awk -v w="$1" -v c="$2" -v e="$3" -v n="$robots" -v s="$steps" \
        'BEGIN { printf "fleet-hosts: %-28s %d robots, %.1f s simulated: CPU %.1f s, wall %.1f s, %.2f us per robot-step\n", w, n, s / 1000, c, e, c / (n * s) * 1e6 }'
}
ok=1
read -r c e < <(run sim "udpm://239.255.76.67:7668?ttl=1&recv_buf_size=4194304" "$out/hosts" \
    --hosts "$hosts" --host-netns "${tag}h")
report "$hosts hosts (bridge, ttl=1):" "$c" "$e"
grep -h "joined\|dropped" "$out/hosts/children.log" | sed 's/^/fleet-hosts:   /'
if ! grep -q "stopped at step $steps " "$out/hosts/children.log"; then
    echo "fleet-hosts: the run on $hosts hosts did not reach step $steps"
    ok=0
fi
if [ "$one_too" = 1 ]; then
    read -r c e < <(run all "udpm://239.255.76.67:7668?ttl=0&recv_buf_size=4194304" "$out/one")
    report "one process (loopback):" "$c" "$e"
    a=$(md5sum <"$out/hosts/truth.csv" | cut -c1-32)
    b=$(md5sum <"$out/one/truth.csv" | cut -c1-32)
    echo "fleet-hosts: truth.csv md5 $hosts hosts $a, one process $b ($(wc -l <"$out/one/truth.csv") lines)"
    [ "$a" = "$b" ] || ok=0
fi
if [ "$ok" != 1 ]; then
    echo "fleet-hosts: FAILED (logs in $out)"
    exit 1
fi
rm -rf "$out"
echo "fleet-hosts: passed"
