#!/usr/bin/env bash
# The README's test command: install the project with its test extras, then run the whole suite.
# MAVProxy (a real third-party ground station used by the simulator tests) is installed without
# its GUI dependencies (opencv-python, vtk), which would clash with opencv-python-headless.
#
# The install is skipped when nothing it depends on changed since the last one with this
# interpreter: a stamp (.test-install-stamp, git-ignored) holds a hash of pyproject.toml, every
# file of the installed packages and the interpreter; a fresh clone has no stamp and installs.
# DIP3D_REINSTALL=1 forces the install. To run pytest alone on an installed tree:
#     python -m pytest [ARGS]        (e.g. python -m pytest tests/sitl -x)
set -euo pipefail
cd "$(dirname "$0")/.."
STAMP=.test-install-stamp
want=$(
  {
    python -c 'import sys; print(sys.executable, sys.version)'
    find pyproject.toml dip3d_vehicle behaviours sitl params -type f \
      ! -path '*/__pycache__/*' ! -name '*.pyc' -print0 | LC_ALL=C sort -z | xargs -0 sha256sum
  } | sha256sum | cut -d' ' -f1
)
have=$(cat "$STAMP" 2>/dev/null || true)
if [[ "${DIP3D_REINSTALL:-0}" != 1 && "$want" == "$have" ]] \
    && python -c 'import dip3d_vehicle, pytest, hypothesis, MAVProxy' 2>/dev/null; then
  echo "tools/test.sh: install up to date (stamp $STAMP); running pytest (DIP3D_REINSTALL=1 to reinstall)"
else
  python -m pip install --quiet --disable-pip-version-check ".[test]"
  python -m pip install --quiet --disable-pip-version-check --no-deps "MAVProxy>=1.8.70" pynmeagps pyserial
  echo "$want" > "$STAMP"
fi
python -m pytest "$@"
