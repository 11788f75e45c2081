#!/usr/bin/env bash
# Installs everything granstack needs from Debian packages (idempotent: installs only what is
# missing, so a second call is quick and needs no network). Debian 12 or newer, as root or
# with sudo. With --tests, also what only the tests use.
set -euo pipefail
packages=(
  liggghts            # the DEM code (LIGGGHTS-PUBLIC 3.8.0, with Open MPI's mpirun)
  lammps              # the second engine, run --engine lammps (LAMMPS 29 Sep 2021, GRANULAR; binary lmp)
  g++ cmake ninja-build pkg-config git
  libfmt-dev libcli11-dev nlohmann-json3-dev libtomlplusplus-dev libeigen3-dev libhwy-dev libgtest-dev
  libpagmo-dev libsqlite3-dev   # granstack design: NSGA-II (pagmo2) and its store (SQLite)
  coreutils           # stdbuf, so LIGGGHTS's error lines survive an MPI abort
  gnuplot-nox         # granstack plot (PNG and SVG without X)
  zlib1g-dev libzstd-dev zstd   # reading (and, in the tests, making) dumps compressed with gzip or zstd
  time                     # peak memory in bench/
  libfast-float-dev        # number parsing at the speed the dumps need
  libssl-dev               # SHA-256 (OpenSSL) of every case's rendered deck, data file and manifest
  libxxhash-dev            # XXH3-128 of a run's outputs (run.json's digests), checked wherever they are read
  clang libclang-rt-dev    # the fuzz targets (libFuzzer)
)
if [ "${1:-}" = "--tests" ]; then
  packages+=(
    chromium                 # reproduce's HTML report, opened in a real headless browser
    python3-vtk9             # granstack export read back with VTK's own reader
    mkdocs                   # the documentation site, built with --strict (scripts/docs.sh)
    python3                  # the examples' expected values and the docs' tables (tests/check_example.py, scripts/doc_tables.py)
    xxhash                   # xxhsum, which prints the digest run.json records of an output
    slurmctld slurmd slurm-client munge   # a real one-node SLURM (scripts/slurm-local.sh) for submit and status
    # refsim's ARM (NEON) kernels, cross-compiled and run under emulation (refsim.neon_emulated)
    g++-aarch64-linux-gnu qemu-user libhwy-dev:arm64 libfmt-dev:arm64
  )
fi
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#packages[@]} packages are installed"
  exit 0
fi
sudo=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "setup: run as root (or install sudo) to install: ${missing[*]}" >&2; exit 1; }
  sudo="sudo"
fi
echo "setup: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
# Debian's arm64 packages (multiarch) for the ARM kernels' cross build.
if [[ " ${missing[*]}" == *":arm64"* ]] && ! dpkg --print-foreign-architectures | grep -qx arm64; then
  $sudo dpkg --add-architecture arm64
fi
$sudo apt-get update -qq
# --no-install-recommends: liggghts recommends paraview (about 1 GB) that granstack does not need.
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "setup: done"
