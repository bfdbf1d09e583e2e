#!/usr/bin/env bash
# Fails if the core library calls anything outside what a bare board gives
# it: C99 <math.h>, the <string.h> block functions, the platform clock
# (include/tandem/base/rtclock.h) and the compiler's own runtime (__*: soft-float,
# 64-bit division; sincos: GCC fuses a sin and cos of one angle into it),
# so a malloc, printf or POSIX call shows up here even if its header was
# not included. Usage: check-core-calls.sh NM LIB.a
set -euo pipefail
nm=$1 lib=$2
allowed='^(__.*|mem(cpy|set|move|cmp)|str(len|cmp|ncmp)|rtclock_(now|sleep_until)_ns|'
allowed+='(sin|cos|tan|asin|acos|atan|atan2|sinh|cosh|tanh|exp|exp2|expm1|log|log2|log10|log1p|'
allowed+='sincos|pow|sqrt|cbrt|hypot|fabs|floor|ceil|round|lround|trunc|rint|lrint|fmod|remainder|'
allowed+='fmin|fmax|fdim|copysign|nextafter|frexp|ldexp|modf|scalbn)f?)$'
defined=$("$nm" --defined-only -g "$lib" 2>/dev/null | awk 'NF == 3 { print $3 }' | sort -u)
undefined=$("$nm" -u "$lib" 2>/dev/null | awk 'NF == 2 { print $2 }' | sort -u)
bad=$(comm -23 <(echo "$undefined") <(echo "$defined") | grep -Ev "$allowed" || true)
if [ -n "$bad" ]; then
    echo "$lib: the core calls outside libm/string.h/rtclock: $(echo $bad)" >&2
    exit 1
fi
