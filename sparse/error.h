#pragma once
// The library's kinds of error (DEVELOPERS.md): programmer errors inside the library are asserts;
// bad user input is an InputError thrown at the boundary, with a one-line message naming the
// file, the line or entry, and the problem ("m.mtx:12: row index 50 out of range 1..48"); a
// caller passing the public API what it cannot take (a matrix whose pattern is not the one
// analyzed, a right-hand side of the wrong size, a partition that does not cover the rows) gets
// an ArgumentError, checked in every build, Release included; numerical failure is a returned
// status (factor/).
#include <stdexcept>
#include <string>

namespace ldlpgs {

struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct ArgumentError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

}  // namespace ldlpgs
