#include "document/command_line.h"

#include <charconv>
#include <cmath>

#include "data/table.h"

namespace kfw {

namespace {

// The shortest text that reads back to the same double.
std::string exact(double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

}  // namespace

std::vector<std::string> mapping_args(const Mapping& m) {
  std::vector<std::string> a;
  if (auto t = m.find("t"); t != m.end() && !t->second.column.empty()) {
    a.insert(a.end(),
             {"--time", t->second.column + (t->second.unit.empty() ? "" : ":" + t->second.unit)});
  }
  for (const auto& [role, r] : m) {
    if (role == "t") continue;
    if (!r.column.empty()) a.insert(a.end(), {"--map", role + "=" + r.column});
    if (!r.unit.empty()) a.insert(a.end(), {"--unit", role + "=" + r.unit});
    if (r.scale != 1.0) a.insert(a.end(), {"--scale", role + "=" + exact(r.scale)});
    if (r.offset != 0.0) a.insert(a.end(), {"--offset", role + "=" + exact(r.offset)});
    if (r.flip) a.insert(a.end(), {"--flip", role});
  }
  if (m.separator) a.insert(a.end(), {"--sep", separator_key(m.separator)});
  if (m.header != HeaderRow::detect) a.insert(a.end(), {"--header", header_row_name(m.header)});
  return a;
}

std::vector<std::string> document_args(const Document& doc) {
  const Preset& p = doc.preset();
  std::vector<std::string> a{p.path.empty() ? p.scenario : p.path};
  const auto& data = doc.data();
  const bool preset_data = data && p.data_path && data->path == *p.data_path;
  if (data && !preset_data) a.insert(a.end(), {"--data", data->path});
  if (data && !(preset_data && data->mapping == p.mapping)) {
    const auto m = mapping_args(data->mapping);
    a.insert(a.end(), m.begin(), m.end());
  }
  for (const auto& [key, v] : doc.values()) {
    auto it = p.values.find(key);
    if (it != p.values.end() && (it->second == v || (std::isnan(it->second) && std::isnan(v))))
      continue;
    a.insert(a.end(), {"--set", key + "=" + exact(v)});
  }
  return a;
}

std::string shell_quote(const std::string& arg) {
  const bool plain = !arg.empty() && arg.find_first_not_of(
                                         "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz"
                                         "0123456789_./=:+-,@%") == std::string::npos;
  if (plain) return arg;
  std::string out = "'";
  for (char c : arg)
    out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

std::string command_lines(const Document& doc) {
  std::string args;
  for (const auto& a : document_args(doc))
    args += " " + shell_quote(a);
  std::string out = "kfw-cli run" + args + "\nkfw --export plots" + args + "\n";
  // The command line has no switch from a preset's own log to simulated data.
  if (!doc.data() && doc.preset().data_path) {
    out += "# the window simulates data; these commands read the preset's log " +
           shell_quote(*doc.preset().data_path) + "\n";
  }
  return out;
}

}  // namespace kfw
