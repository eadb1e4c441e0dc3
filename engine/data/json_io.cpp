#include "data/json_io.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <memory>
#include <ostream>
#include <sstream>
#include <unordered_map>
#include <vector>

#include "core/suggest.h"
#include "data/input_file.h"

namespace kfw {

using nlohmann::json;

namespace {

// A SAX pass that keeps the dotted path of the value being read, so that an error can name it.
class PathTracker final : public nlohmann::json_sax<json> {
 public:
  std::string error;                     // "path: text" once something is wrong
  std::size_t byte = std::string::npos;  // where, when the parser knows

  bool null() override { return value(); }
  bool boolean(bool) override { return value(); }
  bool number_integer(number_integer_t) override { return value(); }
  bool number_unsigned(number_unsigned_t) override { return value(); }
  bool number_float(number_float_t v, const string_t&) override {
    if (!std::isfinite(v)) return fail("number is not finite");
    return value();
  }
  bool string(string_t&) override { return value(); }
  bool binary(binary_t&) override { return value(); }
  bool start_object(std::size_t) override { return open(false); }
  bool key(string_t& k) override {
    stack_.back().key = k;
    return true;
  }
  bool end_object() override { return close(); }
  bool start_array(std::size_t) override { return open(true); }
  bool end_array() override { return close(); }
  bool parse_error(std::size_t position, const std::string&,
                   const nlohmann::detail::exception& ex) override {
    byte = position == 0 ? 0 : position - 1;
    std::string what = ex.what();
    if (auto p = what.find("] "); p != std::string::npos) what = what.substr(p + 2);
    if (auto p = what.find("parse error at line"); p != std::string::npos) {
      if (auto q = what.find(": ", p); q != std::string::npos) what = what.substr(q + 2);
    }
    if (ex.id == 406) what = "number overflows a double";
    // nlohmann echoes the whole token read so far (a string of any length, control characters
    // included): cut and made printable like every echoed token.
    static constexpr std::string_view kLastRead = "; last read: '";
    if (auto b = what.find(kLastRead); b != std::string::npos) {
      b += kLastRead.size();
      const auto e = what.rfind('\'');
      if (e != std::string::npos && e >= b)
        what = what.substr(0, b) + truncate_token(std::string_view(what).substr(b, e - b)) +
               what.substr(e);
    }
    return fail(truncate_token(what, 400));
  }

 private:
  struct Level {
    bool array = false;
    std::size_t index = 0;
    std::string key;
  };
  std::vector<Level> stack_;

  std::string path() const {
    std::string p;
    for (const auto& l : stack_) {
      if (l.array) {
        p = index_path(p, l.index);
      } else if (!l.key.empty()) {
        p = key_path(p, l.key);
      }
    }
    return p;
  }
  bool value() {
    if (!stack_.empty() && stack_.back().array) ++stack_.back().index;
    return true;
  }
  bool open(bool array) {
    if (stack_.size() >= kMaxJsonDepth) {
      return fail("nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
    }
    stack_.push_back({array, 0, {}});
    return true;
  }
  bool close() {
    stack_.pop_back();
    return value();
  }
  bool fail(const std::string& what) {
    const std::string p = truncate_token(path());  // 256 levels or a huge key: cut
    error = (p.empty() ? "" : p + ": ") + what;
    return false;
  }
};

std::string line_col_of(const std::string& text, std::size_t byte) {
  std::size_t line = 1, col = 1;
  for (std::size_t i = 0; i < byte && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      col = 1;
    } else {
      ++col;
    }
  }
  return std::to_string(line) + ":" + std::to_string(col);
}

}  // namespace

std::string key_path(std::string_view parent, std::string_view key) {
  // The key as messages show any token from a file: control bytes as \xNN, long keys cut.
  const std::string shown = truncate_token(key);
  return parent.empty() ? shown : std::string(parent) + "." + shown;
}

std::string index_path(std::string_view parent, std::size_t index) {
  return std::string(parent) + "[" + std::to_string(index) + "]";
}

std::string json_type_name(const json& j) {
  if (j.is_null()) return "null";
  if (j.is_boolean()) return "a boolean";
  if (j.is_number()) return "a number";
  if (j.is_string()) return "a string";
  if (j.is_array()) return "an array";
  if (j.is_object()) return "an object";
  return "a value";
}

namespace {

// The checks before a DOM parse: the size limit, then a SAX pass that stops at the first problem
// with the key path (the DOM parse after it cannot fail on anything the pass accepted).
Status check_json_text(const std::string& text, const std::string& path) {
  if (text.size() > kMaxJsonBytes) {
    return Error{path + ": " + std::to_string(text.size()) + " bytes: larger than the " +
                 std::to_string(kMaxJsonBytes / (1024 * 1024)) + " MB limit for a JSON file"};
  }
  PathTracker tracker;
  if (!json::sax_parse(text, &tracker, json::input_format_t::json, true)) {
    std::string where = path;
    if (tracker.byte != std::string::npos) where += ":" + line_col_of(text, tracker.byte);
    return Error{where + ": " + (tracker.error.empty() ? "invalid JSON" : tracker.error)};
  }
  return Ok{};
}

// Builds an ordered document from SAX events, each key found through a hash table: nlohmann's own
// parser inserts a key of an ordered object after a linear search for it (a 10 MB object of short
// keys took minutes). A repeated key keeps its first place and its last value, as there.
class OrderedBuilder final : public nlohmann::json_sax<nlohmann::ordered_json> {
 public:
  using OJson = nlohmann::ordered_json;
  OJson root;

  bool null() override { return put(nullptr); }
  bool boolean(bool v) override { return put(v); }
  bool number_integer(number_integer_t v) override { return put(v); }
  bool number_unsigned(number_unsigned_t v) override { return put(v); }
  bool number_float(number_float_t v, const string_t&) override { return put(v); }
  bool string(string_t& v) override { return put(std::move(v)); }
  bool binary(binary_t& v) override { return put(OJson::binary(std::move(v))); }
  bool start_object(std::size_t) override { return open(OJson::object()); }
  bool key(string_t& k) override {
    Level& l = stack_.back();
    OJson::object_t::Container& items = l.value->get_ref<OJson::object_t&>();
    const auto [at, fresh] = l.index.try_emplace(k, items.size());
    if (fresh) items.emplace_back(k, nullptr);
    l.slot = &items[at->second].second;
    return true;
  }
  bool end_object() override { return close(); }
  bool start_array(std::size_t) override { return open(OJson::array()); }
  bool end_array() override { return close(); }
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) override {
    return false;
  }

 private:
  struct Level {
    OJson* value;
    std::unordered_map<std::string, std::size_t> index;  // key -> place (objects)
    OJson* slot;                                         // the value of the last key
  };
  std::vector<Level> stack_;  // a container's place is stable while it is open

  OJson* place(OJson v) {
    if (stack_.empty()) {
      root = std::move(v);
      return &root;
    }
    Level& l = stack_.back();
    if (l.value->is_array()) {
      l.value->push_back(std::move(v));
      return &l.value->back();
    }
    *l.slot = std::move(v);
    return l.slot;
  }
  bool put(OJson v) {
    place(std::move(v));
    return true;
  }
  bool open(OJson v) {
    stack_.push_back({place(std::move(v)), {}, nullptr});
    return true;
  }
  bool close() {
    stack_.pop_back();
    return true;
  }
};

limits::Input json_kind(std::string_view what) {
  if (what == "session") return limits::Input::kSession;
  if (what == "mapping") return limits::Input::kMapping;
  if (what == "part") return limits::Input::kPart;
  if (what == "model") return limits::Input::kModel;
  return limits::Input::kPreset;
}

Expected<std::string> read_json_text(const std::string& path, const char* what) {
  return read_input_file(path, json_kind(what));
}

}  // namespace

Expected<json> parse_json_document(const std::string& text, const std::string& path) {
  if (auto st = check_json_text(text, path); !st) return st.err();
  try {
    return json::parse(text);
  } catch (const json::exception& e) {
    return Error{path + ": invalid JSON: " + std::string(e.what())};
  }
}

Expected<nlohmann::ordered_json> parse_ordered_json_document(const std::string& text,
                                                             const std::string& path) {
  if (auto st = check_json_text(text, path); !st) return st.err();
  OrderedBuilder builder;
  if (!nlohmann::ordered_json::sax_parse(text, &builder)) return Error{path + ": invalid JSON"};
  return std::move(builder.root);
}

Expected<json> read_json_document(const std::string& path, const char* what) {
  auto text = read_json_text(path, what);
  if (!text) return text.err();
  return parse_json_document(*text, path);
}

Expected<nlohmann::ordered_json> read_ordered_json_document(const std::string& path,
                                                            const char* what) {
  auto text = read_json_text(path, what);
  if (!text) return text.err();
  return parse_ordered_json_document(*text, path);
}

namespace {
template <class Json>
Status stage_json_doc(OutputSet& outs, const std::string& path, Json doc, int indent) {
  auto held = std::make_shared<const Json>(std::move(doc));
  return outs.stage_stream(path, [held, indent](OutputStream& out) -> Status {
    OutputStreamBuf buf(out);
    std::ostream os(&buf);
    os << std::setw(indent) << *held << '\n';
    return Ok{};
  });
}
}  // namespace

Status stage_json(OutputSet& outs, const std::string& path, nlohmann::json doc, int indent) {
  return stage_json_doc(outs, path, std::move(doc), indent);
}

Status stage_json(OutputSet& outs, const std::string& path, nlohmann::ordered_json doc,
                  int indent) {
  return stage_json_doc(outs, path, std::move(doc), indent);
}

}  // namespace kfw
