#pragma once
// The library's three kinds of error (DEVELOPERS.md): programmer errors are asserts; bad user
// input is an InputError thrown at the boundary, with a one-line message naming the file, the
// line or entry, and the problem ("m.mtx:12: row index 50 out of range 1..48"); numerical
// failure is a returned status (factor/).
#include <stdexcept>
#include <string>

namespace ldlpgs {

struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace ldlpgs
