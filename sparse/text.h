#pragma once
// Text for one-line messages, and the reader every input file goes through (Matrix Market,
// block partitions, scene files, MJCF): a file read a chunk at a time, so that what is not the
// format (a directory, /dev/zero, gigabytes of NUL bytes) is refused having read at most a chunk
// past the point where it stopped being it.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>

namespace ldlpgs {

// Input text as it may appear in a one-line message: control bytes, DEL and bytes >= 0x80 (binary
// or UTF-8) written as \xNN, a backslash as \\, and cut after max_chars with "...".
// escape_backslash = false is for text that is printable already, a message whose quotes
// printable() made, so that its \xNN are not made \\xNN.
std::string printable(std::string_view text, size_t max_chars = 300, bool escape_backslash = true);

// Concatenation by appending (GCC 12 warns falsely on "literal" + std::string, DEVELOPERS.md).
template <typename... Parts>
std::string cat(const Parts&... parts) {
  std::string s;
  (s += ... += parts);
  return s;
}

// The shortest text that reads back as x ("0.1", "1e-320", "inf", "nan").
std::string format_number(double x);

// The file opened for reading ("rb"), or an InputError naming it through printable():
// "PATH: cannot read: it is a directory" or "PATH: cannot open file: REASON".
std::FILE* open_input(const std::string& path);

// A file read kChunk bytes at a time (open_input; a read error is "PATH: cannot read: read error").
class FileChunks {
 public:
  static constexpr size_t kChunk = size_t{1} << 16;
  explicit FileChunks(const std::string& path);
  ~FileChunks();
  FileChunks(const FileChunks&) = delete;
  FileChunks& operator=(const FileChunks&) = delete;

  // Appends the next chunk to `text`; false (nothing appended) at the end of the file.
  bool append_to(std::string& text);
  const std::string& name() const { return name_; }  // the path through printable()

 private:
  std::FILE* f_ = nullptr;
  std::string name_;
  bool eof_ = false;
};

// The lines of a file, numbered from 1, without their "\n" or "\r\n" (files from Windows).
class LineReader {
 public:
  enum class Got { line, end, too_long };
  explicit LineReader(const std::string& path) : file_(path) {}

  // The next line, valid until the next call. One longer than max_length bytes is too_long,
  // `line` then its first max_length bytes (having read at most a chunk past them).
  Got next(std::string_view& line, size_t max_length);
  int64_t number() const { return number_; }
  const std::string& name() const { return file_.name(); }

 private:
  FileChunks file_;
  std::string buffer_;
  size_t pos_ = 0;
  bool eof_ = false;
  int64_t number_ = 0;
};

}  // namespace ldlpgs
