// Hardening round 2 (issue 29), the type fuzz: every JSON node of each input kind — a preset, a
// model file, a session (versions 2 and 3), a mapping, a Monte Carlo and a sweep part — replaced
// in turn by each other JSON type
// and by ±1e308. Each case loads (a value) or is refused with exit 2 and a one-line message that
// names the file; never an exception, never exit 1 from a parse. The cases that load are listed in
// type_fuzz_loaded_<kind>.txt in the test's working folder (the build's tests/). Before (the
// report's 920 cases): 7 aborts on uncaught type errors and 130 silent or vague outcomes, all in
// merge.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <sstream>

#include "data/mapping.h"
#include "document/preset.h"
#include "document/session.h"
#include "experiment/monte_carlo.h"
#include "experiment/sweep_part.h"

namespace kfw {
namespace {

using nlohmann::json;

json read_json(const std::string& rel) {
  std::ifstream in(std::string(KFW_SOURCE_DIR) + "/" + rel);
  return json::parse(in);
}

// Every node's JSON pointer, the root excluded.
void pointers(const json& j, const json::json_pointer& at, std::vector<json::json_pointer>& out) {
  if (j.is_object()) {
    for (const auto& [k, v] : j.items()) {
      out.push_back(at / k);
      pointers(v, at / k, out);
    }
  } else if (j.is_array()) {
    for (std::size_t i = 0; i < j.size(); ++i) {
      out.push_back(at / i);
      pointers(j[i], at / i, out);
    }
  }
}

struct Outcome {
  bool ok = false;
  int code = 0;
  std::string message;
};

// Replaces each node by each replacement and loads the result with `load`; returns the cases that
// load ("/values/Q = 2.5").
std::vector<std::string> fuzz_types(const json& base, const std::string& file,
                                    const std::function<Outcome(const json&)>& load) {
  const std::vector<json> replacements = {nullptr,       true,          0, 2.5, -1e308, 1e308, "x",
                                          json::array(), json::object()};
  std::vector<json::json_pointer> nodes;
  pointers(base, json::json_pointer(), nodes);
  std::vector<std::string> loaded;
  for (const auto& at : nodes) {
    for (const auto& r : replacements) {
      json j = base;
      j[at] = r;
      Outcome o;
      try {
        o = load(j);
      } catch (const std::exception& e) {
        ADD_FAILURE() << file << " " << at.to_string() << " = " << r.dump()
                      << ": an exception escaped: " << e.what();
        continue;
      }
      if (o.ok) {
        loaded.push_back(at.to_string() + " = " + r.dump());
        continue;
      }
      EXPECT_EQ(o.code, 2) << file << " " << at.to_string() << " = " << r.dump() << ": "
                           << o.message;
      EXPECT_EQ(o.message.find('\n'), std::string::npos) << o.message;
      EXPECT_NE(o.message.find(file), std::string::npos)
          << at.to_string() << " = " << r.dump() << ": " << o.message;
    }
  }
  return loaded;
}

// Lists the cases of one input kind that load, one per line, and says how many.
void list_loaded(const std::string& kind, const std::vector<std::string>& cases) {
  const std::string file = "type_fuzz_loaded_" + kind + ".txt";
  std::ofstream out(file);
  for (const auto& c : cases)
    out << c << "\n";
  std::cout << kind << ": " << cases.size() << " replaced nodes load (listed in " << file << ")\n";
}

template <class T>
Outcome outcome(const Expected<T>& e) {
  return e ? Outcome{true, 0, {}} : Outcome{false, e.exit_code(), e.error()};
}

TEST(TypeFuzz, PresetsAndModelFiles) {
  for (const char* rel : {"presets/helicopter.json", "presets/models/cv1d.json",
                          "presets/models/range_bearing.json"}) {
    const json base = read_json(rel);
    const auto loaded = fuzz_types(base, "fuzz.json", [](const json& j) {
      return outcome(parse_preset(j.dump(), "fuzz.json"));
    });
    list_loaded(std::filesystem::path(rel).stem().string(), loaded);
  }
}

TEST(TypeFuzz, Sessions) {
  const json v2 = read_json("tests/fixtures/session_v2/helicopter.json");
  auto s = parse_session(v2.dump(), "fuzz.session.json");
  ASSERT_TRUE(s.ok()) << s.error();
  // Version 3, as this build writes it (unknown keys refused).
  const json v3 = json::parse(session_to_json(*s));
  ASSERT_EQ(v3.at("version"), 3);
  for (const json& base : {v2, v3}) {
    const auto loaded = fuzz_types(base, "fuzz.session.json", [](const json& j) {
      return outcome(parse_session(j.dump(), "fuzz.session.json"));
    });
    list_loaded("session_v" + base.at("version").dump(), loaded);
  }
}

TEST(TypeFuzz, Mappings) {
  const json base = json::parse(R"({"t": {"column": "time_ms", "unit": "ms"},
      "gyro": {"column": "omega", "unit": "rad/s", "scale": 2, "offset": 1, "flip": true},
      "angle": "roll", "separator": ";", "header": "first"})");
  ASSERT_TRUE(mapping_from_json(base, "map.json: mapping").ok());
  const auto loaded = fuzz_types(base, "map.json", [](const json& j) {
    return outcome(mapping_from_json(j, "map.json: mapping"));
  });
  list_loaded("mapping", loaded);
}

TEST(TypeFuzz, MonteCarloParts) {
  const std::string dir = std::string(KFW_SOURCE_DIR) + "/tests/fuzz/corpus/montecarlo_part";
  // The corpus's first valid version-2 part.
  json base;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    std::ifstream in(e.path());
    json j = json::parse(in, nullptr, false);
    if (j.is_object() && j.value("version", json()) == 2 && part_from_json(j, "p").ok()) {
      base = j;
      break;
    }
  }
  ASSERT_TRUE(base.is_object());
  const auto loaded = fuzz_types(base, "part.json", [](const json& j) -> Outcome {
    auto p = part_from_json(j, "part.json");
    if (!p) return outcome(p);
    auto m = merge_montecarlo_parts({*p}, {"part.json"});
    return outcome(m);
  });
  list_loaded("montecarlo_part", loaded);
}

// Found by the session fuzzer: a key with a newline, inside a session's mapping, was echoed raw
// in "unknown key", a message of two lines. Every key path shows control bytes escaped.
TEST(TypeFuzz, ControlBytesInKeysAreEscaped) {
  const json m = json::parse(R"({"angle": {"column": "x", "offse\nt": 1}})");
  auto r = mapping_from_json(m, "s.json: mapping");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().find('\n'), std::string::npos) << r.error();
  EXPECT_NE(r.error().find("s.json: mapping.angle.offse\\nt: unknown key"), std::string::npos)
      << r.error();
}

// Found by the session fuzzer: a role with a unit and no column ("t": {"unit": "ms"}) was written
// with its own name as the column, so a saved session's mapping read back as another mapping.
TEST(TypeFuzz, AMappingWithoutAColumnReadsBackAsItWas) {
  const json base = json::parse(R"({"t": {"unit": "ms"}, "gyro": {}, "angle": "roll"})");
  auto m = mapping_from_json(base, "m.json: mapping");
  ASSERT_TRUE(m.ok()) << m.error();
  auto again = mapping_from_json(json::parse(mapping_to_json(*m).dump()), "again.json: mapping");
  ASSERT_TRUE(again.ok()) << again.error();
  EXPECT_TRUE(*again == *m) << mapping_to_json(*m).dump();
}

TEST(TypeFuzz, SweepParts) {
  const json base = read_json("tests/fuzz/corpus/sweep_part/cv1d_whole.json");
  ASSERT_TRUE(check_sweep_part(base, "p").ok());
  const auto loaded = fuzz_types(base, "part.json", [](const json& j) {
    return outcome(merge_sweep_documents({j}, {"part.json"}));
  });
  list_loaded("sweep_part", loaded);
}

}  // namespace
}  // namespace kfw
