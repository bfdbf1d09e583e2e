#!/usr/bin/env bash
# Fails unless every file given is a big-endian 32-bit m68k ELF executable,
# so test-cross cannot pass by running host binaries. Prints the header of
# the first one as evidence. Usage: check-elf.sh FILE...
set -euo pipefail
first=1
for f in "$@"; do
    h=$(LC_ALL=C readelf -h "$f")
    grep -q 'Class:.*ELF32' <<<"$h" && grep -q 'Data:.*big endian' <<<"$h" &&
        grep -q 'Machine:.*MC68000' <<<"$h" && grep -q 'Type:.*EXEC' <<<"$h" ||
        { echo "$f: not a big-endian m68k ELF executable" >&2; exit 1; }
    if [ $first = 1 ]; then
        echo "$(basename "$f"): $(grep -E 'Class|Data|Machine|Type' <<<"$h" | awk -F: '{gsub(/^ +/, "", $2); printf "%s; ", $2}')"
        first=0
    fi
done
echo "check-elf: $# test programs are big-endian m68k ELF executables"
