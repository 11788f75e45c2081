#!/usr/bin/env bash
# refsim.neon_emulated: the kernel tests' stacks written to files by the native build, then
# checked on an emulated ARM CPU by the cross-compiled checker (emulated_kernels.cpp).
# Usage: run_emulated.sh WRITER QEMU CHECKER WORK_DIR
set -euo pipefail
writer=$1 qemu=$2 checker=$3 work=$4
mkdir -p "$work"
mapfile -t cases < <("$writer" "$work")
# The arm64 C library and loader of Debian's cross toolchain; Highway and fmt from multiarch.
exec "$qemu" -L /usr/aarch64-linux-gnu "$checker" neon "${cases[@]}"
