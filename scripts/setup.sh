#!/usr/bin/env bash
# Installs dgmpm's build dependencies from Debian 12's packages (run as root); with --tests also
# what the test suite needs beyond them (python3-vtk9, to read the VTK output back; clang with
# libFuzzer and its OpenMP runtime, for the fuzz test; valgrind, whose callgrind counts the
# benchmark's flops: bench/count_flops.py).
set -euo pipefail
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
apt-get install -y -qq --no-install-recommends \
  g++ cmake make pkg-config \
  libeigen3-dev libarpack2-dev libgsl-dev libboost-test-dev \
  nlohmann-json3-dev libcli11-dev libopenmpi-dev openmpi-bin zlib1g-dev \
  python3 python3-matplotlib python3-numpy >/dev/null
if [ "${1:-}" = --tests ]; then
  apt-get install -y -qq --no-install-recommends python3-vtk9 \
    clang libclang-rt-14-dev libomp-14-dev valgrind >/dev/null
fi
