#!/bin/sh
# Usage: avx2_symbols.sh OBJECT... (the factor library's objects). Fails when the object built
# with -mavx2 (passes_avx2) defines a weak or unique symbol outside ldlpgs::kernels::avx2: the
# linker could pick that copy for the SSE2 code and run AVX2 instructions on a CPU without them
# (factor/kernels.h, factor/passes.h).
found=0
for object in "$@"; do
  case "$object" in
    *passes_avx2*)
      found=1
      shared=$(nm -C "$object" | awk '$2 == "W" || $2 == "V" || $2 == "u"' | grep -v 'ldlpgs::kernels::avx2::')
      if [ -n "$shared" ]; then
        echo "passes_avx2 defines symbols the SSE2 code could be linked to:"
        echo "$shared"
        exit 1
      fi
      ;;
  esac
done
[ "$found" = 1 ] || { echo "no passes_avx2 object among: $*"; exit 1; }
echo "passes_avx2: every weak symbol is in ldlpgs::kernels::avx2"
