#!/usr/bin/env bash
# Packs snag-scan built with MPI and CUDA, and Open MPI itself, for a GPU
# machine that has an NVIDIA driver but no compiler, MPI or Debian packages
# (scripts/make-gpu-bundle.sh packs the GPU tests and benchmarks the same
# way). Open MPI is relocatable: its binaries, libraries, plugins and help
# files go under ompi/ in Debian's layout, and OPAL_PREFIX (PMIX_INSTALL_PREFIX
# for PMIx) points it there; mpi-run.sh sets them up and starts mpirun.
#
# Usage:  scripts/make-mpi-bundle.sh [extra cmake configure arguments...]
#   SNAG_CUDA_ARCHITECTURES  CUDA architectures (default 90: H100/H200)
#   JOBS                     parallel build jobs (default 2)
#   SNAG_BUNDLE_LIMIT_MIB    largest compressed bundle allowed, MiB (default 64)
#   SNAG_OLD_SCAN            another snag-scan built the same way (an earlier commit's),
#                            packed as bin/snag-scan-old for mpi-scaling.sh to compare
#
# Writes .mpi-bundle/ and .mpi-bundle.tar.xz:
#   bin/snag-scan              Release, CUDA and MPI, no OpenVDB or assimp, stripped
#   lib/                       the libraries snag-scan and Open MPI load (ldd), except
#                              the C library family and the NVIDIA driver
#   ompi/                      Open MPI: bin/mpirun, orted; its lib/ tree with the MCA
#                              plugins that need nothing beyond lib/ (not the InfiniBand,
#                              UCX, libfabric, PSM or Java ones: one host needs shared
#                              memory and TCP); share/openmpi help files
#   pmix2/                     PMIx, Open MPI's process manager library, likewise
#   mpi-run.sh                 runs mpirun from the bundle: mpi-run.sh -n 2 bin/snag-scan ...
#   mpi-scaling.sh, make_long_cache.py, mpi-make-cloth.py   the scaling measurement
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
build=$root/build-mpi-gpu
bundle=$root/.mpi-bundle
arch=${SNAG_CUDA_ARCHITECTURES:-90}
jobs=${JOBS:-2}
limit_mib=${SNAG_BUNDLE_LIMIT_MIB:-64}
multiarch=lib/x86_64-linux-gnu
ompi_lib=/usr/$multiarch/openmpi/lib
pmix=/usr/$multiarch/pmix2

[ -x /usr/bin/orterun ] || { echo "make-mpi-bundle: Open MPI not found (scripts/setup.sh installs it)" >&2; exit 1; }

echo "== configure and build $build (snag-scan, CUDA architectures $arch, MPI)"
cmake -S "$root" -B "$build" $( [ -f "$build/CMakeCache.txt" ] || echo -G Ninja) -DCMAKE_BUILD_TYPE=Release \
  -DSNAG_WITH_CUDA=ON -DCMAKE_CUDA_ARCHITECTURES="$arch" -DSNAG_WITH_MPI=ON -DSNAG_WITH_OPENVDB=OFF \
  -DSNAG_WITH_ASSIMP=OFF -DSNAG_BUILD_TESTS=OFF -DSNAG_BUILD_BENCHMARKS=OFF "$@" >/dev/null
cmake --build "$build" --target snag-scan --parallel "$jobs"

rm -rf "$bundle"
mkdir -p "$bundle/bin" "$bundle/lib" "$bundle/ompi/bin" "$bundle/ompi/$multiarch/openmpi" \
  "$bundle/ompi/share" "$bundle/pmix2"
cp "$build/tools/snag-scan" "$bundle/bin/"
if [ -n "${SNAG_OLD_SCAN:-}" ]; then cp "$SNAG_OLD_SCAN" "$bundle/bin/snag-scan-old"; fi
cp /usr/bin/orterun "$bundle/ompi/bin/mpirun"
cp /usr/bin/orted "$bundle/ompi/bin/"
cp -r "$ompi_lib" "$bundle/ompi/$multiarch/openmpi/"
rm -rf "$bundle/ompi/$multiarch/openmpi/lib/pkgconfig" "$bundle/ompi/$multiarch/openmpi/lib/"*java*
cp -r /usr/share/openmpi "$bundle/ompi/share/"
cp -r "$pmix/lib" "$pmix/share" "$bundle/pmix2/"
rm -f "$bundle/pmix2/lib/libpmix.a"

# Plugins whose libraries are for networks between hosts are left out.
needs_network_library() {
  local libraries
  libraries=$(ldd "$1" 2>/dev/null || true)  # whole, before grep: grep -q would end ldd early (pipefail)
  grep -Eq 'libuc[pst]|libfabric|libpsm|libibverbs|librdmacm|libjvm' <<<"$libraries"
}
for plugin in "$bundle/ompi/$multiarch/openmpi/lib/openmpi3/"*.so "$bundle/ompi/$multiarch/openmpi/lib/"*.so; do
  if needs_network_library "$plugin"; then rm -f "$plugin"; fi
done

# The machine's own: the C library's files and the NVIDIA driver's.
machine_library() {
  case "$1" in
    libcuda.so* | libnvidia-*.so* | linux-vdso.so*) return 0 ;;
  esac
  dpkg -S "$(readlink -f "$2")" 2>/dev/null | grep -q '^libc6:' || dpkg -S "$2" 2>/dev/null | grep -q '^libc6:'
}
# Everything the executables and the remaining plugins load, found with ldd
# here, where the system's copies are; the bundle's own Open MPI libraries
# stay in its ompi/ tree.
{
  ldd "$bundle/bin/snag-scan"
  for f in "$bundle/ompi/bin/"* "$bundle/ompi/$multiarch/openmpi/lib/"*.so* \
    "$bundle/ompi/$multiarch/openmpi/lib/openmpi3/"*.so "$bundle/pmix2/lib/"*.so* "$bundle/pmix2/lib/pmix/"*.so; do
    ldd "$f" 2>/dev/null || true
  done
} | awk '$2 == "=>" && $3 ~ /^\// {print $1, $3}' | sort -u | while read -r soname file; do
  machine_library "$soname" "$file" && continue
  case "$soname" in libstdc++.so* | libgcc_s.so*) continue ;; esac  # a newer system's are newer
  cp -L "$file" "$bundle/lib/$soname"
  chmod u+w "$bundle/lib/$soname"
done
strip --strip-unneeded "$bundle/bin/"* "$bundle/ompi/bin/"* "$bundle/lib/"*.so* 2>/dev/null || true

cp scripts/mpi-run.sh scripts/mpi-scaling.sh scripts/mpi-make-cloth.py bench/report/make_long_cache.py "$bundle/"
{
  echo "commit $(git rev-parse HEAD)$(git diff --quiet HEAD -- . ':!build*' || echo ' (with local changes)')"
  echo "cuda_architectures $arch"
  echo "open_mpi $(ompi_info --parsable 2>/dev/null | awk -F: '/^ompi:version:full/ {print $NF}')"
  echo "glibc_needed $(objdump -T "$bundle/bin/snag-scan" "$bundle/lib/"*.so* 2>/dev/null |
    grep -o 'GLIBC_[0-9.]*' | sort -uV | tail -1)"
} >"$bundle/BUILD_INFO"

tar -C "$root" -cJf "$root/.mpi-bundle.tar.xz" .mpi-bundle
size_mib=$(( $(stat -c %s "$root/.mpi-bundle.tar.xz") / 1048576 ))
echo "== .mpi-bundle.tar.xz: ${size_mib} MiB (uncompressed $(du -sh "$bundle" | cut -f1))"
if [ "$size_mib" -ge "$limit_mib" ]; then
  echo "make-mpi-bundle: the bundle is over ${limit_mib} MiB" >&2
  exit 1
fi
