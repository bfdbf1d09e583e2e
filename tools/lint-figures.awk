# make lint (tools/lint-docs.sh): every figure names its command. A section
# of a Markdown page (from a # or ## heading to the next; ### and below
# are parts of it) that gives a measured
# figure -- a decimal (0.028) in a table, a ratio (52/52), a percentage
# (38 %) or a factor (3.1x), outside code and backticks -- must
# also give, in the same section, the command that produced it: a command
# line in backticks or in a code block (fenced or indented) that starts
# with make TARGET,
# tandem-PROGRAM ARG..., build/bin/PROGRAM or tools/SCRIPT. A bare program
# name does not count: the reader must be able to run it.
# Usage: awk [-v strict=1] -f tools/lint-figures.awk PAGE.md...   (one line per
# section that fails; the caller decides the exit status from the output)
function is_cmd(c) {
    return c ~ /^make [a-z]/ || c ~ /^tandem-[a-z0-9]+ [^ ]/ ||
           c ~ /^build\/bin\/[a-z_0-9-]+/ || c ~ /^tools\/[a-z_0-9.-]+/
}
# a backticked span may run over a line break: what follows an unmatched
# backtick is carried to the next line (pend)
function commands_in(s) {
    s = pend s
    pend = ""
    while (match(s, /`[^`]+`/)) {
        if (is_cmd(substr(s, RSTART + 1, RLENGTH - 2)))
            cmd = 1
        s = substr(s, RSTART + RLENGTH)
    }
    if (gsub(/`/, "`", s) % 2 == 1)
        pend = substr(s, index(s, "`")) " "
}
function flush() {
    if (fig != "" && !cmd)
        printf "%s:%d: section \"%s\" gives a figure (%s) but no command that produced it (`make ...`, `tandem-<program> ...`, `build/bin/<program>`, `tools/<script>`)\n", FILENAME, figline, sec, fig
    fig = ""; cmd = 0
}
FNR == 1 { flush(); sec = "(top)"; fence = 0; pend = "" }
/^[[:space:]]*$/ { pend = "" }
/^```/ { fence = !fence; next }
fence { if (is_cmd($0)) cmd = 1; next }
/^    [^ *-]/ { c = $0; sub(/^ +/, "", c); if (is_cmd(c)) cmd = 1 }   # an indented code block
/^##?[^#]/ { flush(); sec = $0; sub(/^#+ */, "", sec); commands_in($0); next }
/^###/ { commands_in($0); next }   # a subsection is part of its section
{
    commands_in($0)
    line = $0
    gsub(/`[^`]*`/, "", line)          # names and commands, not figures
    gsub(/\]\([^)]*\)/, "]", line)     # link targets
    gsub(/§[0-9.]+/, "", line)         # section numbers of a method page
    gsub(/[0-9]+\.[0-9]+\.[0-9]+/, "", line)   # versions (LCM 1.3.1)
    # in prose, a decimal is often a parameter (d = 0.15 m): outside a
    # table only a ratio, percentage or factor counts, unless strict=1
    # (README.md: every number there is a headline figure)
    re = (strict || line ~ /^\|/) ? "[0-9]+\\.[0-9]+|[0-9]+/[0-9]+|[0-9]+ ?%|[0-9][0-9.]*x( |,|;|\\)|$)" \
                                 : "[0-9]+/[0-9]+|[0-9]+ ?%|[0-9][0-9.]*x( |,|;|\\)|$)"
    if (fig == "" && match(line, re)) {
        fig = substr(line, RSTART, RLENGTH); figline = FNR
    }
}
END { flush() }
