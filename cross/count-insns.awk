# count-insns.awk: instructions executed between pairs of probe calls in a
# qemu-m68k trace taken with one instruction per translation block
# (-singlestep -d in_asm,exec,nochain): every "Trace" line is one executed
# instruction, its PC the second field of the bracket; the "IN:" listing
# before it gives the mnemonic at that PC. The k-th region runs from the
# (2k-1)-th entry into budget_probe to the 2k-th (the probe's own rts and
# the call of the closing probe, about 4 instructions, are included).
#   awk -v probe=HEXPC -v costs=m68040-cycles.txt -f count-insns.awk TRACE
# Prints per region: instructions, FP instructions, FPSP-trapped ones,
# estimated clocks (costs table).
BEGIN {
    while ((getline line < costs) > 0) {
        if (line ~ /^#/ || line == "") continue
        split(line, f, "\t"); nc++; pat[nc] = f[1]; clk[nc] = f[2]; what[nc] = f[3]
    }
    probe = tolower(probe); sub(/^0+/, "", probe)
}
/^0x[0-9a-f]+:/ { pc = substr($1, 3, length($1) - 3); sub(/^0+/, "", pc); op[pc] = $2; next }
/^Trace/ {
    split($4, b, "/"); pc = b[2]; sub(/^0+/, "", pc)
    if (pc == probe) { hits++; return_region = int((hits + 1) / 2); on = hits % 2; if (on) region = return_region; next }
    if (!on) next
    m = op[pc]
    if (!(m in cls)) for (i = 1; i <= nc; i++) if (m ~ pat[i]) { cls[m] = i; break }
    n[region]++
    cyc[region] += clk[cls[m]]
    if (m ~ /^f/) fp[region]++
    if (what[cls[m]] ~ /FPSP/) fpsp[region]++
}
END {
    for (r = 1; r <= int(hits / 2); r++)
        printf "%d\t%d\t%d\t%d\t%d\n", r, n[r], fp[r], fpsp[r], cyc[r]
}
