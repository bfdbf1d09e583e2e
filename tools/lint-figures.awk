# make lint (tools/lint-docs.sh): every figure names its command. A section
# of a Markdown page (from one heading to the next) that gives a measured
# figure -- a decimal (0.028), a ratio (52/52), a percentage (38 %) or a
# factor (3.1x), in a table or in prose, outside code and backticks -- must
# also give, in the same section, the command that produced it: a command
# line in backticks or in a code block that starts with make TARGET,
# tandem-PROGRAM ARG..., build/bin/PROGRAM or tools/SCRIPT. A bare program
# name does not count: the reader must be able to run it.
# Usage: awk -f tools/lint-figures.awk PAGE.md...   (prints one line per
# section that fails; the caller decides the exit status from the output)
function is_cmd(c) {
    return c ~ /^make [a-z]/ || c ~ /^tandem-[a-z0-9]+ [^ ]/ ||
           c ~ /^build\/bin\/[a-z_0-9-]+/ || c ~ /^tools\/[a-z_0-9.-]+/
}
function commands_in(s) {
    while (match(s, /`[^`]+`/)) {
        if (is_cmd(substr(s, RSTART + 1, RLENGTH - 2)))
            cmd = 1
        s = substr(s, RSTART + RLENGTH)
    }
}
function flush() {
    if (fig != "" && !cmd)
        printf "%s:%d: section \"%s\" gives a figure (%s) but no command that produced it (`make ...`, `tandem-<program> ...`, `build/bin/<program>`, `tools/<script>`)\n", FILENAME, figline, sec, fig
    fig = ""; cmd = 0
}
FNR == 1 { flush(); sec = "(top)"; fence = 0 }
/^```/ { fence = !fence; next }
fence { if (is_cmd($0)) cmd = 1; next }
/^#/ { flush(); sec = $0; sub(/^#+ */, "", sec); commands_in($0); next }
{
    commands_in($0)
    line = $0
    gsub(/`[^`]*`/, "", line)          # names and commands, not figures
    gsub(/\]\([^)]*\)/, "]", line)     # link targets
    gsub(/§[0-9.]+/, "", line)         # section numbers of a method page
    if (fig == "" && match(line, /[0-9]+\.[0-9]+|[0-9]+\/[0-9]+|[0-9]+ ?%|[0-9]x( |,|;|\)|$)/)) {
        fig = substr(line, RSTART, RLENGTH); figline = FNR
    }
}
END { flush() }
