#!/usr/bin/env bash
# make mcap-test: tandem-log2mcap on a recorded run. Records every channel
# of a short run of the whole cell (tools/tandem-run --duration, lcm-logger)
# in its own network namespace when it can (root), converts it, and checks
# with tools/mcap/mcap_check.py that every message of every channel is in
# the MCAP file and decodes back, field by field, to what lcm-gen's decoder
# reads from the log; then that a truncated and a foreign file fail with a
# message and keep what came before the damage; then the file's structure
# with tools/mcap/mcap_doctor.py (the checks of `mcap doctor` on the mcap
# package's records; it must refuse damaged copies) and `mcap doctor` itself
# (the Go mcap CLI, installed with go install when go is there; skipped otherwise).
#   tools/mcap-test.sh [SECONDS]       (default 20)
set -u
here=$(cd "$(dirname "$0")/.." && pwd)
if [ -z "${TANDEM_MCAP_TEST_NS:-}" ] && [ "$(id -u)" -eq 0 ] && command -v unshare >/dev/null &&
   unshare -n true 2>/dev/null; then
    TANDEM_MCAP_TEST_NS=1 exec unshare -n "$0" "$@"
fi
if [ -n "${TANDEM_MCAP_TEST_NS:-}" ]; then
    ip link set lo up
    ip route add 224.0.0.0/4 dev lo 2>/dev/null   # LCM's multicast on the loopback
fi
secs=${1:-20}
out=$here/build/mcap-test
py=$here/build/venv-tools/bin/python
conv=$here/build/bin/tandem-log2mcap
mkdir -p "$out"
export LCM_DEFAULT_URL="udpm://239.255.76.67:$((20000 + $$ % 20000))?ttl=0"
passed=0 failed=0 skipped=0
check() {  # check NAME COMMAND...: one test case
    local name=$1; shift
    if "$@"; then passed=$((passed + 1)); echo "mcap-test: $name: ok"
    else failed=$((failed + 1)); echo "mcap-test: $name: FAILED" >&2; fi
}

rm -f "$out/run.lcmlog"
lcm-logger --force "$out/run.lcmlog" >/dev/null 2>&1 &
logger=$!
"$here/tools/tandem-run" --duration "$secs" > "$out/run.log" 2>&1
kill -INT $logger; wait $logger
echo "mcap-test: recorded $(du -h "$out/run.lcmlog" | cut -f1) in $secs s of tools/tandem-run"

convert_all() {
    "$conv" "$out/run.lcmlog" "$out/run.mcap" > "$out/convert.log" &&
        "$py" "$here/tools/mcap/mcap_check.py" "$out/run.lcmlog" "$out/run.mcap"
}
check "every channel converted and decoded back" convert_all

# a log cut inside an event: exit 1, the damage named, the events before it kept
truncated() {
    local size cut rc
    size=$(stat -c %s "$out/run.lcmlog"); cut=$((size / 2))
    head -c "$cut" "$out/run.lcmlog" > "$out/cut.lcmlog"
    "$conv" --no-geometry "$out/cut.lcmlog" "$out/cut.mcap" > "$out/cut.log" 2> "$out/cut.err"; rc=$?
    cat "$out/cut.err"
    [ $rc -eq 1 ] && grep -q "damaged at byte" "$out/cut.err" &&
        "$py" - "$out/cut.lcmlog" "$out/cut.mcap" "$here/tools/mcap" <<'PY'
import sys
from mcap.reader import make_reader
sys.path.insert(0, sys.argv[3])
import lcmlog
n = 0
try:
    for _ in lcmlog.events(open(sys.argv[1], "rb")):
        n += 1
except lcmlog.LogError:
    pass
with open(sys.argv[2], "rb") as f:
    m = sum(make_reader(f).get_summary().statistics.channel_message_counts.values())
print(f"truncated log: {n} whole events before the cut, {m} in the MCAP file")
sys.exit(0 if n == m and n > 0 else 1)
PY
}
check "truncated log" truncated
foreign() {
    head -c 4096 /dev/urandom > "$out/foreign.lcmlog"
    ! "$conv" "$out/foreign.lcmlog" "$out/foreign.mcap" 2> "$out/foreign.err" >/dev/null &&
        grep -q "not an lcm-logger file" "$out/foreign.err" && cat "$out/foreign.err"
}
check "not a log" foreign

# the file's structure: the Go mcap CLI's doctor when it can be had, and
# always tools/mcap/mcap_doctor.py (the same checks on the mcap package's
# records), which must also refuse a damaged copy
pydoctor() { "$py" "$here/tools/mcap/mcap_doctor.py" "$out/run.mcap" | tail -4; }
check "MCAP structure (mcap_doctor.py)" pydoctor
doctor_refuses() {
    "$py" - "$out/run.mcap" "$here/tools/mcap" <<'PY'
import struct, sys
sys.path.insert(0, sys.argv[2])
import mcap_doctor as md
buf = open(sys.argv[1], "rb").read()
recs = [(off, op) for off, op, _, _ in md.records(buf, 8, len(buf) - 8)]
chunk = next(off for off, op in recs if op == md.Opcode.CHUNK)
stats = next(off for off, op in recs if op == md.Opcode.STATISTICS)
cases = {"a byte of the first chunk flipped": (chunk + 80, None),
         "Statistics.message_count one short": (stats + 9, "count"),
         "cut in the middle": (len(buf) // 2, "cut")}
ok = True
for what, (at, how) in cases.items():
    bad = bytearray(buf)
    if how == "cut":
        bad = bad[:at]
    elif how == "count":
        struct.pack_into("<Q", bad, at, struct.unpack_from("<Q", buf, at)[0] - 1)
    else:
        bad[at] ^= 0xFF
    errs = md.examine(bytes(bad)).errors
    print(f"mcap_doctor on a copy with {what}: {len(errs)} errors, first: {errs[0] if errs else '-'}")
    ok = ok and bool(errs)
sys.exit(0 if ok else 1)
PY
}
check "mcap_doctor.py refuses damaged copies" doctor_refuses
mcap_cli=$(command -v mcap || echo "${GOPATH:-$HOME/go}/bin/mcap")
if [ ! -x "$mcap_cli" ] && command -v go >/dev/null; then
    go install github.com/foxglove/mcap/go/cli/mcap@latest >/dev/null 2>&1
fi
if [ -x "$mcap_cli" ]; then
    doctor() { "$mcap_cli" doctor "$out/run.mcap" > "$out/doctor.log" 2>&1; local rc=$?; tail -3 "$out/doctor.log"; [ $rc -eq 0 ]; }
    check "mcap doctor" doctor
else
    skipped=$((skipped + 1))
    echo "mcap-test: mcap doctor (Go) skipped: the Go mcap CLI is not installed and go install github.com/foxglove/mcap/go/cli/mcap@latest failed; mcap_doctor.py checked the structure"
fi
echo "mcap-test: $passed passed, $failed failed, $skipped skipped"
[ $failed -eq 0 ]
