#!/usr/bin/env bash
# Installs dependencies, builds, and runs every test (unit, integration, fault) with CTest.
set -euo pipefail
cd "$(dirname "$0")/../.."
# Each phase's wall time on stderr, so a CI log shows where its time went.
phase() { echo "run_tests: $1 done at $((SECONDS / 60)) min $((SECONDS % 60)) s" >&2; }
# Warnings are errors here, so no new warning lands.
FLEETLOC_WERROR=ON tools/scripts/setup.sh
phase "install and build"
# clang-format (.clang-format) over every tracked C++ file; a file it would change fails.
tools/scripts/check_format.sh
phase "format check"
ctest --test-dir build --output-on-failure -j "$(nproc)" --timeout 600
phase "tests"
# clang-tidy (.clang-tidy) over the C++ sources the last change touched; any finding fails.
tools/scripts/check_tidy.sh
phase "tidy check"
# Every decoder of outside input under libFuzzer (ASan + UBSan) for a short while; any crash fails.
FLEETLOC_FUZZ_SECONDS="${FLEETLOC_FUZZ_SECONDS:-20}" tools/scripts/run_fuzz.sh
phase "fuzzing"
