#!/usr/bin/env bash
# Builds snag's GPU executables here and packs them into .gpu-bundle/ for a GPU
# machine that has an NVIDIA driver but no compiler, CUDA toolkit or Debian
# packages. Nothing is built on the GPU machine: it runs scripts/gpu-check.sh
# (also copied into the bundle), which reads only the bundle.
#
# Usage:  scripts/make-gpu-bundle.sh [extra cmake configure arguments...]
#   SNAG_CUDA_ARCHITECTURES  CUDA architectures to compile for (default 90: H100/H200)
#   JOBS                     parallel build jobs (default 2)
#   SNAG_BUNDLE_LIMIT_MIB    largest bundle allowed, uncompressed MiB (default 96)
#   SNAG_BUNDLE_FROM         an existing build folder with CUDA on (e.g. build/ of
#                            scripts/build.sh): its GPU executables are packed as
#                            they are, without configuring or building build-gpu/
#
# What goes in (the executables are listed by CMake in build-gpu/gpu-targets.txt,
# see snag_register_gpu_target in libcd/cuda/CMakeLists.txt):
#   bin/          the GPU test executables, GPU benchmarks, snag-scan (when it
#                 exists) and the device tracer (libsnag_cupti_trace, when the
#                 toolkit has CUPTI; its libcupti comes from the GPU machine's
#                 toolkit, and trace_summary.py goes beside gpu-check.sh),
#                 stripped; Release build in build-gpu/, OpenVDB and assimp
#                 off (the bundled data is PLY, OBJ and PC2, which snag reads
#                 itself; assimp and its codecs alone would take 12 MiB of the 64)
#   lib/          the shared libraries they load (from ldd), except the C library
#                 family (libc, libm, libpthread, libdl, librt, ld-linux, ...)
#                 and the NVIDIA driver (libcuda, libnvidia-*), which must come
#                 from the GPU machine. The CUDA runtime is linked statically.
#   lib/compat/   libstdc++ and libgcc_s of this machine. A newer system (e.g.
#                 Ubuntu 24.04) has newer, backward-compatible ones, and forcing
#                 ours onto it could break its own programs (nvidia-smi,
#                 compute-sanitizer); so gpu-check.sh adds lib/compat to the
#                 library path only when the system's copies lack a version our
#                 executables need (an older system).
#   data/         the reference data the tests read (meshes/cloth_ball9[23].ply,
#                 ccd-queries/); gpu-check.sh points SNAG_SHARED_DATA_DIR here
#   (samples/ is not copied: the bundle travels inside the project tree, and
#   gpu-check.sh reads the sample caches from the project's samples/)
#   manifest.txt  one "kind name bin/file" line per executable
#   BUILD_INFO    commit, architectures, compiler, glibc needed
# The total must stay under the limit (the bundle travels with a size cap, as
# an xz archive of about a fifth of it: tar -cf - .gpu-bundle | xz); the
# script prints the size and fails when it is over.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
build=${SNAG_BUNDLE_FROM:-$root/build-gpu}
bundle=$root/.gpu-bundle
data=$root/../shared/data
arch=${SNAG_CUDA_ARCHITECTURES:-90}
jobs=${JOBS:-2}
limit_mib=${SNAG_BUNDLE_LIMIT_MIB:-96}

[ -d "$data" ] || { echo "make-gpu-bundle: reference data not found at $data" >&2; exit 1; }

targets_file=$build/gpu-targets.txt
if [ -z "${SNAG_BUNDLE_FROM:-}" ]; then
  launchers=()
  if command -v ccache >/dev/null; then
    launchers=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_CUDA_COMPILER_LAUNCHER=ccache)
  fi
  generator=()
  [ -f "$build/CMakeCache.txt" ] || { command -v ninja >/dev/null && generator=(-G Ninja); }

  echo "== configure $build (CUDA architectures $arch)"
  cmake -S "$root" -B "$build" "${generator[@]}" "${launchers[@]}" \
    -DCMAKE_BUILD_TYPE=Release -DSNAG_WITH_CUDA=ON -DCMAKE_CUDA_ARCHITECTURES="$arch" \
    -DSNAG_WITH_OPENVDB=OFF -DSNAG_WITH_ASSIMP=OFF -DSNAG_BUILD_TESTS=ON -DSNAG_BUILD_BENCHMARKS=ON "$@" >/dev/null

  [ -s "$targets_file" ] || { echo "make-gpu-bundle: no GPU executables registered ($targets_file is empty)" >&2; exit 1; }
  mapfile -t targets < <(awk '{print $2}' "$targets_file")
  echo "== build ${targets[*]}"
  cmake --build "$build" --parallel "$jobs" --target "${targets[@]}"
else
  [ -s "$targets_file" ] || { echo "make-gpu-bundle: $build has no GPU executables ($targets_file is missing or empty)" >&2; exit 1; }
  arch=$(sed -n 's/^CMAKE_CUDA_ARCHITECTURES:[A-Z]*=//p' "$build/CMakeCache.txt")
  arch=${arch:-90}  # not in the cache: CMakeLists.txt's default
  echo "== packing the GPU executables of $build as built (CUDA architectures $arch)"
fi

echo "== pack $bundle"
rm -rf "$bundle"
mkdir -p "$bundle/bin" "$bundle/lib/compat" "$bundle/data/meshes"
: >"$bundle/manifest.txt"
while read -r kind name path; do
  cp "$path" "$bundle/bin/$name"
  strip --strip-unneeded "$bundle/bin/$name"
  echo "$kind $name bin/$name" >>"$bundle/manifest.txt"
done <"$targets_file"

# Shared libraries, from ldd of the unstripped executables (ldd lists the whole closure).
is_system_library() {
  case "$1" in
    linux-vdso.so* | ld-linux*.so* | libc.so* | libm.so* | libpthread.so* | libdl.so* | librt.so* | \
      libresolv.so* | libutil.so* | libmvec.so* | libanl.so* | libcuda.so* | libnvidia-*.so*) return 0 ;;
    libcupti.so*) return 0 ;;  # the tracer's: from the GPU machine's CUDA toolkit (gpu-check.sh)
  esac
  return 1
}
while read -r _ _ path; do
  ldd "$path" | awk '$2 == "=>" && $3 ~ /^\// {print $1, $3}'
done <"$targets_file" | sort -u | while read -r soname file; do
  is_system_library "$soname" && continue
  case "$soname" in
    libstdc++.so* | libgcc_s.so*) dest=$bundle/lib/compat ;;
    *) dest=$bundle/lib ;;
  esac
  cp -L "$file" "$dest/$soname"
  chmod u+w "$dest/$soname"
  strip --strip-unneeded "$dest/$soname" 2>/dev/null || true
done

# Data the tests and benchmarks read.
cp "$data/README.md" "$bundle/data/"
cp "$data"/meshes/cloth_ball9[23].ply "$data/meshes/LICENSE" "$bundle/data/meshes/"
cp -r "$data/ccd-queries" "$bundle/data/"
cp "$root/scripts/gpu-check.sh" "$bundle/gpu-check.sh"
cp "$root/bench/gpu/trace_summary.py" "$bundle/trace_summary.py"
chmod -R u+w "$bundle"

shopt -s nullglob
glibc_needed=$(for f in "$bundle"/bin/* "$bundle"/lib/*.so* "$bundle"/lib/compat/*.so*; do
  objdump -T "$f" 2>/dev/null || true
done | grep -o 'GLIBC_[0-9.]*' | sort -t. -k1,1 -k2,2n -k3,3n -u | tail -1 || true)
shopt -u nullglob
nvcc=$(sed -n 's/^set(CMAKE_CUDA_COMPILER "\(.*\)")$/\1/p' "$build"/CMakeFiles/*/CMakeCUDACompiler.cmake | head -1)
{
  echo "commit      $(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo unknown)$(git -C "$root" diff --quiet 2>/dev/null || echo ' (modified)')"
  echo "built       $(date -u +%Y-%m-%dT%H:%M:%SZ) on $(. /etc/os-release && echo "$PRETTY_NAME")"
  echo "cuda_arch   $arch"
  echo "nvcc        $("${nvcc:-nvcc}" --version 2>/dev/null | tail -1)"
  echo "glibc_need  ${glibc_needed:-unknown}"
} >"$bundle/BUILD_INFO"

echo "== contents"
(cd "$bundle" && du -ah --max-depth=2 . | sort -k2)
bytes=$(du -sb "$bundle" | cut -f1)
mib=$(awk -v b="$bytes" 'BEGIN {printf "%.1f", b / 1048576}')
echo "== bundle size: $mib MiB ($bytes bytes), limit $limit_mib MiB"
if [ "$bytes" -gt $((limit_mib * 1048576)) ]; then
  echo "make-gpu-bundle: the bundle is over the $limit_mib MiB limit" >&2
  exit 1
fi
