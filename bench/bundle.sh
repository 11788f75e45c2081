#!/usr/bin/env bash
# A copy of granstack, LIGGGHTS and Open MPI that runs on an x86-64 Linux machine without them
# (a benchmark host with no packages and no network): the programs, every library they and Open
# MPI's plugins load except glibc's own, and Open MPI's plugins and help texts, found there
# through OPAL_PREFIX. Then, on that machine: `source DIR/env.sh`, and granstack, liggghts and
# mpirun are on PATH.
# Usage: bench/bundle.sh DIR [GRANSTACK]   (GRANSTACK: the build to bundle [build/release/app/granstack])
set -euo pipefail
out=${1:?usage: bench/bundle.sh DIR [GRANSTACK]}
gs=${2:-build/release/app/granstack}
[[ -x $gs ]] || { echo "bench/bundle.sh: $gs is not an executable; build it first (cmake --preset release && cmake --build build/release)" >&2; exit 2; }
arch=lib/x86_64-linux-gnu
[[ -d /usr/$arch/openmpi ]] || { echo "bench/bundle.sh: Open MPI is not installed here (Debian's openmpi-bin, which liggghts brings)" >&2; exit 2; }
[[ ! -e $out ]] || { echo "bench/bundle.sh: $out exists; give a new directory" >&2; exit 3; }
root=$out/usr
mkdir -p "$root/bin" "$root/lib" "$root/$arch" "$root/share"
cp -a "/usr/$arch/openmpi" "/usr/$arch/pmix2" "$root/$arch/"
cp -a /usr/share/openmpi "$root/share/"
cp -L /usr/bin/orterun /usr/bin/orted "$(command -v liggghts)" "$root/bin/"
ln -s orterun "$root/bin/mpirun"
cp -L "$gs" "$root/bin/granstack"
# Every library the programs and the plugins need, but glibc's (the host has its own).
mapfile -t objects < <(find "$root/bin" "$root/$arch" -type f \( -perm -u+x -o -name '*.so*' \))
ldd "${objects[@]}" 2>/dev/null | awk '/=> \//{print $3}' | sort -u | while read -r lib; do
  case $(basename "$lib") in
    libc.so.* | libm.so.* | libpthread.so.* | libdl.so.* | librt.so.* | ld-linux*) ;;
    *) cp -Ln "$lib" "$root/lib/" ;;
  esac
done
cat >"$out/env.sh" <<'EOF'
# Source this: granstack, liggghts and Open MPI's mpirun from this bundle.
bundle=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/usr
export PATH=$bundle/bin:$PATH
export LD_LIBRARY_PATH=$bundle/lib:$bundle/lib/x86_64-linux-gnu/pmix2/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
export OPAL_PREFIX=$bundle
export PMIX_INSTALL_PREFIX=$bundle/lib/x86_64-linux-gnu/pmix2
export PMIX_MCA_mca_base_component_path=$bundle/lib/x86_64-linux-gnu/pmix2/lib/pmix
EOF
echo "bundle in $out: $(du -sh "$out" | cut -f1); on the other machine: source $out/env.sh"
