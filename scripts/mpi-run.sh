#!/usr/bin/env bash
# Runs Open MPI's mpirun from a bundle made by scripts/make-mpi-bundle.sh, on
# one host: mpi-run.sh -n 2 bin/snag-scan ... (arguments as for mpirun).
# Open MPI finds its plugins and help files through OPAL_PREFIX, PMIx its own
# through PMIX_INSTALL_PREFIX; the ranks inherit the library path. Ranks talk
# over loopback TCP, which works in sandboxed kernels where shared-memory
# single copy does not (their messages are a few bytes; parts go through files).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
export OPAL_PREFIX=$here/ompi
export PMIX_INSTALL_PREFIX=$here/pmix2 PMIX_MCA_mca_base_component_path=$here/pmix2/lib/pmix
export PMIX_MCA_pcompress_base_silence_warning=1
export LD_LIBRARY_PATH=$here/ompi/lib/x86_64-linux-gnu/openmpi/lib:$here/pmix2/lib:$here/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
export PATH=$here/ompi/bin:$PATH
export OMPI_MCA_btl=self,tcp OMPI_MCA_btl_tcp_if_include=lo OMPI_MCA_oob_tcp_if_include=lo OMPI_MCA_pml=ob1
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
exec "$here/ompi/bin/mpirun" "$@"
