#!/usr/bin/env bash
# Installs dgmpm's build dependencies from Debian 12's packages (run as root).
set -euo pipefail
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
apt-get install -y -qq --no-install-recommends \
  g++ cmake make pkg-config \
  libeigen3-dev libarpack2-dev libgsl-dev libboost-test-dev \
  nlohmann-json3-dev libcli11-dev python3 python3-matplotlib python3-numpy >/dev/null
