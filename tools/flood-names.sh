#!/usr/bin/env bash
# flood-names.sh: what a flood of channel names, each new, costs one tandem
# program beside a bare LCM subscriber (docs/security.md §5-6). LCM keeps
# every channel name it sees; tandem's programs renew their LCM handle when
# their resident memory has grown by DAEMON_NAMES_SLACK_KB (daemon.h,
# names_watch), the bare subscriber (bench_bare_sub: lcm_subscribe and a
# counter) cannot. Runs the TARGET and bench_bare_sub on a private bus,
# floods it with tandem-flood --random-channels for FLOOD_S s at RATE
# datagrams/s, and prints both processes' VmRSS every STEP_S s, then the
# peaks. TARGET:
#   arm     `tandem-arm --arm 1 --insecure` (no simulator: it holds on its
#           brakes; its receive path is the one every daemon has) (default)
#   sim     `tandem-sim --insecure` (real time, the arm pair, no controllers:
#           the arms hold on their brakes)
#   status  `tandem-status --insecure` (a tool: its own handle, checked
#           subscriptions)
#   view    the viewer bridge, tools/viewer/tandem_view.py (make viewer):
#           it counts the names it sees and renews its handle at
#           TANDEM_VIEW_NAMES_MAX (its memory is mostly Rerun's store)
# Run it in a network namespace of its own:
#   unshare -n sh -c 'ip link set lo up; ip route add 224.0.0.0/4 dev lo; tools/flood-names.sh'
# TARGET (default arm), FLOOD_S (default 60), RATE (default 50000), STEP_S
# (default 5), G_SLICE (default always-malloc), TANDEM_BIN (default
# build/bin: the programs measured).
set -u
here=$(cd "$(dirname "$0")/.." && pwd)
bin=${TANDEM_BIN:-$here/build/bin}
flood_s=${FLOOD_S:-60}
rate=${RATE:-50000}
step_s=${STEP_S:-5}
target=${TARGET:-arm}
case $target in
arm) cmd=("$bin/tandem-arm" --arm 1 --insecure) ;;
sim) cmd=("$bin/tandem-sim" --insecure) ;;
status) cmd=("$bin/tandem-status" --insecure --every 5) ;;
view) cmd=("$here/build/venv/bin/python" "$here/tools/viewer/tandem_view.py" --bin "$bin" --stats-s 0
           --web-port 29090 --grpc-port 29876) ;;
*) echo "flood-names.sh: TARGET=$target is not arm|sim|status|view" >&2; exit 2 ;;
esac
name=$(basename "${cmd[0]}")
[ "$target" = view ] && name=tandem-view
export LCM_DEFAULT_URL="udpm://239.255.76.67:7667?ttl=0"
# as tools/tandem-run and tandem-scenario start their daemons (daemon.h,
# DAEMON_GLIB_SLICE_ENV); G_SLICE= (empty) on the command line shows why
export G_SLICE=${G_SLICE-always-malloc}
out=$(mktemp -d "${TMPDIR:-/tmp}/tandem-names-XXXXXX")
rss() { awk '/^VmRSS/ {print $2}' "/proc/$1/status" 2>/dev/null; }
"${cmd[@]}" >"$out/target.log" 2>&1 &
arm=$!
"$bin/bench_bare_sub" "$((flood_s + 30))" ARM1_ACTION >"$out/bare.log" 2>&1 &
bare=$!
sleep 3
echo "t_s  ${name}_kB  bench_bare_sub_kB"
peak=$(rss $arm) peak_bare=$(rss $bare)
echo "0  $peak  $peak_bare"
"$bin/tandem-flood" --kind junk --rate "$rate" --random-channels --duration "$flood_s" >"$out/flood.log" 2>&1 &
flood=$!
t=0
while kill -0 "$flood" 2>/dev/null; do
    sleep "$step_s"
    t=$((t + step_s))
    r=$(rss $arm) rb=$(rss $bare)
    echo "$t  $r  $rb"
    [ -n "$r" ] && [ "$r" -gt "$peak" ] && peak=$r
    [ -n "$rb" ] && [ "$rb" -gt "$peak_bare" ] && peak_bare=$rb
done
wait "$flood"
cat "$out/flood.log"
echo "$name renewed its LCM handle $(grep -c 'LCM handle renewed' "$out/target.log") times; peak VmRSS (every ${step_s} s) $peak kB, bench_bare_sub $peak_bare kB"
kill -TERM "$arm" "$bare" 2>/dev/null
wait "$arm" "$bare" 2>/dev/null
rm -rf "$out"
