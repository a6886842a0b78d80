#!/usr/bin/env bash
# ./build.sh test    install missing Debian packages, build into build/, run ctest
# ./build.sh report  the same set-up (and python3-matplotlib, python3-markdown for the figures), then
#                    the main job: build/bin/ldlpgs report (writes report/index.md and index.html)
# ./build.sh build   set-up and build only
# ./build.sh fuzz [SECONDS]  clang, the libraries under libFuzzer + ASan + UBSan into build-fuzz/,
#                    then each target of fuzz/ for SECONDS (default 60), JOBS at a time, on a
#                    scratch copy of its seed corpus fuzz/corpus/<target>; fails on any finding (kept in
#                    build-fuzz/findings/, the log in build-fuzz/fuzz_<target>.log)
# Environment: BUILD_DIR (default build), SANITIZE=1 (AddressSanitizer + UBSan build),
#              JOBS (default: number of cores).
set -euo pipefail
cd "$(dirname "$0")"
cmd=${1:-test}
shift || true

packages=(cmake g++ make ninja-build libsuitesparse-dev libmetis-dev libeigen3-dev libgtest-dev
          libbenchmark-dev nlohmann-json3-dev libcli11-dev pkg-config
          libmujoco-dev libqhull-dev libmujoco-samples libode-dev libbullet-dev libccd-dev
          pybind11-dev python3-dev python3-numpy python3-scipy python3-pytest python3-matplotlib
          python3-markdown python3-pandas python3-distributed libopenblas0-serial libjs-three chromium python3-pil)
# (pybind11 and python3-*: the Python module, python/, its pytest suite and the example script
# examples/compare_orderings.py, which draws with matplotlib; python3-markdown: the report's
# index.html, tested from the install prefix; python3-pandas, python3-distributed: ldlpgs.study's
# tables and its Dask clusters)
# (ninja-build: the generator of a new build directory, below; make for the examples tests' consumer
# builds, tests/examples_test.cmake)
# (libqhull-dev: Debian's mujocoConfig.cmake names /usr/include/libqhull_r/ and fails without it)
# (libopenblas0-serial: an optimized BLAS/LAPACK, one thread, registered as the libblas.so.3 and
# liblapack.so.3 alternative above the reference libblas3 that libsuitesparse-dev pulls in, so
# that CHOLMOD supernodal is timed as on a user's machine (papers/factor.md, "BLAS: CHOLMOD supernodal with the reference BLAS and with OpenBLAS");
# `ldlpgs bench` prints the BLAS in use)
# (libjs-three: three.js, compiled into the viewer's page, view/; chromium and python3-pil: the
# page's test in a headless browser, tests/view/view_browser_test.py)

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

# A new build directory is generated for Ninja (CMake keeps an existing one's generator): Ninja
# compiles a target's objects while the libraries it links are still compiling, where Make waits
# for each dependency to be built and leaves a core idle behind the long unity sources and
# kernels (DEVELOPERS.md, "Where CI's time goes"). CMAKE_GENERATOR set by the caller wins.
configure() {
  CMAKE_GENERATOR=${CMAKE_GENERATOR:-Ninja} cmake "$@"
}

build() {
  install_missing "${packages[@]}"
  local dir=${BUILD_DIR:-build}
  # Release (-O3) is what every timing in README and papers/ was taken with: GCC vectorizes the
  # kernels only there (papers/factor.md). Sanitized builds are for the tests: debug info for
  # their reports, and no benchmarks, since timings under ASan mean nothing.
  local sanitize=OFF bench=ON type=Release
  if [ "${SANITIZE:-0}" = 1 ]; then sanitize=ON; bench=OFF; type=RelWithDebInfo; fi
  configure -S . -B "$dir" -DCMAKE_BUILD_TYPE=$type -DLDLPGS_SANITIZE=$sanitize -DLDLPGS_BUILD_BENCH=$bench -DLDLPGS_REQUIRE_PEERS=ON
  cmake --build "$dir" -j "${JOBS:-$(nproc)}"
}

fuzz_targets=(matrix_market partition scene factor)

# One target for SECONDS on a scratch copy of its seed corpus: libFuzzer adds what it finds to
# the corpus directory, and the copy keeps the tree clean. Its log: DIR/fuzz_TARGET.log.
fuzz_one() {
  local dir=$1 t=$2 seconds=$3 scratch dict=() rc=0
  scratch=$(mktemp -d)
  cp fuzz/corpus/"$t"/* "$scratch"/
  [ -f fuzz/"$t".dict ] && dict=(-dict=fuzz/"$t".dict)
  "$dir/bin/fuzz_$t" "$scratch" "${dict[@]}" -max_total_time="$seconds" -timeout=30 -rss_limit_mb=2048 \
    -print_final_stats=1 -artifact_prefix="$dir/findings/$t-" >"$dir/fuzz_$t.log" 2>&1 || rc=$?
  rm -rf "$scratch"
  return $rc
}

fuzz() {
  # Only what the libraries need: the fuzz build has no program, tests, peers, MuJoCo or Python.
  install_missing cmake ninja-build clang libclang-rt-14-dev libsuitesparse-dev libmetis-dev libeigen3-dev nlohmann-json3-dev pkg-config libode-dev libccd-dev
  local dir=${BUILD_DIR:-build-fuzz} seconds=${1:-60} failed=0
  CC=clang CXX=clang++ configure -S . -B "$dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DLDLPGS_BUILD_FUZZ=ON \
    -DLDLPGS_BUILD_CLI=OFF -DLDLPGS_BUILD_TESTS=OFF -DLDLPGS_BUILD_BENCH=OFF -DLDLPGS_BUILD_PEERS=OFF \
    -DLDLPGS_BUILD_PYTHON=OFF -DLDLPGS_WITH_MUJOCO=OFF -DLDLPGS_INSTALL=OFF
  cmake --build "$dir" -j "${JOBS:-$(nproc)}"
  rm -rf "$dir/findings" && mkdir -p "$dir/findings"  # this run's findings only
  # libFuzzer runs one process on one core: JOBS targets at a time, each still for SECONDS (on
  # the 2-core CI machine the four take 2 x SECONDS instead of 4 x SECONDS, each with a core).
  local jobs=${JOBS:-$(nproc)} pids=() names=()
  for t in "${fuzz_targets[@]}"; do
    while (($(jobs -rp | wc -l) >= jobs)); do wait -n || true; done
    echo "build.sh fuzz: $t for ${seconds} s"
    fuzz_one "$dir" "$t" "$seconds" &
    pids+=($!) names+=("$t")
  done
  for i in "${!pids[@]}"; do  # in the targets' order, whichever ends first
    local t=${names[$i]}
    if wait "${pids[$i]}"; then
      grep -h "stat::number_of_executed_units" "$dir/fuzz_$t.log" || true
    else
      failed=1
      echo "build.sh fuzz: $t FOUND A FAILURE (input in $dir/findings/, log $dir/fuzz_$t.log):" >&2
      grep -v "^#" "$dir/fuzz_$t.log" | tail -40 >&2
    fi
  done
  return $failed
}

case "$cmd" in
  build) build ;;
  fuzz) fuzz "$@" ;;
  test)
    build
    ctest --test-dir "${BUILD_DIR:-build}" --output-on-failure -j "${JOBS:-$(nproc)}" "$@"
    ;;
  report)
    # the report's plots and index.html: Debian's matplotlib and markdown (papers/scripts/*.py)
    install_missing python3 python3-matplotlib python3-markdown
    build
    "${BUILD_DIR:-build}/bin/ldlpgs" report "$@"
    ;;
  *) echo "usage: ./build.sh test|report|build|fuzz [SECONDS]" >&2; exit 2 ;;
esac
