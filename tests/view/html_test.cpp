// view/html.cpp: the page's encoding (RFC 4648's own examples), its data block against the
// recording it holds, and what no scene name can break.
#include "view/html.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstring>
#include <sstream>
#include <string>

#include "ldlpgs/physics/io/scenes.h"

namespace ldlpgs::view {
namespace {

TEST(Base64, Rfc4648Examples) {
  const std::pair<const char*, const char*> cases[] = {{"", ""},         {"f", "Zg=="},     {"fo", "Zm8="},
                                                       {"foo", "Zm9v"},  {"foob", "Zm9vYg=="}, {"fooba", "Zm9vYmE="},
                                                       {"foobar", "Zm9vYmFy"}};
  for (const auto& [in, out] : cases) EXPECT_EQ(base64(in, std::strlen(in)), out) << in;
  const unsigned char high[] = {0xfb, 0xff, 0xbf};  // the alphabet's last two digits, + and /
  EXPECT_EQ(base64(high, 3), "+/+/");
}

// Decodes base64 back to bytes (the test's own, plain decoder).
std::string decoded(const std::string& text) {
  const std::string digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  unsigned bits = 0, value = 0;
  for (char c : text) {
    if (c == '=') break;
    value = value << 6 | static_cast<unsigned>(digits.find(c));
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out += static_cast<char>(value >> bits & 0xff);
    }
  }
  return out;
}

Recording recorded(const Mechanism& m, int steps) {
  ShatterResult whole;
  whole.mechanism = m;
  for (size_t i = 0; i < m.bodies.size(); ++i) whole.shards.push_back({static_cast<int>(i)});
  Recording r(m, whole);
  StepOptions o;
  o.diagnostics = true;
  Simulation sim(m, o);
  for (int s = 0; s < steps; ++s) r.add(sim, sim.step());
  r.finish(sim);
  return r;
}

// The data block is JSON whose arrays decode to the recording's own numbers.
TEST(PageData, HoldsTheRecording) {
  Mechanism m;
  ASSERT_TRUE(builtin_scene("box-stack-1000", &m));
  const Recording r = recorded(m, 40);
  const nlohmann::json j = nlohmann::json::parse(page_data(r));
  EXPECT_EQ(j["scene"], "box-stack-1000");
  EXPECT_EQ(j["frames"], r.frames());
  EXPECT_EQ(j["solids"].size(), r.solids().size());
  EXPECT_EQ(j["static"].size(), m.bodies.size());
  const std::string positions = decoded(j["positions"].get<std::string>());
  ASSERT_EQ(positions.size(), r.positions().size() * sizeof(float));
  EXPECT_EQ(std::memcmp(positions.data(), r.positions().data(), positions.size()), 0);
  const std::string contacts = decoded(j["contacts"].get<std::string>());
  ASSERT_EQ(contacts.size(), r.contacts().size() * sizeof(float));
  ASSERT_GT(contacts.size(), 0u);
  EXPECT_EQ(std::memcmp(contacts.data(), r.contacts().data(), contacts.size()), 0);
  EXPECT_EQ(decoded(j["orientations"].get<std::string>()).size(), r.orientations().size() * sizeof(int16_t));
}

// A body or scene named "</script>..." cannot end the script element that holds the data:
// the block has no '<' at all, and reads back as the same name.
TEST(PageData, NoNameEndsTheScript) {
  Mechanism m;
  ASSERT_TRUE(builtin_scene("pendulum", &m));
  m.name = "</script><script>alert(1)</script><!--";
  m.bodies[0].name = "</SCRIPT>";
  const Recording r = recorded(m, 2);
  const std::string data = page_data(r);
  EXPECT_EQ(data.find('<'), std::string::npos);
  const nlohmann::json j = nlohmann::json::parse(data);
  EXPECT_EQ(j["scene"], m.name);
  EXPECT_EQ(j["groups"][0], "</SCRIPT>");
  std::ostringstream page;
  write_html(r, page);
  const std::string html = page.str();
  EXPECT_EQ(html.find("</script><script>alert"), std::string::npos);
  EXPECT_NE(html.find("<title>ldlpgs view: &lt;/script&gt;&lt;script&gt;alert(1)&lt;/script&gt;&lt;!--</title>"), std::string::npos);
}

// The page: three.js and OrbitControls inlined (nothing fetched), every marker replaced.
TEST(WriteHtml, IsOneSelfContainedPage) {
  Mechanism m;
  ASSERT_TRUE(builtin_scene("pendulum", &m));
  std::ostringstream page;
  write_html(recorded(m, 5), page);
  const std::string html = page.str();
  EXPECT_EQ(html.rfind("<!doctype html>", 0), 0u);
  for (const char* marker : {"{{title}}", "{{three}}", "{{orbit_controls}}", "{{data}}"})
    EXPECT_EQ(html.find(marker), std::string::npos) << marker;
  EXPECT_NE(html.find("REVISION=\"111\""), std::string::npos);  // three.min.js
  EXPECT_NE(html.find("OrbitControls"), std::string::npos);
  EXPECT_EQ(html.find("<script src"), std::string::npos);
  EXPECT_EQ(html.find("<link"), std::string::npos);
  EXPECT_GT(html.size(), 800000u);
}

}  // namespace
}  // namespace ldlpgs::view
