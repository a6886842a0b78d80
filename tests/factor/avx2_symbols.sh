#!/bin/sh
# Usage: avx2_symbols.sh [ISA] OBJECT... (the factor library's objects; ISA avx2, the default, or
# avx512). Fails when the object built for ISA (passes_ISA) defines a weak or unique symbol
# outside ldlpgs::kernels::ISA: the linker could pick that copy for the SSE2 code and run AVX2 or
# AVX-512 instructions on a CPU without them (factor/kernels.h, factor/passes.h).
isa=avx2
case "$1" in avx2|avx512) isa=$1; shift ;; esac
found=0
for object in "$@"; do
  case "$object" in
    *passes_"$isa".*)
      found=1
      shared=$(nm -C "$object" | awk '$2 == "W" || $2 == "V" || $2 == "u"' | grep -v "ldlpgs::kernels::$isa::")
      if [ -n "$shared" ]; then
        echo "passes_$isa defines symbols the SSE2 code could be linked to:"
        echo "$shared"
        exit 1
      fi
      ;;
  esac
done
[ "$found" = 1 ] || { echo "no passes_$isa object among: $*"; exit 1; }
echo "passes_$isa: every weak symbol is in ldlpgs::kernels::$isa"
