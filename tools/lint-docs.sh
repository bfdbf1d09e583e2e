#!/usr/bin/env bash
# make lint, part 2: docs that cannot drift. Every repository path, make
# target, function, channel and option that README.md or docs/ names in
# backticks (or a path anywhere) must exist in the tree:
#   paths      src/... include/... sim/... tools/... test/... bench/...
#              cross/... fuzz/... docs/... lcmtypes/... (globs and <...>
#              placeholders are skipped)
#   make X     a target of the Makefile or the files it includes
#   f()/name   an identifier with an underscore (function, constant,
#              type, field, summary.json key) found in the sources, the
#              message types or the scripts
#   CHANNEL    an upper-case name with an underscore found likewise
#              (names with a digit or a trailing _K are instances of a
#              pattern, ROVER3_SENSORS of ROVERk_SENSORS: skipped)
#   --option   an option some program or script defines
#   test_x     a test or tool program: a source file of that name
# and every figure of README.md and docs/*.md shares its section with the
# command that produced it (tools/lint-figures.awk).
# Names of other projects the docs discuss are listed in EXTERNAL.
# Usage: tools/lint-docs.sh  (exit 1 on the first file naming a missing thing)
set -u
cd "$(dirname "$0")/.."
docs=(README.md CONTRIBUTING.md $(git ls-files 'docs/*.md' 2>/dev/null || ls docs/*.md docs/*/*.md))
srcs=$(git ls-files -- src include sim tools test bench cross fuzz lcmtypes Makefile '*.mk' .ci 2>/dev/null)
words=$(mktemp); trap 'rm -f "$words"' EXIT
# every identifier-like word of the sources, once
grep -ohaIE '[A-Za-z_][A-Za-z0-9_]*' $srcs 2>/dev/null | sort -u > "$words"
targets=$(cat Makefile $(git ls-files '*.mk') | sed -n 's/^\([a-z][a-z0-9_-]*\)\( [a-z][a-z0-9_ -]*\)*:.*/\1 \2/p' | tr ' ' '\n' | sed '/^$/d' | sort -u)
# other projects' names the docs discuss (LCM's internals, POSIX, libsodium)
EXTERNAL=" SO_RCVBUF lcm_udpm lcm_get_handlers handlers_map sodium_malloc "
files=$(git ls-files | sed 's#.*/##; s#\.[a-z]*$##' | sort -u)
bad=0
say() { echo "$1: names $2, which $3"; bad=1; }
known() {
    grep -qx -- "$1" "$words" || grep -qx -- "$1" <<<"$files" || [[ $EXTERNAL == *" $1 "* ]]
}
for d in "${docs[@]}"; do
    [ -f "$d" ] || continue
    # repository paths, backticked or not
    for p in $(grep -ohE '(^|[^A-Za-z0-9_./-])(src|include|sim|tools|test|bench|cross|fuzz|docs|lcmtypes)/[A-Za-z0-9_./*<>{}-]*[A-Za-z0-9_/*>}]' "$d" \
               | sed -E 's/^[^a-z]//' | sort -u); do
        case $p in *'*'* | *'<'* | *'{'* | *'..'*) continue;; esac
        # a file (an extension) or a folder (a trailing /); "sim/wall" is a ratio
        case $p in */ | *.[a-z]*) ;; *) [ -d "$p" ] || continue;; esac
        [ -e "$p" ] || [ -e "${p%/}" ] || say "$d" "$p" "does not exist"
    done
    # backticked tokens
    for t in $(grep -oE '`[^`]+`' "$d" | tr -d '`' | tr ' ' '\n' | sed -E 's/[(),;:.]+$//; s/\(\)$//' | sort -u); do
        case $t in
            --[a-z]*)
                o=${t%%=*}; o=${o#--}
                grep -qE -- "(\"$o\"|--$o\b)" $srcs 2>/dev/null || say "$d" "option --$o" "no program defines";;
            [a-z]*_*[a-z0-9])
                [[ $t =~ ^[a-z][a-z0-9_]*$ ]] || continue
                known "$t" || say "$d" "\`$t\`" "is not in the sources";;
            [A-Z]*_*[A-Z0-9])
                [[ $t =~ ^[A-Z][A-Z_]*$ ]] && [[ ! $t =~ _K$ ]] || continue
                known "$t" || say "$d" "\`$t\`" "is not in the sources";;
        esac
    done
    # make targets
    for m in $(grep -oE '`make [a-z][a-z0-9/_-]*' "$d" | awk '{print $2}' | grep -v / | sort -u); do
        grep -qx -- "$m" <<<"$targets" || say "$d" "make $m" "is not a target"
    done
done
# every relative link of a page resolves from where the page is
for d in "${docs[@]}"; do
    [ -f "$d" ] || continue
    for l in $(grep -oE '\]\([^)#[:space:]]+' "$d" | sed 's/^](//' | grep -v '^http'); do
        [ -e "$(dirname "$d")/$l" ] || say "$d" "a link to $l" "does not resolve"
    done
done
# every figure of the README and of the result pages (docs/*.md; the
# method pages give parameters, not results) names the command that
# produced it (tools/lint-figures.awk: per section, a command line beside
# the figures; in the README every number is a figure)
figs=$(awk -v strict=1 -f tools/lint-figures.awk README.md
       awk -f tools/lint-figures.awk $(git ls-files 'docs/*.md' ':!docs/method' 2>/dev/null || ls docs/*.md))
[ -z "$figs" ] || { echo "$figs"; bad=1; }
[ $bad -eq 0 ] && echo "lint: every path, target, name, option and link the docs cite exists; every figure of README and docs/ names its command"
exit $bad
