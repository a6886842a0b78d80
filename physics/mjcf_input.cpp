// MJCF input hardening (mjcf_input.h): MuJoCo's numbers checked in the XML before MuJoCo reads it.
#include "ldlpgs/physics/mjcf_input.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iterator>
#include <string_view>

#include "ldlpgs/sparse/error.h"
#include "ldlpgs/sparse/text.h"

namespace ldlpgs {

namespace {

// The XML's numeric attributes, checked before MuJoCo sees the file: MuJoCo reads nan and inf,
// and a hinge axis "nan 0 0" makes mj_loadXML never return (its length-range computation steps
// the model). A tag-level scan, not an XML parser: comments, declarations and CDATA are
// skipped, entities are not expanded (MuJoCo's tinyxml2 then reports them), and <include file>
// is followed (relative to the including file, at most kMaxIncludeDepth deep). Only these
// attributes are checked; every whitespace-separated token must be a finite double.
constexpr std::string_view kNumericAttributes[] = {
    "pos",      "quat",        "axisangle",  "euler",     "xyaxes",   "zaxis",     "axis",   "mass",
    "diaginertia", "fullinertia", "range",   "timestep",  "gravity",  "fromto",    "size",   "density",
    "ref",      "springref",   "stiffness",  "damping",   "armature", "frictionloss", "relpose", "anchor",
    "ipos",     "iquat",       "refpos",     "refquat",   "qpos",     "qvel",      "margin", "gap",
    "solref",   "solimp",      "friction",   "impratio",  "tolerance", "wind",     "magnetic", "viscosity"};
constexpr int kMaxIncludeDepth = 16;

// An MJCF file is text of some kilobytes (MuJoCo's humanoid: 9 KB): past this it is not one.
constexpr size_t kMaxMjcfBytes = size_t{1} << 26;

// The file's text, read a chunk at a time (FileChunks) so that what is not XML fails at its first
// chunk: read whole, /dev/zero named z.xml would never return. A file that cannot be opened gives
// "": MuJoCo then names what is missing.
std::string read_mjcf_text(const std::string& file) {
  std::error_code ec;
  if (!std::filesystem::exists(file, ec)) return {};
  FileChunks chunks(file);
  std::string text;
  while (chunks.append_to(text)) {
    if (text.size() <= FileChunks::kChunk) {
      // XML starts with '<' after blanks (and a UTF-8 byte order mark)
      size_t at = text.starts_with("\xEF\xBB\xBF") ? 3 : 0;
      while (at < text.size() && std::isspace(static_cast<unsigned char>(text[at]))) ++at;
      if (at == text.size() || text[at] != '<')
        throw InputError(chunks.name() + ": not an MJCF (XML) file: it does not start with '<'");
    }
    if (text.size() > kMaxMjcfBytes)
      throw InputError(chunks.name() + ": more than " + std::to_string(kMaxMjcfBytes >> 20) +
                       " MiB: not an MJCF model (those are kilobytes)");
  }
  return text;
}

constexpr std::string_view kSpace = " \t\r\n";

// What is wrong with an attribute value that must be whitespace-separated finite doubles, or null.
const char* numbers_problem(std::string_view value) {
  for (size_t t = value.find_first_not_of(kSpace); t != std::string_view::npos;) {
    const size_t t_end = std::min(value.find_first_of(kSpace, t), value.size());
    std::string_view token = value.substr(t, t_end - t);
    if (token.starts_with('+')) token.remove_prefix(1);
    double x = 0;
    const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), x);
    if (end != token.data() + token.size() || (ec != std::errc() && ec != std::errc::result_out_of_range))
      return "not a number";
    // out of range: an underflow reads as 0 or a subnormal, an overflow as inf
    if (ec == std::errc::result_out_of_range) x = std::strtod(std::string(token).c_str(), nullptr);
    if (!std::isfinite(x)) return "not a finite number (nan, inf or beyond 1.8e308)";
    t = value.find_first_not_of(kSpace, t_end);
  }
  return nullptr;
}

// The scan of one file (`file`, included by `path` unless they are the same) and its includes.
void check_numbers(const std::string& path, const std::string& file, int depth) {
  const std::string text = read_mjcf_text(file);
  if (text.empty()) return;
  auto fail = [&](size_t at, std::string_view element, std::string_view attribute, std::string_view value,
                  const char* problem) {
    std::string s = printable(file);
    s += ":";
    s += std::to_string(1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
    s += ": <";
    s += printable(element, 40);
    s += "> ";
    s += printable(attribute, 40);
    s += "=\"";
    s += printable(value, 80);
    s += "\": ";
    s += problem;
    if (file != path) {
      s += " (included by ";
      s += printable(path);
      s += ")";
    }
    throw InputError(s);
  };
  auto skip_past = [&](size_t from, std::string_view end) {
    const size_t k = text.find(end, from);
    return k == std::string::npos ? text.size() : k + end.size();
  };
  size_t i = 0;
  while ((i = text.find('<', i)) != std::string::npos) {
    const std::string_view rest = std::string_view(text).substr(i);
    if (rest.starts_with("<!--")) {
      i = skip_past(i, "-->");
      continue;
    }
    if (rest.starts_with("<![CDATA[")) {
      i = skip_past(i, "]]>");
      continue;
    }
    if (rest.starts_with("<?") || rest.starts_with("<!") || rest.starts_with("</")) {
      i = skip_past(i, ">");
      continue;
    }
    size_t k = i + 1;
    const size_t name_end = std::min(text.find_first_of(" \t\r\n/>", k), text.size());
    const std::string_view element = std::string_view(text).substr(k, name_end - k);
    k = name_end;
    while (k < text.size() && text[k] != '>') {  // attributes: name = "value" or 'value'
      const size_t a = text.find_first_not_of(kSpace, k);
      if (a == std::string::npos || text[a] == '>' || text[a] == '/') {
        k = a == std::string::npos ? text.size() : a + 1;
        if (a != std::string::npos && text[a] == '>') break;
        continue;
      }
      const size_t a_end = std::min(text.find_first_of(" \t\r\n=/>", a), text.size());
      const std::string_view attribute = std::string_view(text).substr(a, a_end - a);
      const size_t eq = text.find_first_not_of(kSpace, a_end);
      if (eq == std::string::npos || text[eq] != '=') {
        k = a_end;
        continue;
      }
      const size_t q = text.find_first_not_of(kSpace, eq + 1);
      if (q == std::string::npos || (text[q] != '"' && text[q] != '\'')) return;  // malformed: MuJoCo says so
      const size_t q_end = text.find(text[q], q + 1);
      if (q_end == std::string::npos) return;
      const std::string_view value = std::string_view(text).substr(q + 1, q_end - q - 1);
      k = q_end + 1;
      if (element == "include" && attribute == "file") {
        if (depth >= kMaxIncludeDepth) fail(q, element, attribute, value, "includes nested too deep");
        const std::filesystem::path included = std::filesystem::path(file).parent_path() / std::string(value);
        check_numbers(path, included.string(), depth + 1);
        continue;
      }
      if (std::find(std::begin(kNumericAttributes), std::end(kNumericAttributes), attribute) ==
          std::end(kNumericAttributes))
        continue;
      if (const char* problem = numbers_problem(value)) fail(q, element, attribute, value, problem);
    }
    i = k;
  }
}

}  // namespace

void check_mjcf_numbers(const std::string& path) { check_numbers(path, path, 0); }

}  // namespace ldlpgs
