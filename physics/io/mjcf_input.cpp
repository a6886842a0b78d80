// MJCF input hardening (mjcf_input.h): MuJoCo's numbers checked in the XML before MuJoCo reads it.
#include "ldlpgs/physics/io/mjcf_input.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string_view>
#include <utility>

#include "ldlpgs/sparse/error.h"
#include "ldlpgs/sparse/text.h"

namespace ldlpgs {

namespace {

// The XML's numeric attributes, checked before MuJoCo sees the file: MuJoCo reads nan and inf,
// and a hinge axis "nan 0 0" makes mj_loadXML never return (its length-range computation steps
// the model). A tag-level scan, not an XML parser, that reads what MuJoCo 2.2.2 reads: comments,
// declarations and CDATA are skipped, values are decoded as tinyxml2 decodes them, only the root
// element's children count (MuJoCo ignores what follows it, and an included file's root), and
// <include file> is followed (relative to the top file's folder, as MuJoCo does, at most
// kMaxIncludeDepth deep). Every whitespace-separated token of a checked attribute must be a
// finite double.
//
// The checked attributes, per element: those of MuJoCo 2.2.2's schema (the MJCF[] table of
// src/xml/xml_native_reader.cc) that its reader reads as real numbers (ReadAttr, ReadAlternative):
// positions, orientations, inertias, ranges, the physical and solver parameters. An element name
// stands for all its places (<joint> in a body, a default, a composite, an equality): in each
// these are numbers. Not checked: keywords (every <flag> attribute is "enable" or "disable":
// <flag gravity="disable"/>), strings, and integers, which MuJoCo reads with sscanf (<numeric
// size="3abc"/> is 3) and which cannot be nan or inf.
struct NumericAttributes {
  std::string_view element;
  std::string_view attributes;  // separated by spaces
};
constexpr NumericAttributes kNumericAttributes[] = {
    {"option", "timestep apirate impratio tolerance noslip_tolerance mpr_tolerance gravity wind magnetic density "
               "viscosity o_margin o_solref o_solimp"},
    {"lengthrange", "timestep"},
    {"map", "stiffness"},
    {"body", "pos quat axisangle xyaxes zaxis euler"},
    {"inertial", "pos quat mass diaginertia axisangle xyaxes zaxis euler fullinertia"},
    {"joint", "pos axis stiffness range margin ref springref armature damping frictionloss solref solimp"},
    {"geom", "size friction mass density solref solimp margin gap fromto pos quat axisangle xyaxes zaxis euler"},
    {"site", "pos quat size fromto axisangle xyaxes zaxis euler"},
    {"camera", "pos quat axisangle xyaxes zaxis euler"},
    {"light", "pos"},
    {"pair", "friction solref solimp gap margin"},
    {"equality", "solref solimp"},
    {"connect", "anchor solref solimp"},
    {"weld", "relpose anchor solref solimp"},
    {"distance", "solref solimp"},
    {"tendon", "range frictionloss margin stiffness damping solref solimp"},
    {"spatial", "range frictionloss margin stiffness damping"},
    {"fixed", "range frictionloss margin stiffness damping"},
    {"muscle", "range"},
    {"hfield", "size"},
    {"mesh", "refpos refquat"},
    {"key", "qpos qvel"}};
constexpr int kMaxIncludeDepth = 16;

// Whitespace as MuJoCo's reader splits numbers (operator>> in the C locale) and as tinyxml2
// separates attributes (isspace).
constexpr std::string_view kSpace = " \t\n\v\f\r";

bool is_numeric(std::string_view element, std::string_view attribute) {
  for (const NumericAttributes& row : kNumericAttributes) {
    if (row.element != element) continue;
    for (size_t t = 0; t < row.attributes.size();) {
      const size_t t_end = std::min(row.attributes.find(' ', t), row.attributes.size());
      if (row.attributes.substr(t, t_end - t) == attribute) return true;
      t = t_end + 1;
    }
    return false;
  }
  return false;
}

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

// The code point of the character reference at raw[p] ("&#48;", "&#x30;") and the index past its
// ';', as tinyxml2 9 (XMLUtil::GetCharacterRef) reads it: its digits read backwards from the ';'
// to the '#' or 'x', its multiplier wrapping at 2^32. {0, 0}: not a reference, the '&' is kept.
std::pair<unsigned long, size_t> character_reference(std::string_view raw, size_t p) {
  const bool hex = raw[p + 2] == 'x';
  if (hex && p + 3 >= raw.size()) return {0, 0};
  const size_t semicolon = raw.find(';', p + (hex ? 3 : 2));
  if (semicolon == std::string_view::npos) return {0, 0};
  unsigned long code = 0;
  unsigned mult = 1;
  for (size_t q = semicolon - 1; raw[q] != (hex ? 'x' : '#'); --q) {
    const char c = raw[q];
    unsigned digit = 0;
    if (c >= '0' && c <= '9')
      digit = static_cast<unsigned>(c - '0');
    else if (hex && c >= 'a' && c <= 'f')
      digit = static_cast<unsigned>(c - 'a' + 10);
    else if (hex && c >= 'A' && c <= 'F')
      digit = static_cast<unsigned>(c - 'A' + 10);
    else
      return {0, 0};
    code += mult * digit;
    mult *= hex ? 16 : 10;
  }
  return {code, semicolon + 1};
}

// An attribute's value as MuJoCo receives it from tinyxml2 9 (Debian's, which libmujoco links): the
// entities &quot; &amp; &apos; &lt; &gt; and character references replaced, in place as tinyxml2
// does it (an unknown entity's '&' leaves the byte already at the write position), and the value
// cut at a reference to code point 0 (MuJoCo reads a C string). What the checker reads is then
// what MuJoCo reads: "&#110;an" is nan, "0&#32;1" two numbers.
std::string xml_value(std::string_view raw) {
  std::string s(raw);
  size_t p = 0, q = 0;  // read and write positions
  while (p < s.size()) {
    if (s[p] != '&') {
      s[q++] = s[p++];
      continue;
    }
    if (p + 1 < s.size() && s[p + 1] == '#') {
      if (p + 2 >= s.size()) {  // "&#" ending the value: tinyxml2 skips the '&'
        ++p;
        continue;
      }
      const auto [code, next] = character_reference(raw, p);
      if (next == 0) {
        s[q++] = s[p++];
        continue;
      }
      // UTF-8 (tinyxml2's ConvertUTF32ToUTF8: nothing past 0x1FFFFF)
      char bytes[4];
      int n = code < 0x80 ? 1 : code < 0x800 ? 2 : code < 0x10000 ? 3 : code < 0x200000 ? 4 : 0;
      unsigned long c = code;
      for (int k = n - 1; k > 0; --k, c >>= 6) bytes[k] = static_cast<char>((c | 0x80) & 0xBF);
      if (n > 0) bytes[0] = static_cast<char>(c | (n == 1 ? 0x00 : n == 2 ? 0xC0 : n == 3 ? 0xE0 : 0xF0));
      // raw and s agree up to p: s is rewritten only behind the read position
      for (int k = 0; k < n; ++k) s[q++] = bytes[k];
      p = next;
      continue;
    }
    bool found = false;
    for (const auto& [name, c] : {std::pair<std::string_view, char>{"quot", '"'}, {"amp", '&'}, {"apos", '\''},
                                  {"lt", '<'}, {"gt", '>'}}) {
      if (raw.substr(p + 1).starts_with(name) && p + 1 + name.size() < raw.size() && raw[p + 1 + name.size()] == ';') {
        s[q++] = c;
        p += name.size() + 2;
        found = true;
        break;
      }
    }
    if (!found) {  // the '&' not copied: the byte at the write position stays
      ++p;
      ++q;
    }
  }
  s.resize(q);
  return s.substr(0, s.find('\0'));
}

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

bool equals_ignoring_case(std::string_view a, std::string_view b) {
  return std::equal(a.begin(), a.end(), b.begin(), b.end(), [](char x, char y) {
    return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
  });
}

// The scan of one file (`file`, included by `path` unless they are the same) and its includes,
// which MuJoCo resolves against `dir`, the top file's folder.
void check_numbers(const std::string& path, const std::string& dir, const std::string& file, int depth) {
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
  int open = 0;  // elements open: the scan ends where the root element does
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
    if (rest.starts_with("</")) {
      i = skip_past(i, ">");
      if (--open <= 0) return;
      continue;
    }
    if (rest.starts_with("<?") || rest.starts_with("<!")) {
      i = skip_past(i, ">");
      continue;
    }
    // MuJoCo reads only the root's children: the top file's root is <mujoco model>, an included
    // file's root is dropped
    const bool root = open == 0;
    bool empty_element = false;  // <.../>
    size_t k = i + 1;
    const size_t name_end = std::min(text.find_first_of(" \t\n\v\f\r/>", k), text.size());
    const std::string_view element = std::string_view(text).substr(k, name_end - k);
    k = name_end;
    while (k < text.size() && text[k] != '>') {  // attributes: name = "value" or 'value'
      const size_t a = text.find_first_not_of(kSpace, k);
      if (a == std::string::npos || text[a] == '>' || text[a] == '/') {
        k = a == std::string::npos ? text.size() : a + 1;
        if (a != std::string::npos && text[a] == '/') empty_element = k < text.size() && text[k] == '>';
        if (a != std::string::npos && text[a] == '>') break;
        continue;
      }
      const size_t a_end = std::min(text.find_first_of(" \t\n\v\f\r=/>", a), text.size());
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
      const std::string_view raw = std::string_view(text).substr(q + 1, q_end - q - 1);
      k = q_end + 1;
      if (root) continue;
      // MuJoCo matches <include> in any case
      if (equals_ignoring_case(element, "include") && attribute == "file") {
        if (depth >= kMaxIncludeDepth) fail(q, element, attribute, raw, "includes nested too deep");
        check_numbers(path, dir, dir + xml_value(raw), depth + 1);
        continue;
      }
      if (!is_numeric(element, attribute)) continue;
      if (const char* problem = numbers_problem(xml_value(raw))) fail(q, element, attribute, raw, problem);
    }
    if (!empty_element)
      ++open;
    else if (root)
      return;
    i = k;
  }
}

}  // namespace

void check_mjcf_numbers(const std::string& path) {
  // MuJoCo's folder of the file (mjuu_getfiledir): up to its last '/' or '\', "" when it has none
  const size_t slash = path.find_last_of("/\\");
  check_numbers(path, slash == std::string::npos ? "" : path.substr(0, slash + 1), path, 0);
}

}  // namespace ldlpgs
