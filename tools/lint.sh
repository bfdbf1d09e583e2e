#!/usr/bin/env bash
# make lint: the rules the build also enforces, checked from the sources so
# that a violation is named even where no compile reaches it.
#   1. layering: a file of core domain <d> (src/core/<d>/, include/tandem/<d>/)
#      includes only headers of the domains LAYER_<d> in src/core/layers.mk
#      lists (quoted includes); a private header (src/core/<o>/) only from
#      its own domain's sources, never from a public header, and
#   2. the core reaches no POSIX or stdio header (CORE_FORBIDDEN, cross.mk);
#   3. no tracked file cites a specification outside the repository or
#      holds an absolute path of a development machine;
#   4. no two error codes of one header share a value, and
#   5. every error code has a text in its module's code list.
# Usage: tools/lint.sh "base:base" "arm:base arm" ... -- FORBIDDEN_HEADER...
set -u
cd "$(dirname "$0")/.."
declare -A allowed
while [ $# -gt 0 ] && [ "$1" != -- ]; do allowed[${1%%:*}]=${1#*:}; shift; done
shift
forbidden=("$@")
bad=0
# the domain whose header it is (public: include/tandem/<o>, private:
# src/core/<o>, private ones marked with a trailing "*")
home_of() {
    local h
    h=$(ls include/tandem/*/"$1" 2>/dev/null | head -1)
    [ -n "$h" ] && { basename "$(dirname "$h")"; return 0; }
    h=$(ls src/core/*/"$1" 2>/dev/null | head -1)
    [ -n "$h" ] && { echo "$(basename "$(dirname "$h")")*"; return 0; }
    return 1
}
for d in "${!allowed[@]}"; do
    for f in src/core/"$d"/*.[ch] include/tandem/"$d"/*.h; do
        [ -e "$f" ] || continue
        while IFS= read -r line; do
            n=${line%%:*}; inc=$(sed 's/.*#include *[<"]\([^>"]*\)[>"].*/\1/' <<<"$line")
            for x in "${forbidden[@]}"; do
                if [ "$inc" = "$x" ]; then
                    echo "$f:$n: core reaches <$inc>: the core is ISO C99 + libm only (cross/cross.mk CORE_FORBIDDEN)"; bad=1
                fi
            done
            o=$(home_of "$inc") || continue
            case $o in
                "$d*") case $f in include/*)
                    echo "$f:$n: a public header includes the private $inc (src/core/$d): a program linking libtandem would not find it"; bad=1;;
                   esac;;
                *"*") echo "$f:$n: layering: $inc is private to src/core/${o%\*} (only its own domain includes it)"; bad=1;;
                *) case " ${allowed[$d]} " in *" $o "*) ;; *)
                    echo "$f:$n: layering: src/core/$d may include only include/tandem/{${allowed[$d]}} (src/core/layers.mk); $inc is in include/tandem/$o"; bad=1;;
                   esac;;
            esac
        done < <(grep -n '^[[:space:]]*#[[:space:]]*include' "$f")
    done
done
# outside references: the method docs are docs/method/, not a spec beside
# the checkout; no tracked file names a directory beside the checkout
# (../<sibling>/), the directory the checkout sits in, or a home directory
if git rev-parse --git-dir >/dev/null 2>&1; then
    here=$(pwd -P); above=$(dirname "$here")
    refs=$(git grep -nI -E -e 'SPEC\.md' -e '/home/[a-z]' -e '/root/' -e '/Users/' -- . ':!tools/lint.sh' || true)
    # the directory the checkout sits in and the ones beside it, unless
    # that is a shared place (/, a temp directory) where anything may stand
    case $above in
        / | /tmp | /var/tmp | "${TMPDIR:-/tmp}") ;;
        *) fixed=(-e "$above/")
           for s in "$above"/*/; do
               s=$(basename "$s"); [ "$s" = "$(basename "$here")" ] || fixed+=(-e "../$s/")
           done
           refs="$refs$(git grep -nI -F "${fixed[@]}" -- . ':!tools/lint.sh' || true)" ;;
    esac
    if [ -n "$refs" ]; then
        echo "$refs" | sed 's/$/   <- a reference outside the repository/'; bad=1
    fi
fi
# The *_ERR_* codes a header defines, one "VALUE NAME" a line: a
# #define NAME (-N) (a line clang-format continued with "\" joined first)
# or an enumerator NAME = -N (one a line, or several).
err_codes() {
    local text
    text=$(sed -e ':a' -e '/\\$/{N; s/\\\n[[:space:]]*/ /; ba' -e '}' "$1")
    sed -nE 's/^#[[:space:]]*define[[:space:]]+([A-Z][A-Z0-9_]*_ERR_[A-Z0-9_]+)[[:space:]]+\(?(-?[0-9]+)\)?([[:space:]].*)?$/\2 \1/p' <<<"$text"
    grep -oE '\b[A-Z][A-Z0-9_]*_ERR_[A-Z0-9_]+[[:space:]]*=[[:space:]]*\(?-?[0-9]+' <<<"$text" |
        sed -E 's/^([A-Z0-9_]+)[[:space:]]*=[[:space:]]*\(?(-?[0-9]+)$/\2 \1/'
}
# 4. error codes say what failed: no two *_ERR_* names of one module (the
#    prefix before _ERR_) in one header share a value (a caller could not
#    tell them apart)
if git rev-parse --git-dir >/dev/null 2>&1; then
    dups=$(for h in $(git ls-files '*.h' ':!third_party'); do
               err_codes "$h" |
               awk -v h="$h" '{ m = $2; sub(/_ERR_.*/, "", m); k = m " " $1
                                if (k in n) print h ": " n[k] " and " $2 " are both " $1; else n[k] = $2 }'
           done)
    if [ -n "$dups" ]; then
        echo "$dups" | sed 's/$/   <- error codes must be distinct/'; bad=1
    fi
fi
# 5. ... and say it in words: every *_ERR_* name a header of include/tandem,
#    src/, sim/ or tools/scenario defines has a text in a code list
#    (X(NAME, "text"), include/tandem/base/status.h), which the module's
#    strerror is made from (STATUS_STRERROR): no hand-written switch
if git rev-parse --git-dir >/dev/null 2>&1; then
    coded=('include/*.h' 'src/*.h' 'sim/*.h' 'tools/scenario/*.h')
    texts=$(git grep -hoE 'X\([[:space:]]*[A-Z][A-Z0-9_]*_ERR_[A-Z0-9_]+' -- 'include/*.[ch]' 'src/*.[ch]' \
                'sim/*.[ch]' 'tools/scenario/*.[ch]' | sed -E 's/^X\([[:space:]]*//' | sort -u)
    for h in $(git ls-files "${coded[@]}"); do
        for name in $(err_codes "$h" | cut -d' ' -f2); do
            grep -qx "$name" <<<"$texts" ||
                { echo "$h: $name has no text: add it to its module's code list (<domain>_status.h)"; bad=1; }
        done
    done
fi
[ $bad -eq 0 ] && echo "lint: layering, core headers, references and error codes (distinct, each with its text) ok"
exit $bad
