#!/usr/bin/env bash
# README command 1: install dependencies, build, and run the main job on its built-in example.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
# The main job: discrepancy diagnosis of a built-in simulated plant (no files needed).
"${BUILD_DIR:-build}"/apps/sets-diagnose/sets-diagnose --example "$@"
