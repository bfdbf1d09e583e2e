#!/usr/bin/env bash
# make lint: the rules the build also enforces, checked from the sources so
# that a violation is named even where no compile reaches it.
#   1. layering: a core/<d> file includes only headers of the domains
#      LAYER_<d> in core/layers.mk lists (quoted includes), and
#   2. the core reaches no POSIX or stdio header (CORE_FORBIDDEN, cross.mk);
#   3. no tracked file cites a specification outside the repository or
#      holds an absolute path of a development machine.
# Usage: tools/lint.sh "base:base" "arm:base arm" ... -- FORBIDDEN_HEADER...
set -u
cd "$(dirname "$0")/.."
declare -A allowed
while [ $# -gt 0 ] && [ "$1" != -- ]; do allowed[${1%%:*}]=${1#*:}; shift; done
shift
forbidden=("$@")
bad=0
home_of() { local h; h=$(ls core/*/"$1" 2>/dev/null | head -1); [ -n "$h" ] && basename "$(dirname "$h")"; }
for d in "${!allowed[@]}"; do
    for f in core/"$d"/*.[ch]; do
        while IFS= read -r line; do
            n=${line%%:*}; inc=$(sed 's/.*#include *[<"]\([^>"]*\)[>"].*/\1/' <<<"$line")
            for x in "${forbidden[@]}"; do
                if [ "$inc" = "$x" ]; then
                    echo "$f:$n: core reaches <$inc>: the core is ISO C99 + libm only (cross/cross.mk CORE_FORBIDDEN)"; bad=1
                fi
            done
            o=$(home_of "$inc") || continue
            case " ${allowed[$d]} " in *" $o "*) ;; *)
                echo "$f:$n: layering: core/$d may include only core/{${allowed[$d]}} (core/layers.mk); $inc is in core/$o"; bad=1;;
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
[ $bad -eq 0 ] && echo "lint: layering, core headers and references ok"
exit $bad
