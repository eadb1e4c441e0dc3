#include "data/mapping.h"

#include <cmath>

#include "data/json_io.h"

namespace kfw {

using nlohmann::json;

namespace {

struct UnitInfo {
  const char* name;
  const char* kind;
  double si;  // value in the kind's base unit for 1 of this unit
};

constexpr double kPi = 3.14159265358979323846;
constexpr UnitInfo kUnits[] = {
    {"s", "time", 1.0},           {"ms", "time", 1e-3},        {"us", "time", 1e-6},
    {"ns", "time", 1e-9},         {"deg", "angle", kPi / 180}, {"rad", "angle", 1.0},
    {"deg/s", "rate", kPi / 180}, {"rad/s", "rate", 1.0},      {"m/s^2", "accel", 1.0},
    {"g", "accel", 9.80665},      {"m", "length", 1.0},        {"mm", "length", 1e-3},
};

const UnitInfo* find_unit(const std::string& u) {
  for (const auto& i : kUnits) {
    if (u == i.name) return &i;
  }
  return nullptr;
}

}  // namespace

const std::vector<std::string>& known_units() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> v;
    for (const auto& i : kUnits)
      v.emplace_back(i.name);
    return v;
  }();
  return names;
}

Expected<double> unit_factor(const std::string& from, const std::string& to) {
  if (from.empty() || to.empty() || from == to) return 1.0;
  const UnitInfo* a = find_unit(from);
  const UnitInfo* b = find_unit(to);
  std::string list;
  for (const auto& n : known_units())
    list += (list.empty() ? "" : ", ") + n;
  if (!a) return Error{"unknown unit '" + from + "' (known: " + list + ")"};
  if (!b) return Error{"cannot convert to '" + to + "': not a unit kfw converts (" + list + ")"};
  if (std::string(a->kind) != b->kind) {
    return Error{"cannot convert '" + from + "' to '" + to + "' (a " + a->kind + " and a " +
                 b->kind + ")"};
  }
  return a->si / b->si;
}

bool is_iso_unit(const std::string& unit) {
  return unit == "iso" || (unit.size() > 4 && unit.compare(0, 4, "iso@") == 0);
}

std::string iso_zone(const std::string& unit) {
  return is_iso_unit(unit) && unit.size() > 4 ? unit.substr(4) : std::string();
}

void Mapping::override_with(const Mapping& over) {
  for (const auto& [role, r] : over)
    (*this)[role] = r;
  if (over.separator) separator = over.separator;
  if (over.header != HeaderRow::detect) header = over.header;
}

TableOptions Mapping::table_options() const {
  TableOptions o;
  o.separator = separator;
  o.header = header;
  return o;
}

Expected<Mapping> mapping_from_json(const json& j, const std::string& where) {
  if (!j.is_object()) return Error{where + ": must be an object of role -> column"};
  Mapping m;
  for (auto it = j.begin(); it != j.end(); ++it) {
    const std::string at = key_path(where, it.key());
    if (it.key() == "sep" || it.key() == "header") {  // how the file is read, not a role
      if (!it->is_string()) return Error{at + ": must be a string, not " + json_type_name(*it)};
      const std::string v = it->get<std::string>();
      if (it.key() == "sep") {
        auto s = parse_separator(v);
        if (!s) return Error{at + ": " + s.error()};
        m.separator = *s;
      } else {
        auto h = parse_header_row(v);
        if (!h) return Error{at + ": " + h.error()};
        m.header = *h;
      }
      continue;
    }
    RoleMapping r;
    if (it->is_string()) {
      r.column = it->get<std::string>();
    } else if (it->is_object()) {
      for (auto f = it->begin(); f != it->end(); ++f) {
        const std::string fk = key_path(at, f.key());
        if (f.key() == "column" || f.key() == "unit") {
          if (!f->is_string()) return Error{fk + ": must be a string, not " + json_type_name(*f)};
          (f.key() == "column" ? r.column : r.unit) = f->get<std::string>();
        } else if (f.key() == "scale" || f.key() == "offset") {
          if (!f->is_number()) return Error{fk + ": must be a number, not " + json_type_name(*f)};
          (f.key() == "scale" ? r.scale : r.offset) = f->get<double>();
        } else if (f.key() == "flip") {
          if (!f->is_boolean()) return Error{fk + ": must be true or false"};
          r.flip = f->get<bool>();
        } else {
          return Error{fk + ": unknown key (column, unit, scale, offset, flip)"};
        }
      }
      if (r.scale == 0.0) return Error{key_path(at, "scale") + ": must not be 0"};
      if (!std::isfinite(r.scale) || !std::isfinite(r.offset))
        return Error{at + ": scale and offset must be finite"};
    } else {
      return Error{at + ": must be a column name or an object, not " + json_type_name(*it)};
    }
    if (is_iso_unit(r.unit) && it.key() != "t") {
      return Error{key_path(at, "unit") +
                   ": 'iso' (an ISO-8601 date-time) is for the time 't' only"};
    }
    if (!r.unit.empty() && !is_iso_unit(r.unit) && !find_unit(r.unit)) {
      return Error{key_path(at, "unit") + ": " + unit_factor(r.unit, "s").error()};
    }
    m[it.key()] = r;
  }
  return m;
}

nlohmann::ordered_json mapping_to_json(const Mapping& m) {
  nlohmann::ordered_json j = nlohmann::ordered_json::object();
  if (m.separator) j["sep"] = separator_key(m.separator);
  if (m.header != HeaderRow::detect) j["header"] = header_row_name(m.header);
  for (const auto& [role, r] : m) {
    if (r.unit.empty() && r.scale == 1.0 && r.offset == 0.0 && !r.flip && !r.column.empty()) {
      j[role] = r.column;
      continue;
    }
    // No column: the role reads the column a guess or another mapping gives it, else the one of
    // its own name; written as no "column", so the mapping reads back as it was.
    nlohmann::ordered_json e = nlohmann::ordered_json::object();
    if (!r.column.empty()) e["column"] = r.column;
    if (!r.unit.empty()) e["unit"] = r.unit;
    if (r.scale != 1.0) e["scale"] = r.scale;
    if (r.offset != 0.0) e["offset"] = r.offset;
    if (r.flip) e["flip"] = true;
    j[role] = e;
  }
  return j;
}

}  // namespace kfw
