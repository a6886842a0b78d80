#!/bin/sh
# Usage: isa_symbols.sh ISA STEM NAMESPACE OBJECT... (a library's objects). Fails when the object
# built for ISA (STEM_ISA, e.g. passes_avx2) defines a weak or unique symbol outside NAMESPACE::ISA:
# the linker could pick that copy for the baseline code and run AVX2 or AVX-512 instructions on a
# CPU without them (factor/kernels.h and factor/passes.h; solver/lanes_sweep.h).
isa=$1 stem=$2 namespace=$3
shift 3
found=0
for object in "$@"; do
  case "$object" in
    *"$stem"_"$isa".*)
      found=1
      symbols=$(nm -C "$object") || { echo "nm cannot read $object"; exit 1; }
      shared=$(echo "$symbols" | awk '$2 == "W" || $2 == "V" || $2 == "u"' | grep -v "$namespace::$isa::")
      if [ -n "$shared" ]; then
        echo "${stem}_$isa defines symbols the baseline code could be linked to:"
        echo "$shared"
        exit 1
      fi
      ;;
  esac
done
[ "$found" = 1 ] || { echo "no ${stem}_$isa object among: $*"; exit 1; }
echo "${stem}_$isa: every weak symbol is in $namespace::$isa"
