#!/usr/bin/env bash
# make budget: the three budget tables of the cross builds.
#   1. text/data/bss per core module, 68040 and Cortex-M4F (size(1))
#   2. worst-case stack of each per-cycle entry point (cross/budget/cycles.h)
#      from -fcallgraph-info=su (stack-depth.awk)
#   3. instructions of one cycle of each on the 68040, counted in a qemu
#      trace (count-insns.awk), and the time on a 25 MHz 68040
# Usage: budget.sh CROSS_DIR BUDGET_M68K_PROGRAM
set -euo pipefail
cross=$1 prog=$2
here=$(dirname "$0")
mhz=25
entries="budget_arm_joint_cycle budget_arm_cart_cycle budget_arm_tdsd_cycle budget_supervisor_step budget_rover_step"

echo "== memory per module (bytes; size of each object) =="
printf '%-12s %8s %6s %6s   %8s %6s %6s\n' module "m68k text" data bss "cm4 text" data bss
for o in "$cross"/m68k/core/*/*.o; do
    m=$(basename "$o" .o); d=$(basename "$(dirname "$o")")
    a=$(m68k-linux-gnu-size "$o" | awk 'NR == 2 { print $1, $2, $3 }')
    b=$(arm-none-eabi-size "$cross/cm4/core/$d/$m.o" | awk 'NR == 2 { print $1, $2, $3 }')
    echo "$m $a $b"
done | awk '{ printf "%-12s %8d %6d %6d   %8d %6d %6d\n", $1, $2, $3, $4, $5, $6, $7
              for (i = 2; i <= 7; i++) t[i] += $i }
            END { printf "%-12s %8d %6d %6d   %8d %6d %6d\n", "total", t[2], t[3], t[4], t[5], t[6], t[7] }'

echo
echo "== worst-case stack per cycle entry point (bytes, core call graph) =="
for t in m68k cm4; do
    awk -v entries="$entries" -f "$here/stack-depth.awk" "$cross/$t"/core/*/*.ci "$cross/$t"/budget/*.ci |
        awk -F'\t' -v t="$t" '{ sf = gsub(/__aeabi_[a-z0-9]+ ?/, "", $4); sub(/ $/, "", $4)
                                 if (sf) $4 = $4 " + soft-float double (__aeabi_d*)"
                                 printf "%-5s %-24s %7s  via %s\n", t, $1, $2, $3
                                 if ($4 != "") printf "      %-24s          + outside the analysis: %s\n", "", $4 }'
done

echo
echo "== one cycle on a ${mhz} MHz 68040 (instructions counted under qemu-m68k) =="
fifo=$(mktemp -u)
mkfifo -m 600 "$fifo"
out=$(mktemp)
trap 'rm -f "$fifo" "$out"' EXIT
probe=$(m68k-linux-gnu-nm "$prog" | awk '$3 == "budget_probe" { print $1 }')
qemu-m68k-static -cpu m68040 -singlestep -d in_asm,exec,nochain -D "$fifo" "$prog" >"$out" &
counts=$(awk -v probe="$probe" -v costs="$here/m68040-cycles.txt" -f "$here/count-insns.awk" "$fifo")
wait $! || { cat "$out" >&2; exit 1; }
# period of each region (s): tandem-arm 1 ms, tandem-supervisor 10 ms, tandem-rover 50 ms
printf '%-27s %8s %7s %5s %9s %9s %9s %7s  %s\n' cycle instr "FP" FPSP clocks "@20MIPS" "est." period fits
grep '^region' "$out" | sed 's/^region \([0-9]*\): /\1\t/' | join -t $'\t' - <(echo "$counts") |
    awk -F'\t' -v mhz=$mhz '
    { period = ($2 ~ /^arm/) ? 1e-3 : ($2 ~ /^supervisor/) ? 10e-3 : 50e-3
      lower = $3 / 20e6; est = $6 / (mhz * 1e6)
      if (est <= period) fits = sprintf("yes (%.0f%%)", 100 * est / period)
      else fits = sprintf("NO: %.1fx; fits a %d ms period", est / period, int(est * 1e3) + 1)
      printf "%-27s %8d %7d %5d %9d %7.3fms %7.3fms %5.0fms  %s\n", $2, $3, $4, $5, $6, lower * 1e3, est * 1e3,
             period * 1e3, fits }'
echo "instr: executed between the probes; FP: of them floating point; FPSP: FP instructions the"
echo "68040 traps to software. @20MIPS: instr at the 68040's rated integer rate (lower bound);"
echo "est.: clocks from cross/m68040-cycles.txt (cache hits) at $mhz MHz."
grep '^budget:' "$out"
