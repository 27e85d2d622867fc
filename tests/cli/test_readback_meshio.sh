#!/usr/bin/env bash
# test_readback_meshio.sh -- meshio (an independent reader) opens gigatet's .ele, .msh, .vtu files and finds
# the input points bit-exact, the reported tet count and only positively oriented tets.
# Skips (exit 77, loudly) only when the python module really is missing.  Needs the kernel.
. "$(dirname "$0")/common.sh"
. "$HERE/readback_common.sh"
readback meshio ele msh vtu
