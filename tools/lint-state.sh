#!/usr/bin/env bash
# make lint, part 3: no state hidden at file scope. Every variable of src/
# that can change -- a non-const global or file-scope static, or a static
# inside a function -- is found from the compiled objects (what lands in
# .data, .bss or thread-local storage; const tables go to read-only
# sections, so `static const char *names[]`, whose pointers can be
# re-pointed, is caught and `static const char *const names[]` is not).
# State belongs in a struct its owner passes explicitly; the few that
# cannot be are listed in tools/lint-state.allow, each with its reason.
# An entry of the allow-list that no longer matches anything fails too.
# Usage: tools/lint-state.sh OBJDIR   (the objects of src/ built under it)
set -u
cd "$(dirname "$0")/.."
obj=${1:?usage: tools/lint-state.sh OBJDIR}
allow=tools/lint-state.allow
bad=0
declare -A allowed used
while read -r file name reason; do
    case $file in '#'* | '') continue;; esac
    if [ -z "$reason" ]; then
        echo "$allow: $file $name has no reason"; bad=1
    fi
    allowed["$file $name"]=1
done < "$allow"
for src in $(git ls-files 'src/*.c' 2>/dev/null || find src -name '*.c'); do
    o=$obj/${src%.c}.o
    if [ ! -f "$o" ]; then
        echo "$src: not compiled ($o missing): make lint builds it"; bad=1; continue
    fi
    # symbol table: "... l     O .bss	0000000000000004 name"
    for sym in $(objdump -t "$o" | awk '/ O \.(data|bss|tdata|tbss)/ && !/ O \.data\.rel\.ro/ { print $NF }'); do
        name=${sym%%.*}                       # a static local is name.N
        kind="a mutable file-scope variable"
        [ "$name" != "$sym" ] && kind="a mutable static local"
        if [ -n "${allowed["$src $name"]:-}" ]; then
            used["$src $name"]=1; continue
        fi
        line=$(grep -nE "\\b$name\\b" "$src" | head -1 | cut -d: -f1)
        echo "$src:${line:-1}: $name is $kind: put it in its owner's struct and pass that (or list it in $allow with the reason)"
        bad=1
    done
done
for k in "${!allowed[@]}"; do
    [ -n "${used[$k]:-}" ] || { echo "$allow: $k matches no variable any more: remove the entry"; bad=1; }
done
[ $bad -eq 0 ] && echo "lint: no mutable file-scope or static-local state in src/ beyond $allow"
exit $bad
