# stack-depth.awk: worst-case stack depth of entry points from GCC's
# -fcallgraph-info=su files (.ci: one node per function with its frame in
# bytes, one edge per call site). Depth of f = frame(f) + max over callees.
# Functions with no frame in the files (libm, libgcc, libc) are leaves
# outside the analysis; they are listed, not guessed. A static function
# defined in two files under one name counts its larger frame. Recursion
# or an indirect call makes the depth unbounded: reported as such.
#   awk -v entries="f g" -f stack-depth.awk build/.../*.ci
# Prints: entry <tab> bytes <tab> deepest path <tab> outside leaves
/^node:/ {
    name = $0; sub(/.*title: "/, "", name); sub(/".*/, "", name)
    if (match($0, /\\n[0-9]+ bytes/)) {
        b = substr($0, RSTART + 2, RLENGTH - 2) + 0
        if (!(name in frame) || b > frame[name]) frame[name] = b
    }
    if (name == "__indirect_call") indirect = 1
}
/^edge:/ {
    s = $0; sub(/.*sourcename: "/, "", s); sub(/".*/, "", s)
    t = $0; sub(/.*targetname: "/, "", t); sub(/".*/, "", t)
    if (!((s, t) in seen)) { seen[s, t] = 1; callees[s] = callees[s] " " t }
}
function depth(f,    n, i, c, d, best) {
    if (f in memo) return memo[f]
    if (f in onpath) { unbounded = unbounded " " f; return 0 }
    if (!(f in frame)) { outside[f] = 1; memo[f] = 0; path[f] = f "()"; return 0 }
    onpath[f] = 1
    best = -1; path[f] = f
    n = split(callees[f], c, " ")
    for (i = 1; i <= n; i++) {
        d = depth(c[i])
        if (d > best) { best = d; path[f] = f " > " path[c[i]] }
    }
    delete onpath[f]
    memo[f] = frame[f] + (best > 0 ? best : 0)
    return memo[f]
}
END {
    n = split(entries, e, " ")
    for (i = 1; i <= n; i++) {
        split("", outside); unbounded = ""
        if (!(e[i] in frame)) { printf "%s\tmissing\t-\t-\n", e[i]; continue }
        d = depth(e[i])
        # leaves reached from this entry (memo is shared: walk again)
        split("", vis); leaves = ""; reach(e[i])
        if (unbounded != "" || indirect) printf "%s\tunbounded\t%s\t%s\n", e[i], unbounded, leaves
        else printf "%s\t%d\t%s\t%s\n", e[i], d, path[e[i]], leaves
    }
}
function reach(f,    n, i, c) {
    if (f in vis) return
    vis[f] = 1
    if (!(f in frame)) { leaves = leaves (leaves == "" ? "" : " ") f; return }
    n = split(callees[f], c, " ")
    for (i = 1; i <= n; i++) reach(c[i])
}
