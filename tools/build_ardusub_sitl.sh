#!/usr/bin/env bash
# Build an ArduSub SITL binary (software in the loop) to fly dip3d-vehicle against the real firmware:
#   dip3d-vehicle sitl --ardusub build/ardusub-sitl/ardusub
#
# usage: tools/build_ardusub_sitl.sh [RELEASE_TAG] [OUT_DIR]
#   RELEASE_TAG  an ArduSub release tag of ArduPilot/ardupilot (default ArduSub-stable, the current stable
#                release; pin one, e.g. ArduSub-4.5.x, for reproducible builds: git ls-remote --tags
#                https://github.com/ArduPilot/ardupilot "ArduSub-*")
#   OUT_DIR      where ardusub, sub.parm and COPYING.txt go (default build/ardusub-sitl)
#
# It clones ArduPilot (GPLv3) at that tag with its submodules, configures `--board sitl` and builds
# `sub` (about 6 minutes and 1249 tasks on 2 cores; Debian 12 / Ubuntu 22.04+, g++, python3), then
# copies the stripped binary and the `vectored` frame's defaults (Tools/autotest/default_params/sub.parm).
# The binary is a test tool beside the project, never part of the package.
#
# NOTE: this script cannot run on the team's machines, which reach no source hosts (github.com etc.);
# the binary in ../shared/ardusub-sitl was built from a source snapshot instead (its README gives the
# commit and the exact steps: ArduSub 4.7.0-dev, upstream 90700977, --disable-networking). Run this
# script on a machine with internet access.
set -euo pipefail
TAG=${1:-ArduSub-stable}
OUT=${2:-build/ardusub-sitl}
WORK=$(mktemp -d -t ardupilot-XXXXXX)
trap 'rm -rf "$WORK"' EXIT
command -v git >/dev/null || { echo "build_ardusub_sitl: git is needed" >&2; exit 2; }
command -v g++ >/dev/null || { echo "build_ardusub_sitl: g++ is needed (apt install build-essential)" >&2; exit 2; }
echo "build_ardusub_sitl: cloning ArduPilot at $TAG into $WORK"
git clone --depth 1 --branch "$TAG" --recurse-submodules --shallow-submodules \
    https://github.com/ArduPilot/ardupilot.git "$WORK/ardupilot"
python3 -m venv "$WORK/venv"
"$WORK/venv/bin/pip" install --quiet empy==3.3.4 pexpect future pymavlink
cd "$WORK/ardupilot"
PATH="$WORK/venv/bin:$PATH" ./waf configure --board sitl
PATH="$WORK/venv/bin:$PATH" ./waf sub -j"$(nproc)"
cd - >/dev/null
mkdir -p "$OUT"
strip -o "$OUT/ardusub" "$WORK/ardupilot/build/sitl/bin/ardusub"
cp "$WORK/ardupilot/Tools/autotest/default_params/sub.parm" "$OUT/sub.parm"
cp "$WORK/ardupilot/COPYING.txt" "$OUT/COPYING.txt"
echo "build_ardusub_sitl: wrote $OUT/ardusub ($("$OUT/ardusub" --help >/dev/null 2>&1 && echo runs || echo 'check it runs'))"
echo "fly the mission against it: dip3d-vehicle sitl --ardusub $OUT/ardusub"
