#pragma once
// The library's kinds of error (DEVELOPERS.md): programmer errors inside the library are asserts;
// bad user input is an InputError thrown at the boundary, with a one-line message naming the
// file, the line or entry, and the problem ("m.mtx:12: row index 50 out of range 1..48"); a
// caller passing the public API what it cannot take (a matrix whose pattern is not the one
// analyzed, a right-hand side of the wrong size, a partition that does not cover the rows) gets
// an ArgumentError, checked in every build, Release included; numerical failure is a returned
// status (factor/).
#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>

namespace ldlpgs {

struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct ArgumentError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

// Input text as it may appear in a one-line message: control bytes, DEL and bytes >= 0x80 (binary
// or UTF-8) written as \xNN, a backslash as \\, and cut after max_chars with "..." (a 1 MB
// one-line JSON file, a NUL inside a matrix entry and raw binary would make unbounded, cut or
// multi-line messages otherwise). escape_backslash = false is for text that is printable
// already, a message whose quotes printable() made, so that its \xNN are not made \\xNN.
inline std::string printable(std::string_view text, size_t max_chars = 300, bool escape_backslash = true) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string out;
  for (size_t k = 0; k < text.size(); ++k) {
    if (out.size() >= max_chars) {
      out += "...";
      break;
    }
    const unsigned char c = static_cast<unsigned char>(text[k]);
    if (c == '\\' && escape_backslash) {
      out += "\\\\";
    } else if (c < 0x20 || c >= 0x7f) {
      out += "\\x";
      out += kHex[c >> 4];
      out += kHex[c & 15];
    } else {
      out += static_cast<char>(c);
    }
  }
  return out;
}

}  // namespace ldlpgs
