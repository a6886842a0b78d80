// kernels_test.cpp on the kernels' AVX-512 build (8 lanes; factor/passes.h): tests/CMakeLists.txt
// compiles this file with -mavx512f.
#define LDLPGS_KERNELS_AVX512
#include "kernels_test.cpp"
