#!/usr/bin/env bash
# ./build.sh test    install missing Debian packages, build into build/, run ctest
# ./build.sh report  the same set-up (and python3-matplotlib, python3-markdown for the figures), then
#                    the main job: build/bin/ldlpgs report (writes report/index.md and index.html)
# ./build.sh build   set-up and build only
# Environment: BUILD_DIR (default build), SANITIZE=1 (AddressSanitizer + UBSan build),
#              JOBS (default: number of cores).
set -euo pipefail
cd "$(dirname "$0")"
cmd=${1:-test}
shift || true

packages=(cmake g++ make libsuitesparse-dev libmetis-dev libeigen3-dev libgtest-dev
          libbenchmark-dev nlohmann-json3-dev libcli11-dev pkg-config
          libmujoco-dev libqhull-dev libmujoco-samples libode-dev libbullet-dev
          pybind11-dev python3-dev python3-numpy python3-scipy python3-pytest python3-matplotlib
          libopenblas0-serial)
# (pybind11 and python3-*: the Python module, python/, its pytest suite and the example script
# examples/compare_orderings.py, which draws with matplotlib)
# (libqhull-dev: Debian's mujocoConfig.cmake names /usr/include/libqhull_r/ and fails without it)
# (libopenblas0-serial: an optimized BLAS/LAPACK, one thread, registered as the libblas.so.3 and
# liblapack.so.3 alternative above the reference libblas3 that libsuitesparse-dev pulls in, so
# that CHOLMOD supernodal is timed as on a user's machine: issue 13 measured it on bcsstk13 2.3x
# slower than ours with the reference BLAS, 1.3x faster with OpenBLAS (papers/factor.md has ours);
# `ldlpgs bench` prints the BLAS in use)

install_missing() {
  local missing=()
  for p in "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  if ((${#missing[@]})); then
    echo "build.sh: installing ${missing[*]}"
    local sudo=""
    [ "$(id -u)" -eq 0 ] || sudo="sudo"
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
  fi
}

build() {
  install_missing "${packages[@]}"
  local dir=${BUILD_DIR:-build}
  # Release (-O3) is what every timing in README and papers/ was taken with: GCC vectorizes the
  # kernels only there (papers/factor.md). Sanitized builds are for the tests: debug info for
  # their reports, and no benchmarks, since timings under ASan mean nothing.
  local sanitize=OFF bench=ON type=Release
  if [ "${SANITIZE:-0}" = 1 ]; then sanitize=ON; bench=OFF; type=RelWithDebInfo; fi
  cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=$type -DLDLPGS_SANITIZE=$sanitize -DLDLPGS_BUILD_BENCH=$bench -DLDLPGS_REQUIRE_PEERS=ON
  cmake --build "$dir" -j "${JOBS:-$(nproc)}"
}

case "$cmd" in
  build) build ;;
  test)
    build
    ctest --test-dir "${BUILD_DIR:-build}" --output-on-failure -j "${JOBS:-$(nproc)}" "$@"
    ;;
  report)
    # the report's plots and index.html: Debian's matplotlib and markdown (papers/*.py)
    install_missing python3 python3-matplotlib python3-markdown
    build
    "${BUILD_DIR:-build}/bin/ldlpgs" report "$@"
    ;;
  *) echo "usage: ./build.sh test|report|build" >&2; exit 2 ;;
esac
