# Shared by tools/demo, tools/test, tools/validate, tools/extremes and tools/peers/prologue.sh
# (sourced, not run): installs the Debian packages bagdem needs if any is missing, then configures
# and builds build/ (Release).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="${BAGDEM_BUILD_DIR:-$ROOT/build}"
PACKAGES=(build-essential cmake pkg-config libeigen3-dev libhdf5-dev hdf5-tools libnanoflann-dev
          libgtest-dev libtomlplusplus-dev libcli11-dev zlib1g-dev nlohmann-json3-dev python3-numpy python3-h5py python3-matplotlib
          python3-pandas python3-pytest
          libopenmpi-dev openmpi-bin clang-19 libomp-19-dev)
# The compiler: clang 19 (Debian 12's clang-19), whose code runs the step 10-12% faster than GCC 12's
# on the PD-box beds (docs/performance.md); the results are the same bits. BAGDEM_COMPILER=gcc
# builds with GCC 12 instead (build-essential).
case "${BAGDEM_COMPILER:-clang}" in
  clang) CC_BIN=clang-19 CXX_BIN=clang++-19 ;;
  gcc) CC_BIN=gcc CXX_BIN=g++ ;;
  *) echo "bagdem: BAGDEM_COMPILER must be clang or gcc, not '${BAGDEM_COMPILER}'" >&2; exit 2 ;;
esac

install_missing() {
  local missing=()
  for p in "${PACKAGES[@]}"; do
    dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p")
  done
  # Matplotlib builds its font cache on first import and says so on stderr: do it here, once,
  # rather than inside the first plot (tools/plot, the plot tests).
  [ ${#missing[@]} -eq 0 ] && { warm_matplotlib; return 0; }
  echo "bagdem: installing ${missing[*]}"
  local cmd=(apt-get install -y --no-install-recommends "${missing[@]}")
  if [ "$(id -u)" -eq 0 ]; then
    DEBIAN_FRONTEND=noninteractive apt-get update -qq
    DEBIAN_FRONTEND=noninteractive "${cmd[@]}" -qq >/dev/null
  elif command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then
    sudo DEBIAN_FRONTEND=noninteractive apt-get update -qq
    sudo DEBIAN_FRONTEND=noninteractive "${cmd[@]}" -qq >/dev/null
  else
    echo "bagdem: missing packages and no root or sudo. Run as root:" >&2
    echo "  apt-get update && ${cmd[*]}" >&2
    exit 1
  fi
  warm_matplotlib
}

warm_matplotlib() {
  MPLBACKEND=Agg /usr/bin/python3 -c 'import matplotlib.pyplot' >/dev/null 2>&1 || true
}

build() {
  # A build directory configured with another compiler is configured anew (CMake keeps the compiler
  # of its first configuration).
  local cache="$BUILD/CMakeCache.txt"
  if [ -f "$cache" ] && ! grep -q "^CMAKE_CXX_COMPILER:[A-Z]*=.*/$CXX_BIN\$" "$cache"; then
    rm -rf "$cache" "$BUILD/CMakeFiles"
  fi
  # MPI lets `bagdem sweep` share a study among the ranks of mpirun (HDF5 stays the serial library).
  cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DBAGDEM_MPI=ON \
    -DCMAKE_C_COMPILER="$(command -v "$CC_BIN")" -DCMAKE_CXX_COMPILER="$(command -v "$CXX_BIN")" >/dev/null
  # Quiet on success (warnings are shown); the whole log on failure, which stops the script.
  local log
  log=$(mktemp)
  if ! cmake --build "$BUILD" -j "$(nproc)" >"$log" 2>&1; then
    grep -Ev '^\[ *[0-9]+%\]' "$log" >&2
    rm -f "$log"
    echo "bagdem: build failed" >&2
    exit 1
  fi
  grep -E 'warning:' "$log" || true
  rm -f "$log"
}
