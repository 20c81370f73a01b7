#!/usr/bin/env bash
# Installs the Debian packages fovsim needs (only the missing ones; idempotent, no prompts),
# then configures and builds. Usage:
#   scripts/setup.sh               # build/ (RelWithDebInfo)
#   scripts/setup.sh --sanitize    # build-asan/ (ASan + UBSan, Debug)
#   scripts/setup.sh --cluster     # only the packages of the cluster tests (ctest -L slurm); no build
#   scripts/setup.sh --fuzz        # build-fuzz/: the libFuzzer targets only (clang, ASan + UBSan; tests/fuzz)
set -euo pipefail
cd "$(dirname "$0")/.."

# The cluster tests (tests/cluster, docs/cluster.md) start a one-node Slurm of their own; without
# systemd (or runlevel) the packages' init scripts start nothing. GNU parallel: the jobs-file sweep.
cluster_packages=(slurmctld slurmd slurm-client munge parallel)

packages=(
  build-essential cmake pkg-config
  libegl-dev libegl-mesa0 libgl1-mesa-dri libgl-dev libepoxy-dev   # headless GL: EGL + llvmpipe
  libglfw3-dev                                                      # the interactive viewer
  xvfb xauth                                                        # tests: the viewer under a virtual X server
  libopenexr-dev openexr openimageio-tools                          # EXR output + external readers for tests
  ffmpeg                                                            # compare --video (the program); tests: ffprobe, EXR decoding
  chromium                                                          # tests only: report.html in headless Chromium (big)
  libtinygltf-dev nlohmann-json3-dev libstb-dev                     # glTF 2.0
  libcjson-dev                                                      # scene files
  zlib1g-dev                                                        # PNG export (FovVideoVDP input)
  python3 python3-numpy python3-openimageio                         # tests: bench JSON, EXR layers (test_taa_fidelity)
  gnuplot-nox                                                       # bench --accuracy: the accuracy-vs-time plot
  parallel                                                          # tests: a sweep's jobs file through GNU parallel
)
if [ "${1:-}" = "--fuzz" ]; then
  packages+=(clang libclang-rt-14-dev)                              # libFuzzer + the sanitizer runtimes
fi

[ "${1:-}" != "--cluster" ] || packages=("${cluster_packages[@]}")

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

if [ "${1:-}" = "--cluster" ]; then
  exit 0
elif [ "${1:-}" = "--fuzz" ]; then
  cmake -S . -B build-fuzz -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=Debug \
        -DFOVSIM_FUZZ=ON >/dev/null
  cmake --build build-fuzz --target fuzz -j"$(nproc)"
elif [ "${1:-}" = "--sanitize" ]; then
  cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Debug -DFOVSIM_SANITIZE=ON -DFOVSIM_WERROR=ON >/dev/null
  cmake --build build-asan -j"$(nproc)"
else
  cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo -DFOVSIM_WERROR=ON >/dev/null
  cmake --build build -j"$(nproc)"
fi
