// The bad-input matrix, session JSON (issue 16). Sessions are read only by the window (kfw
// --session, File → Open session…), both through load_session — the entry point tested here: every
// bad file is an error (exit 2) in one line naming the file and line:column or key, in bounded
// time; BOM and CRLF files load like their plain twins.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>

#include "document/session.h"

namespace kfw {
namespace {

class BadSession : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = std::filesystem::path(::testing::TempDir()) /
          ("kfw_bad_session_" +
           std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
  }
  std::string file(const std::string& name, const std::string& text) const {
    const auto p = (dir / name).string();
    std::ofstream(p, std::ios::binary) << text;
    return p;
  }
  static std::string good() {
    Session s;
    s.preset_path = "presets/helicopter.json";
    s.scenario = "helicopter";
    s.values = {{"Q", 67.24}, {"R", 1.96}};
    s.snapshots.push_back({"a", {{"Q", 1.0}}});
    return session_to_json(s);
  }
  std::string edited(const std::string& name, const std::string& from, const std::string& to) {
    std::string t = good();
    const auto at = t.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) t.replace(at, from.size(), to);
    return file(name, t);
  }
  void refused(const std::string& path, std::initializer_list<std::string> fragments) {
    const auto start = std::chrono::steady_clock::now();
    auto s = load_session(path);
    SCOPED_TRACE(path);
    ASSERT_FALSE(s.ok());
    EXPECT_EQ(s.exit_code(), kExitInvalid);
    EXPECT_EQ(s.error().rfind(path, 0), 0u) << s.error();
    for (const auto& f : fragments)
      EXPECT_NE(s.error().find(f), std::string::npos) << "'" << f << "' not in: " << s.error();
    EXPECT_EQ(s.error().find('\n'), std::string::npos) << s.error();
    EXPECT_LT(s.error().size(), 600u) << s.error().substr(0, 600);
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(5));
  }
  std::filesystem::path dir;
};

TEST_F(BadSession, EmptyBinaryAndMalformed) {
  refused(file("empty.json", ""), {});
  refused(file("nul.json", std::string("{\"format\": \0}", 13)), {":1:"});
  refused(file("trunc.json", good().substr(0, 60)), {":"});
  refused(file("array.json", "[]"), {"object"});
  refused(edited("comma.json", "\"scenario\"", ",\"scenario\""), {"comma.json:"});
}

TEST_F(BadSession, ByteOrderMarkAndCrlfLoad) {
  std::string crlf;
  for (char c : good()) {
    if (c == '\n') crlf += '\r';
    crlf += c;
  }
  auto a = load_session(file("plain.json", good()));
  auto b = load_session(file("bom.json", "\xEF\xBB\xBF" + good()));
  auto c = load_session(file("crlf.json", crlf));
  ASSERT_TRUE(a.ok()) << a.error();
  ASSERT_TRUE(b.ok()) << b.error();
  ASSERT_TRUE(c.ok()) << c.error();
  EXPECT_EQ(b->values, a->values);
  EXPECT_EQ(c->snapshots, a->snapshots);
}

TEST_F(BadSession, NumbersTypesAndKeys) {
  refused(edited("ovf.json", "67.24", "1e999"), {"values.Q", "overflows"});
  refused(edited("nan.json", "67.24", "NaN"), {"nan.json:"});
  refused(edited("nantext.json", "67.24", "\"nan\""), {"values.Q", "number"});
  // Sessions are written as version 3 (issue 27).
  refused(edited("version.json", "\"version\": 3", "\"version\": 4294967297"), {"version"});
  refused(edited("format.json", "kfw-session", "kfw-preset"), {"format"});
  refused(edited("values.json", "\"values\": {", "\"values\": 3, \"x\": {"), {"values"});
  refused(edited("preset.json", "\"preset\": \"presets/helicopter.json\"", "\"preset\": 1"),
          {"preset"});
  refused(edited("snap.json", "\"name\": \"a\"", "\"name\": 5"), {"snapshot"});
  refused(
      edited("mapping.json", "\"mapping\": {}", "\"mapping\": {\"gyro\": {\"unit\": \"furlong\"}}"),
      {"mapping.gyro.unit"});
}

TEST_F(BadSession, LimitsAndPaths) {
  refused(edited("deep.json", "\"window\"",
                 "\"x\": " + std::string(300, '[') + std::string(300, ']') + ", \"window\""),
          {"256"});
  refused(edited("big.json", "\"window\": \"", "\"window\": \"" + std::string(11u << 20, 'a')),
          {"10 MB"});
  refused((dir / "absent.json").string(), {"cannot open"});
  std::filesystem::create_directories(dir / "folder.json");
  refused((dir / "folder.json").string(), {"directory"});
}

}  // namespace
}  // namespace kfw
