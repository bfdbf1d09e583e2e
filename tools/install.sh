#!/usr/bin/env bash
# make install: programs, the core library with its headers and a
# pkg-config file, the LCM types jar, tandem-log2mcap's Python modules
# (share/tandem/python), tandem-run and the viewer bridge, and man pages
# generated from each program's --help / --version with help2man.
#   tools/install.sh DESTROOT PREFIX BIN_DIR CORE_LIB TYPES_JAR MAN_BUILD_DIR
# DESTROOT is DESTDIR + PREFIX (where files go); PREFIX is what the
# pkg-config file names (where they will be found).
set -euo pipefail
dest=$1 prefix=$2 bin=$3 corelib=$4 jar=$5 mandir=$6
here=$(cd "$(dirname "$0")/.." && pwd)
# one-line summaries for the NAME section of each man page
declare -A what=(
    [tandem-sim]="ODE simulator of the PUMA 560 pair, work cell and Pioneer team, on LCM"
    [tandem-arm]="1 kHz computed-torque controller of one PUMA 560 arm"
    [tandem-supervisor]="Petri-net supervisor of the two-arm carry task"
    [tandem-rover]="behaviour-based formation controller of Pioneer robots"
    [tandem-kin]="PUMA 560 kinematics calculator (fk, jac, ik, grav)"
    [tandem-stick]="push the stick into an arm of a running tandem-sim, or pull it out"
    [tandem-log2csv]="turn an lcm-logger file of tandem messages into CSV"
    [tandem-log2mcap]="turn an lcm-logger file of tandem messages into MCAP for Foxglove"
    [tandem-scenario]="run a tandem experiment in lockstep and write summary, CSV and plots"
    [tandem-scene]="print the static geometry of the tandem world as JSON, or the cell as URDF"
    [tandem-status]="one status line a second about a running tandem system"
    [tandem-keygen]="make or rotate the tandem bus key (32 random bytes, mode 0600)"
    [tandem-run]="start the whole tandem cell on one LCM bus and keep it running"
)
install -d "$dest/bin" "$dest/lib/pkgconfig" "$dest/include/tandem" "$dest/share/java" "$dest/share/man/man1" "$mandir"
version=$(sed -n 's/^#define TANDEM_VERSION "\(.*\)"$/\1/p' "$here/build/gen/c/tandem_version.h")
for p in "$bin"/tandem-* "$here/tools/tandem-run"; do
    name=$(basename "$p")
    install -m 755 "$p" "$dest/bin/$name"
    help2man --no-info --no-discard-stderr --version-string="$version" \
        --name="${what[$name]:-part of tandem}" --output="$mandir/$name.1" "$p"
    install -m 644 "$mandir/$name.1" "$dest/share/man/man1/$name.1"
done
install -m 644 "$corelib" "$dest/lib/libtandem.a"
# the public headers, one folder per core domain as in the tree
# (include/tandem/<domain>/; the private *_internal.h stay in src/core/)
cflags=
for d in "$here"/include/tandem/*/; do
    d=$(basename "$d")
    install -d "$dest/include/tandem/$d"
    install -m 644 "$here/include/tandem/$d"/*.h "$dest/include/tandem/$d/"
    cflags="$cflags -I\${includedir}/tandem/$d"
done
install -m 644 "$jar" "$dest/share/java/tandem_types.jar"
# tandem-log2mcap's Python: its helpers, lcm-gen's decoders, the JSON schemas
py=$dest/share/tandem/python
install -d "$py/tandem"
install -m 644 "$here/tools/mcap/foxglove.py" "$here/tools/mcap/lcmlog.py" \
    "$here/build/gen/python/tandem_schemas.json" "$py/"
install -m 644 "$here/build/gen/python/tandem"/*.py "$py/tandem/"
# the browser viewer's bridge (tandem-run --view; its Python packages:
# tools/viewer/requirements.txt, with pip)
install -d "$dest/share/tandem/viewer"
install -m 644 "$here/tools/viewer"/*.py "$here/tools/viewer/requirements.txt" "$dest/share/tandem/viewer/"
cat > "$dest/lib/pkgconfig/tandem.pc" <<PC
prefix=$prefix
libdir=\${prefix}/lib
includedir=\${prefix}/include

Name: tandem
Description: tandem robot control core (PUMA 560 dynamics, Petri-net carry, TDSD, formation control), ISO C99
Version: $version
Libs: -L\${libdir} -ltandem
Libs.private: -lm
Cflags:$cflags
PC
echo "tandem: installed $(ls "$dest"/bin/tandem-* | wc -l) programs, man pages, libtandem.a, tandem.pc, tandem_types.jar and the viewer under $dest"
