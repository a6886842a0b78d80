// kernels_test.cpp on the kernels' AVX2 build (4 lanes; factor/passes.h): tests/CMakeLists.txt
// compiles this file with -mavx2.
#define LDLPGS_KERNELS_AVX2
#include "kernels_test.cpp"
