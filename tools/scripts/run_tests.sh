#!/usr/bin/env bash
# Installs dependencies, builds, and runs every test (unit, integration, fault) with CTest.
set -euo pipefail
cd "$(dirname "$0")/../.."
tools/scripts/setup.sh
ctest --test-dir build --output-on-failure -j "$(nproc)" --timeout 600
