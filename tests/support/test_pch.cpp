// The source of tests/CMakeLists.txt's ldlpgs_test_pch: nothing of its own; CMake compiles the
// tests' shared precompiled header with this target's flags, and the tests reuse it.
