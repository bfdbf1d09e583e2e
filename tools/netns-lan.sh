# tools/netns-lan.sh: network namespaces standing for hosts, sourced by
# multihost-test.sh and fleet-hosts.sh (root). The caller sets $tag, the
# namespaces' prefix, unique to its run.

# ns NAME CMD...: run CMD in namespace $tag NAME
ns() { local n=$1; shift; ip netns exec "$tag$n" "$@"; }

# netns_loopback NAME: a namespace with loopback only, multicast on lo
netns_loopback() {
    ip netns add "$tag$1"
    ns "$1" ip link set lo up
    ns "$1" ip route add 224.0.0.0/4 dev lo
}

# netns_lan NET NAME...: a namespace per NAME, each with eth0 (NET.11,
# NET.12, ...) on a bridge in namespace $tag hub, so the machine's own
# network is not touched; multicast routed to eth0, as on one LAN
netns_lan() {
    local net=$1 i=1 h
    shift
    ip netns add "${tag}hub"
    ns hub ip link add br0 type bridge mcast_snooping 0
    ns hub ip link set br0 up
    for h in "$@"; do
        ip netns add "$tag$h"
        ns "$h" ip link set lo up
        ip link add "${tag}v$i" netns "${tag}hub" type veth peer name eth0 netns "$tag$h"
        ns hub ip link set "${tag}v$i" master br0 up
        ns "$h" ip addr add "$net.$((10 + i))/24" dev eth0
        ns "$h" ip link set eth0 up
        ns "$h" ip route add 224.0.0.0/4 dev eth0
        i=$((i + 1))
    done
}

# netns_cleanup NAME...: every process in them killed, the namespaces deleted
netns_cleanup() {
    local n
    for n in "$@"; do
        ip netns pids "$tag$n" 2>/dev/null | xargs -r kill -KILL 2>/dev/null
        ip netns del "$tag$n" 2>/dev/null
    done
}

# netns_root_or_skip WHAT: exits 0 with "WHAT: SKIPPED" unless namespaces can be made
netns_root_or_skip() {
    if [ "$(id -u)" != 0 ] || ! ip netns add "${tag}probe" 2>/dev/null; then
        echo "$1: SKIPPED (needs root for network namespaces)"
        exit 0
    fi
    ip netns del "${tag}probe"
}
