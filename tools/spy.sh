#!/usr/bin/env bash
# lcm-spy with every tandem type decoded. Debian's lcm-spy wrapper passes
# -Xincgc, which Java 9+ rejects, so start the Spy class directly.
set -eu
jar=$1; shift || true
url=${LCM_DEFAULT_URL:-udpm://239.255.76.67:7667?ttl=0}
cp="/usr/share/java/lcm.jar:$jar"
[ -f /usr/share/java/jchart2d.jar ] && cp="$cp:/usr/share/java/jchart2d.jar"
exec java -Djava.net.preferIPv4Stack=true -cp "$cp" lcm.spy.Spy --lcm-url="$url" "$@"
