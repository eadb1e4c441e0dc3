// The import acceptance files (issue 13), generated in a temporary directory from the real BROAD
// log (never copied into the repository): the same rows in kfw's own format and in four foreign
// layouts, each holding values that convert back to the kfw file's to about 1e-15.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "core/dataset.h"
#include "data/csv.h"

namespace kfw::testing {

inline const std::string kRealLog =
    std::string(KFW_SHARED_DIR) + "/data/broad/10_undisturbed_slow_translation_A.csv";

struct ImportFiles {
  std::string reference;  // t,gyro,angle,truth (kfw's format)
  std::string units;      // time_ms,omega_rads,acc_roll_deg,ref_roll_deg (a complete guess)
  std::string german;     // Zeit;Drehrate;Winkel;Referenz, decimal comma, Drehrate in rad/s
  std::string tabs;       // tab-separated with # comment lines: time gyro_dps roll_deg truth_deg
  std::string iso;        // timestamp (ISO-8601, +02:00),gyro,angle,truth
  std::size_t rows = 0;
};

inline std::string g17(double v) {
  if (std::isnan(v)) return "";
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

// 2024-05-01T12:00:00+02:00 plus `ns` nanoseconds, written with the offset.
inline std::string iso_at(long long ns) {
  const long long s = ns / 1000000000LL, frac = ns % 1000000000LL;
  const long long h = 12 + s / 3600, m = (s / 60) % 60, sec = s % 60;
  char b[64];
  std::snprintf(b, sizeof b, "2024-05-01T%02lld:%02lld:%02lld.%09lld+02:00", h, m, sec, frac);
  return b;
}

// The first `rows` rows of the real log, in each layout, under `dir`. False when the log is absent.
inline bool make_import_files(const std::filesystem::path& dir, std::size_t rows, ImportFiles& f) {
  auto log = read_csv(kRealLog);
  if (!log) return false;
  Dataset d;
  d.names = {"t", "gyro", "angle", "truth"};
  for (const auto& n : d.names) {
    const auto& c = log->col(n);
    d.columns.emplace_back(c.begin(),
                           c.begin() + static_cast<std::ptrdiff_t>(std::min(rows, c.size())));
  }
  f.rows = d.rows();
  f.reference = (dir / "reference.csv").string();
  std::ofstream(f.reference) << [&] {
    std::ostringstream os;
    write_csv(os, d);
    return os.str();
  }();
  const double rad = 3.14159265358979323846 / 180.0;
  const auto& t = d.col("t");
  const auto& gyro = d.col("gyro");
  const auto& angle = d.col("angle");
  const auto& truth = d.col("truth");
  f.units = (dir / "units.csv").string();
  f.german = (dir / "german.csv").string();
  f.tabs = (dir / "tabs.tsv").string();
  f.iso = (dir / "iso.csv").string();
  std::ofstream u(f.units), g(f.german), tb(f.tabs), iso(f.iso);
  u << "time_ms,omega_rads,acc_roll_deg,ref_roll_deg\n";
  g << "Zeit;Drehrate;Winkel;Referenz\n";
  tb << "# exported by a logger\n# rate 286 Hz\ntime\tgyro_dps\troll_deg\ttruth_deg\n";
  iso << "timestamp,gyro,angle,truth\n";
  auto comma = [](std::string s) {
    for (auto& c : s)
      if (c == '.') c = ',';
    return s;
  };
  for (std::size_t i = 0; i < f.rows; ++i) {
    u << g17(t[i] * 1000.0) << ',' << g17(gyro[i] * rad) << ',' << g17(angle[i]) << ','
      << g17(truth[i]) << '\n';
    g << comma(g17(t[i])) << ';' << comma(g17(gyro[i] * rad)) << ';' << comma(g17(angle[i])) << ';'
      << comma(g17(truth[i])) << "\r\n";
    if (i == f.rows / 2) tb << "# a comment in the middle\n";
    tb << g17(t[i]) << '\t' << g17(gyro[i]) << '\t' << g17(angle[i]) << '\t' << g17(truth[i])
       << '\n';
    iso << iso_at(std::llround((t[i] - t[0]) * 1e9)) << ',' << g17(gyro[i]) << ',' << g17(angle[i])
        << ',' << g17(truth[i]) << '\n';
  }
  return true;
}

// |a - b| <= 1e-12 |b|, with an absolute floor of 1e-12.
inline bool close12(double a, double b) {
  if (std::isnan(a) && std::isnan(b)) return true;
  return std::abs(a - b) <= std::max(1e-12 * std::abs(b), 1e-12);
}

}  // namespace kfw::testing
