#!/usr/bin/env bash
# Installs the Debian packages tandem needs (apt-get when root; otherwise
# prints the exact command and stops). A no-op when everything is present.
#   tools/deps.sh run     build, run and test
#   tools/deps.sh bench   also the benchmark-only tools
#   tools/deps.sh cross   the 68040 and Cortex-M4 toolchains and qemu (make cross,
#                         test-cross, budget; make test installs them too)
#   tools/deps.sh fuzz    clang and its runtimes (libFuzzer, sanitizers) for make fuzz
#   tools/deps.sh analyze cppcheck and clang-format (make analyze, format-check)
#   tools/deps.sh tidy    clang-tidy (make tidy)
#   tools/deps.sh view    the viewer's Python venv; view-test: also Chromium and tesseract (OCR)
#   tools/deps.sh install man pages (help2man)
set -euo pipefail
pkgs=(build-essential pkg-config libode-dev liblcm-dev liblcm-bin liblcm-java
      libccd-dev libcmocka-dev libglib2.0-dev default-jdk-headless gnuplot-nox
      libjchart2d-java python3 libsodium-dev libyaml-dev libxml2-dev)
if [ "${1:-run}" = bench ]; then
    pkgs=(rt-tests valgrind liborocos-kdl-dev g++)
elif [ "${1:-run}" = cross ]; then
    pkgs=(gcc-m68k-linux-gnu libc6-dev-m68k-cross gcc-arm-none-eabi libnewlib-arm-none-eabi
          qemu-user-static binutils)
fi
case ${1:-run} in
    fuzz) pkgs=(clang libclang-rt-14-dev) ;;   # libFuzzer and the sanitizers' runtimes
    coverage) pkgs=(gcovr) ;;
    analyze) pkgs=(cppcheck clang-format) ;;
    tidy) pkgs=(clang-tidy) ;;
    view) pkgs=(python3-venv) ;;
    view-test) pkgs=(python3-venv chromium fonts-dejavu-core iproute2 tesseract-ocr tesseract-ocr-eng) ;;
    install) pkgs=(help2man man-db) ;;
esac
missing=()
for p in "${pkgs[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0
cmd="apt-get install -y --no-install-recommends ${missing[*]}"
if [ "$(id -u)" -ne 0 ]; then
    echo "tandem: missing Debian packages: ${missing[*]}" >&2
    echo "tandem: install them with:  sudo apt-get update && sudo $cmd" >&2
    exit 1
fi
echo "tandem: installing ${missing[*]}" >&2
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq >/dev/null
$cmd >/dev/null
