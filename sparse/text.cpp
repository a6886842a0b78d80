// Message text and the chunked file reader (text.h).
#include "ldlpgs/sparse/text.h"

#include <cerrno>
#include <charconv>
#include <cstring>
#include <filesystem>

#include "ldlpgs/sparse/error.h"

namespace ldlpgs {

std::string printable(std::string_view text, size_t max_chars, bool escape_backslash) {
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

std::string format_number(double x) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, x);
  return std::string(buffer, result.ptr);
}

std::FILE* open_input(const std::string& path) {
  // A directory opens with fopen on Linux and fails only on read (or reads as empty).
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw InputError(cat(printable(path), ": cannot read: it is a directory"));
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw InputError(cat(printable(path), ": cannot open file: ", std::strerror(errno)));
  return f;
}

FileChunks::FileChunks(const std::string& path) : f_(open_input(path)), name_(printable(path)) {}

FileChunks::~FileChunks() {
  if (f_) std::fclose(f_);
}

bool FileChunks::append_to(std::string& text) {
  if (eof_) return false;
  const size_t old = text.size();
  text.resize(old + kChunk);
  const size_t got = std::fread(text.data() + old, 1, kChunk, f_);
  text.resize(old + got);
  if (std::ferror(f_)) throw InputError(cat(name_, ": cannot read: read error"));
  // fread returns less than asked for only at the end of the file (a pipe included).
  if (got < kChunk) eof_ = true;
  return got > 0;
}

LineReader::Got LineReader::next(std::string_view& line, size_t max_length) {
  size_t scanned = pos_;
  while (true) {
    const size_t newline = buffer_.find('\n', scanned);
    const size_t end = newline == std::string::npos ? buffer_.size() : newline;
    if (end - pos_ > max_length) {
      ++number_;
      line = std::string_view(buffer_).substr(pos_, max_length);
      return Got::too_long;
    }
    if (newline != std::string::npos || (eof_ && pos_ < buffer_.size())) {
      ++number_;
      line = std::string_view(buffer_).substr(pos_, end - pos_);
      if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
      pos_ = newline == std::string::npos ? end : end + 1;
      return Got::line;
    }
    if (eof_) return Got::end;
    buffer_.erase(0, pos_);
    pos_ = 0;
    scanned = buffer_.size();
    eof_ = !file_.append_to(buffer_);
  }
}

}  // namespace ldlpgs
