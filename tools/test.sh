#!/usr/bin/env bash
# The README's test command: install the project with its test extras, then run the whole suite.
# MAVProxy (a real third-party ground station used by the simulator tests) is installed without
# its GUI dependencies (opencv-python, vtk), which would clash with opencv-python-headless.
set -euo pipefail
cd "$(dirname "$0")/.."
python -m pip install --quiet --disable-pip-version-check ".[test]"
python -m pip install --quiet --disable-pip-version-check --no-deps "MAVProxy>=1.8.70" pynmeagps pyserial
python -m pytest "$@"
