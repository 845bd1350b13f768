#!/usr/bin/env bash
# Set-up, then every test (ctest: C++ unit tests, CLI tests).
set -euo pipefail
cd "$(dirname "$0")/.."
MSS_STRICT=${MSS_STRICT:-ON} bash scripts/setup.sh
cd build
ctest --output-on-failure -j"$(nproc)"
