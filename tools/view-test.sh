#!/usr/bin/env bash
# Browser test of the live viewer: a short run of the whole system with the
# viewer (tools/tandem-run --view), the page loaded in headless Chromium,
# a screenshot in build/view-test/viewer.png (--docs: also docs/viewer.png)
# and pixel checks that the arms, the workpieces and every rover were drawn,
# and OCR of the events panel for an event line (tools/viewer/view_check.py). The run is recorded with lcm-logger; then a
# fresh viewer is fed by lcm-logplayer from that log and checked the same
# way (replay.png). Runs in its own network namespace when it can (root),
# so its LCM bus and ports never meet another run's.
#   tools/view-test.sh [--docs] [--world-file PATH [--shot FILE]]
# --world-file: the team flies that map_server world (a drawn map, or one
# of tandem-worldgen's); no replay check; --shot also copies the live
# screenshot to FILE (the docs' pictures of file worlds).
set -u
here=$(cd "$(dirname "$0")/.." && pwd)
if [ -z "${TANDEM_VIEW_TEST_NS:-}" ] && [ "$(id -u)" -eq 0 ] && command -v unshare >/dev/null &&
   unshare -n true 2>/dev/null; then
    TANDEM_VIEW_TEST_NS=1 exec unshare -n "$0" "$@"
fi
if [ -n "${TANDEM_VIEW_TEST_NS:-}" ]; then
    ip link set lo up
    ip route add 224.0.0.0/4 dev lo 2>/dev/null   # LCM's multicast on the loopback
fi
docs=0; world_file=; shot=
while [ $# -gt 0 ]; do
    case $1 in
    --docs) docs=1; shift ;;
    --world-file) world_file=$(cd "$(dirname "$2")" && pwd)/$(basename "$2"); shift 2 ;;
    --shot) shot=$2; shift 2 ;;
    *) echo "view-test: unknown option $1" >&2; exit 2 ;;
    esac
done
world_args=()
[ -n "$world_file" ] && world_args=(--world-file "$world_file")
out=$here/build/view-test
mkdir -p "$out"
# the events panel's feed on encoded messages, before anything is started
"$here/build/venv/bin/python" "$here/tools/viewer/feed_test.py" ||
    { echo "view test: 0 passed, 1 failed"; exit 1; }
# ports and bus of our own (also when no namespace could be had)
base=$((20000 + $$ % 20000))
web=$base; devtools=$((base + 1))
export LCM_DEFAULT_URL="udpm://239.255.76.67:$((base + 2))?ttl=0"
rovers=3
# the first 30 s of the run, the viewer's channels only (not the 1 kHz
# commands and clock), for the replay check
lcm-logger --force -c 'ARM[12]_STATE|ARM_EVENTS|PETRI_MARKING|VISION_DETECTIONS|SIM_STATUS|SIM_CONTROL|ROVER.*|TEAM|HEALTH_.*' \
    "$out/run.lcmlog" >/dev/null 2>&1 &
logger=$!
( sleep 30; kill -INT $logger 2>/dev/null ) &
"$here/tools/tandem-run" --duration 400 --view --web-port "$web" --rovers "$rovers" "${world_args[@]}" \
    > "$out/run.log" 2>&1 &
run=$!
url=
for _ in $(seq 1 300); do
    url=$(sed -n 's/.*tandem-view: open \(http[^ ]*\).*/\1/p' "$out/run.log" | head -1)
    [ -n "$url" ] && break
    kill -0 $run 2>/dev/null || break
    sleep 0.2
done
rc=1
if [ -z "$url" ]; then
    echo "view-test: the viewer never printed its URL" >&2
else
    sleep 3   # let the arms and rovers publish before the page loads
    "$here/build/venv/bin/python" "$here/tools/viewer/view_check.py" --rovers "$rovers" \
        --devtools-port "$devtools" "$url" "$out/viewer.png"
    rc=$?
fi
# TERM: a background job of a script ignores SIGINT, so tandem-run's INT trap never runs
kill -TERM $run 2>/dev/null; wait $run
kill -INT $logger 2>/dev/null; wait $logger
grep -E "tandem-view|\[view\]" "$out/run.log" | tail -5
[ $rc -eq 0 ] || { echo "view-test: run log:" >&2; tail -40 "$out/run.log" >&2; }
if [ $rc -eq 0 ] && [ -n "$shot" ]; then
    cp "$out/viewer.png" "$shot"
fi
if [ $rc -eq 0 ] && [ -z "$world_file" ]; then
    # the same checks on a replay of the recorded run, at half its speed
    "$here/build/venv/bin/python" "$here/tools/viewer/tandem_view.py" --web-port $((web + 3)) \
        --grpc-port $((web + 4)) --rovers "$rovers" > "$out/replay.log" 2>&1 &
    view=$!
    lcm-logplayer -s 0.5 "$out/run.lcmlog" & player=$!
    for _ in $(seq 1 300); do grep -q "tandem-view: open" "$out/replay.log" && break; sleep 0.2; done
    url=$(sed -n 's/.*tandem-view: open \(http[^ ]*\).*/\1/p' "$out/replay.log" | head -1)
    echo "view-test: replay of the recorded run ($(du -h "$out/run.lcmlog" | cut -f1)) with lcm-logplayer"
    "$here/build/venv/bin/python" "$here/tools/viewer/view_check.py" --rovers "$rovers" \
        --devtools-port $((web + 5)) "$url" "$out/replay.png"
    rc=$?
    kill $player $view 2>/dev/null; wait $player $view 2>/dev/null
    [ $rc -eq 0 ] || { echo "view-test: replay viewer log:" >&2; tail -20 "$out/replay.log" >&2; }
fi
[ $rc -eq 0 ] && [ $docs -eq 1 ] && [ -z "$world_file" ] && cp "$out/viewer.png" "$here/docs/viewer.png"
echo "view test: $([ $rc -eq 0 ] && echo "1 passed, 0 failed" || echo "0 passed, 1 failed")"
exit $rc
