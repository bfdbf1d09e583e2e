#!/usr/bin/env bash
# Screenshots of lcm-spy for the docs, under Xvfb, with a live run on a
# private bus (its own network namespace when root): docs/lcm-spy.png (every
# channel) and docs/lcm-spy-plot.png (ARM1_STATE's detail view with a live
# plot of q_rad[1], opened by clicking as a user would, with xdotool).
#   tools/spy-shots.sh        (needs: make all; apt-get install xvfb xdotool)
set -eu
here=$(cd "$(dirname "$0")/.." && pwd)
if [ -z "${TANDEM_SPY_NS:-}" ] && [ "$(id -u)" -eq 0 ] && unshare -n true 2>/dev/null; then
    TANDEM_SPY_NS=1 exec unshare -n "$0" "$@"
fi
[ -n "${TANDEM_SPY_NS:-}" ] && { ip link set lo up; ip route add 224.0.0.0/4 dev lo 2>/dev/null || true; }
export LCM_DEFAULT_URL="udpm://239.255.76.67:$((20000 + $$ % 20000))?ttl=0"
export DISPLAY=:$((100 + $$ % 100))
shot() { "$here/build/venv/bin/python" -c "from PIL import ImageGrab; import sys; ImageGrab.grab(xdisplay='$DISPLAY').crop(tuple(map(int, sys.argv[2:6]))).save(sys.argv[1])" "$@"; }
Xvfb "$DISPLAY" -screen 0 1400x1000x24 >/dev/null 2>&1 & xv=$!
sleep 1
"$here/tools/tandem-run" --duration 90 >/dev/null 2>&1 & run=$!
"$here/tools/spy.sh" "$here/build/lib/tandem_types.jar" >/dev/null 2>&1 & spy=$!
trap 'kill $spy 2>/dev/null; kill -TERM $run 2>/dev/null; wait $run; kill $xv' EXIT
win=
for _ in $(seq 1 60); do win=$(xdotool search --name "LCM Spy" 2>/dev/null | head -1) && [ -n "$win" ] && break; sleep 0.5; done
xdotool windowsize "$win" 820 640
sleep 20                     # every channel seen, rates settled
shot "$here/docs/lcm-spy.png" 0 0 820 640
# ARM1_STATE is the third row (sorted by channel): double-click opens its view
xdotool mousemove 60 $((20 + 16 * 2 + 8)) click --repeat 2 --delay 80 1
sleep 4
before=$(xdotool search --onlyvisible --name '.*' | sort)
# a click on a field's sparkline (q_rad[1]) opens a live chart of it
xdotool mousemove 545 145 click 1
sleep 8
for w in $(xdotool search --onlyvisible --name '.*' | sort); do
    grep -qx "$w" <<<"$before" || xdotool windowmove "$w" 640 0 windowsize "$w" 760 520
done
sleep 6
shot "$here/docs/lcm-spy-plot.png" 0 0 1400 640
