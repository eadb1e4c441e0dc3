// kfw-cli export-c (issue 31): the exported C compiles with gcc and clang (-std=c99 -Wall
// -Wextra -Werror -pedantic), and its example run over a dataset reproduces `kfw-cli run --out`:
// estimates to 1e-9 in double (|a − b| ≤ tol·(|b| + σ_b), ../shared/STAGE.md), --float to 1e-4 of
// the double export after the first second, --steady equal to filter = steady and to the full
// filter after its transient; sanitizers report nothing; a re-export is byte-identical; a model
// that cannot be exported says so in one line with exit 2 and writes nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>

#include "common/cli_runner.h"
#include "common/short_temp_dir.h"

namespace kfw {
namespace {

namespace fs = std::filesystem;
using testing::cli;
using testing::run_command;

const std::string kPresets = std::string(KFW_SOURCE_DIR) + "/presets/";
const std::string kBroad =
    std::string(KFW_SHARED_DIR) + "/data/broad/10_undisturbed_slow_translation_A.csv";
const char* kStrict = "-std=c99 -Wall -Wextra -Werror -pedantic -O2 -ffp-contract=off";

struct CsvTable {
  std::vector<std::string> names;
  std::vector<std::vector<double>> rows;
  int col(const std::string& n) const {
    for (std::size_t i = 0; i < names.size(); ++i)
      if (names[i] == n) return static_cast<int>(i);
    return -1;
  }
};

std::string slurp_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

CsvTable read_csv(const std::string& path) {
  CsvTable t;
  std::ifstream in(path);
  std::string line, cell;
  if (!std::getline(in, line)) return t;
  std::stringstream h(line);
  while (std::getline(h, cell, ','))
    t.names.push_back(cell);
  while (std::getline(in, line)) {
    std::vector<double> row;
    std::stringstream r(line);
    while (std::getline(r, cell, ','))
      row.push_back(cell.empty() ? NAN : std::strtod(cell.c_str(), nullptr));
    t.rows.push_back(row);
  }
  return t;
}

// The largest |a − b| / (|b| + floor) over the columns of `a` from time t0 on: x.S with σ_S
// from b's P.S, P.S.T with √(P.S·P.T), P.S with |b|. Fails on a column b lacks.
double worst_error(const CsvTable& a, const CsvTable& b, double t0, bool states_only,
                   std::string& where, const std::string& skip = {}) {
  EXPECT_EQ(a.rows.size(), b.rows.size());
  double worst = 0.0;
  for (std::size_t j = 1; j < a.names.size(); ++j) {
    const std::string& n = a.names[j];
    if ((states_only && n.rfind("x.", 0) != 0) || n == skip || n.rfind("mu.", 0) == 0) continue;
    const int jb = b.col(n);
    EXPECT_GE(jb, 0) << n;
    if (jb < 0) return INFINITY;
    for (std::size_t k = 0; k < std::min(a.rows.size(), b.rows.size()); ++k) {
      const auto& rb = b.rows[k];
      if (rb[0] < t0) continue;
      const double x = a.rows[k][j], y = rb[static_cast<std::size_t>(jb)];
      if (std::isnan(x) && std::isnan(y)) continue;  // no estimate in either (before x0)
      double floor = 0.0;
      if (n.rfind("x.", 0) == 0) {
        const int p = b.col("P." + n.substr(2));
        if (p >= 0) floor = std::sqrt(std::fabs(rb[static_cast<std::size_t>(p)]));
      } else if (std::count(n.begin(), n.end(), '.') == 2) {
        const auto dot = n.find('.', 2);
        const int p = b.col(n.substr(0, dot)), q = b.col("P." + n.substr(dot + 1));
        if (p >= 0 && q >= 0)
          floor = std::sqrt(
              std::fabs(rb[static_cast<std::size_t>(p)] * rb[static_cast<std::size_t>(q)]));
      }
      const double e = std::fabs(x - y) / (std::fabs(y) + floor);
      if (!(e <= worst) && !(x == y)) {
        worst = e;
        where = n + " at row " + std::to_string(k) + ": " + std::to_string(x) + " vs " +
                std::to_string(y);
      }
    }
  }
  return worst;
}

// The largest |a − b| of the mode probabilities (mu.MODE): kfw keeps them in single precision
// (ImmSeries::mu), so they agree to its rounding, 6e-8, not to 1e-9.
double mu_error(const CsvTable& a, const CsvTable& b) {
  double worst = 0.0;
  for (std::size_t j = 1; j < a.names.size(); ++j) {
    if (a.names[j].rfind("mu.", 0) != 0) continue;
    const int jb = b.col(a.names[j]);
    EXPECT_GE(jb, 0) << a.names[j];
    for (std::size_t k = 0; jb >= 0 && k < std::min(a.rows.size(), b.rows.size()); ++k)
      worst = std::max(worst, std::fabs(a.rows[k][j] - b.rows[k][static_cast<std::size_t>(jb)]));
  }
  return worst;
}

bool have(const std::string& compiler) {
  return run_command("command -v " + compiler + " >/dev/null 2>&1").code == 0;
}

// The system compilers the exports are checked with; under CI=true none may be missing.
std::vector<std::string> compilers() {
  std::vector<std::string> out;
  const char* ci = std::getenv("CI");
  for (const char* cc : {"gcc", "clang"}) {
    if (have(cc)) {
      out.push_back(cc);
    } else {
      EXPECT_FALSE(ci && std::string(ci) == "true") << cc << " is missing (scripts/setup.sh)";
    }
  }
  return out;
}

class CExport : public testing::ShortTempDir {
 protected:
  // The dataset of `preset` with `sets`: simulated into data.csv, or `file`.
  std::string data(const std::string& preset, const std::string& sets,
                   const std::string& file = {}) {
    if (!file.empty()) return file;
    const std::string out = dir_ + "/data.csv";
    const auto c = cli("simulate " + preset + " " + sets + " --out " + out);
    EXPECT_EQ(c.code, 0) << c.text;
    return out;
  }
  // export-c into DIR/NAME, compiled with `cc` and `flags`; the example's estimates on `csv`.
  CsvTable exported(const std::string& preset, const std::string& args, const std::string& name,
                    const std::string& csv, const std::string& cc = "gcc",
                    const std::string& flags = kStrict) {
    const std::string d = dir_ + "/" + name;
    fs::create_directories(d);
    const auto e = cli("export-c " + preset + " " + args + " --out-dir " + d + " --prefix f");
    EXPECT_EQ(e.code, 0) << e.text;
    const auto c = run_command(cc + " " + flags + " " + d + "/f.c " + d + "/f_example.c -lm -o " +
                               d + "/ex 2>&1");
    EXPECT_EQ(c.code, 0) << cc << ": " << c.text;
    const auto r = run_command(d + "/ex " + csv + " " + d + "/est.csv 2>&1");
    EXPECT_EQ(r.code, 0) << r.text;
    EXPECT_EQ(r.text, "");  // nothing on stderr (a sanitizer's report would be there)
    return read_csv(d + "/est.csv");
  }
  CsvTable run(const std::string& preset, const std::string& args, const std::string& csv) {
    const std::string out = dir_ + "/run_" + std::to_string(runs_++) + ".csv";
    const auto r =
        cli("run " + preset + " " + args + " --data " + csv + " --out " + out, "2>&1 >/dev/null");
    EXPECT_EQ(r.code, 0) << r.text;
    return read_csv(out);
  }
  int runs_ = 0;
};

struct Case {
  const char* preset;
  const char* sets;
  bool broad;
};

const Case kCases[] = {
    {"broad_imu.json", "", true},                              // the helicopter filter on BROAD
    {"models/cv1d.json", "", false},                           // constant velocity (KF)
    {"models/range_bearing.json", "", false},                  // range-bearing EKF
    {"models/range_bearing.json", "--set filter=ukf", false},  // and UKF
    {"models/singer.json", "", false},                         // continuous time (Van Loan per dt)
    // Seed 003's beam replayed (mode 1), its KF: the detection circuit's missing flags, an input.
    {"ballbeam.json", "--set mode=1 --set filter=kf", false},
    // The continuous nonlinear process: RK4 in sub-steps, its Jacobian, Van Loan at A(x).
    {"models/van_der_pol.json", "", false},
    {"models/van_der_pol.json", "--set filter=ukf", false},
    // Seed 004: a group of ranges — stacked (the preset's SC), sequential (SI), each on its own
    // (AS) — and the heading's input age.
    {"underwater.json", "", false},
    {"underwater.json", "--set scheme=2", false},
    {"underwater.json", "--set scheme=0", false},
};

TEST_F(CExport, DoubleExportEqualsRunOutToNineDigits) {
  const auto ccs = compilers();
  for (const Case& c : kCases) {
    if (c.broad && !fs::exists(kBroad)) {
      std::cout << "skipped " << c.preset << ": no such file " << kBroad << "\n";
      continue;
    }
    SCOPED_TRACE(std::string(c.preset) + " " + c.sets);
    const std::string p = kPresets + c.preset;
    const std::string csv = data(p, c.sets, c.broad ? kBroad : "");
    const CsvTable ref = run(p, c.sets, csv);
    for (const auto& cc : ccs) {
      SCOPED_TRACE(cc);
      const CsvTable est = exported(p, c.sets, cc + std::to_string(runs_), csv, cc);
      ASSERT_GT(est.rows.size(), 100u);
      std::string where;
      EXPECT_LE(worst_error(est, ref, -INFINITY, false, where), 1e-9) << where;
    }
  }
}

// IMMs (issue 28's modes): a list over the constant-velocity model (KF), the CV / coordinated-turn
// pair (EKF and UKF, a mode with its own process), a Markov matrix with μ0, and a grid: estimates
// and covariance to 1e-9, mode probabilities to kfw's single-precision record.
TEST_F(CExport, ImmExportEqualsRunOutInEstimatesAndModeProbabilities) {
  auto preset = nlohmann::json::parse(slurp_text(kPresets + "models/cv_imm.json"));
  auto dense = preset;
  dense["model"]["modes"]["markov"] = {{"matrix", {{0.97, 0.03}, {0.1, 0.9}}}};
  dense["model"]["modes"]["mu0"] = {0.8, 0.2};
  auto grid = preset;
  grid["model"]["modes"] = {
      {"grid", {{{"param", "q_quiet"}, {"min", 0.01}, {"max", 3}, {"n", 4}, {"label", "q"}}}},
      {"markov", {{"stay", 0.9}}}};
  const std::pair<std::string, std::string> cases[] = {
      {kPresets + "models/cv_imm.json", ""},
      {kPresets + "models/cv_ct_imm.json", ""},
      {kPresets + "models/cv_ct_imm.json", "--set filter=ukf"},
      {write("dense.json", dense.dump()), ""},
      {write("grid.json", grid.dump()), ""},
      // Seed 001: a 49-mode grid, block structure (approximate), each mode's pseudo-measurement
      // (a pre-processed channel), x0 from its first sample at the grid's centre, Van Loan.
      {kPresets + "radome.json", ""},
  };
  for (const auto& [p, sets] : cases) {
    SCOPED_TRACE(p + " " + sets);
    const std::string csv = data(p, sets);
    const CsvTable ref = run(p, sets, csv);
    const CsvTable est = exported(p, sets, "imm" + std::to_string(runs_++), csv);
    ASSERT_GT(est.rows.size(), 100u);
    const auto modes = [](const CsvTable& t) {
      return std::count_if(t.names.begin(), t.names.end(),
                           [](const std::string& n) { return n.rfind("mu.", 0) == 0; });
    };
    EXPECT_GE(modes(est), 2);
    EXPECT_EQ(modes(est), modes(ref));
    std::string where;
    EXPECT_LE(worst_error(est, ref, -INFINITY, false, where), 1e-9) << where;
    EXPECT_LE(mu_error(est, ref), 1e-7);
  }
}

TEST_F(CExport, FloatExportWithinOneInTenThousandOfTheDoubleAfterOneSecond) {
  // Single precision resolves a value to 6e-8 of itself: the Singer run stays within 30 s, where
  // its position (a double integral of the acceleration) is small enough for 1e-4 of σ. On BROAD
  // the bias is a deterministic low-pass of the gyro (Q has no bias term, its σ falls to 1e-47):
  // 1 − γ rounded to float moves it by 5e-6 deg/s, 3 % of its 2e-4 deg/s; θ is compared.
  const Case cases[] = {{"broad_imu.json", "", true},
                        {"models/cv1d.json", "", false},
                        {"models/range_bearing.json", "", false},
                        {"models/range_bearing.json", "--set filter=ukf", false},
                        {"models/singer.json", "--set sim.duration=30", false},
                        {"models/cv_imm.json", "", false}};
  for (const Case& c : cases) {
    if (c.broad && !fs::exists(kBroad)) continue;
    SCOPED_TRACE(std::string(c.preset) + " " + c.sets);
    const std::string p = kPresets + c.preset;
    const std::string csv = data(p, c.sets, c.broad ? kBroad : "");
    const CsvTable d = exported(p, c.sets, "d" + std::to_string(runs_++), csv);
    const CsvTable f =
        exported(p, std::string(c.sets) + " --float", "f" + std::to_string(runs_++), csv);
    std::string where;
    EXPECT_LE(worst_error(f, d, d.rows[0][0] + 1.0, true, where, c.broad ? "x.bias" : ""), 1e-4)
        << where;
  }
}

TEST_F(CExport, SteadyEqualsTheSteadyFilterAndTheFullFilterAfterItsTransient) {
  struct SteadyCase {
    const char* preset;
    const char* sets;
    double settled;  // s: the full filter's gain has converged (and, with dropouts, re-converged)
    bool broad;
  };
  const SteadyCase cases[] = {
      {"helicopter.json", "--set gamma=0.005", 100.0, false},
      {"models/cv1d.json", "--set sim.duration=600", 300.0, false},
      {"broad_imu.json", "", 100.0, true},
      // Seed 003's α-β filter (the preset's own filter = steady), replayed with its missing
      // samples: after each gap the full filter's gain differs, so only the steady filter is
      // compared.
      {"ballbeam.json", "--set mode=1", INFINITY, false},
  };
  for (const auto& c : cases) {
    if (c.broad && !fs::exists(kBroad)) continue;
    SCOPED_TRACE(c.preset);
    const std::string p = kPresets + c.preset;
    const std::string csv = data(p, c.sets, c.broad ? kBroad : "");
    const CsvTable st =
        exported(p, std::string(c.sets) + " --steady", "s" + std::to_string(runs_), csv);
    ASSERT_EQ(st.names.size(), 1 + 2u);  // t and the states: no covariance on the target
    std::string where;
    EXPECT_LE(worst_error(st, run(p, std::string(c.sets) + " --set filter=steady", csv), -INFINITY,
                          true, where),
              1e-9)
        << where;
    EXPECT_LE(worst_error(st, run(p, c.sets, csv), c.settled, true, where), 1e-6) << where;
  }
}

TEST_F(CExport, ExampleUnderAddressAndUndefinedSanitizersReportsNothing) {
  const std::string flags = std::string(kStrict) + " -g -fsanitize=address,undefined " +
                            "-fno-sanitize-recover=all -fno-omit-frame-pointer";
  // One of each kind of generated code: KF and Van Loan, EKF, UKF (and in float), RK4, missing
  // flags and an input, an IMM, a stacked group with an input age.
  const std::pair<const char*, const char*> cases[] = {
      {"models/singer.json", ""},
      {"models/range_bearing.json", ""},
      {"models/range_bearing.json", "--set filter=ukf"},
      {"models/range_bearing.json", "--set filter=ukf --float"},
      {"models/van_der_pol.json", ""},
      {"ballbeam.json", "--set mode=1"},
      {"models/cv_ct_imm.json", ""},
      {"underwater.json", "--set sim.duration=30"},
  };
  for (const auto& [preset, args] : cases) {
    SCOPED_TRACE(std::string(preset) + " " + args);
    const std::string p = kPresets + preset;
    std::string sets = args;
    if (const auto f = sets.find(" --float"); f != std::string::npos) sets.erase(f);
    const std::string csv = data(p, sets);
    const CsvTable est = exported(p, args, "san" + std::to_string(runs_++), csv, "gcc", flags);
    EXPECT_GT(est.rows.size(), 100u);
  }
}

// --params-struct (the generator's second mode, for the native path): the same estimates as the
// constants, and KEY=VALUE on the example equals kfw-cli run --set.
TEST_F(CExport, ParamsStructEqualsTheConstantsAndTakesNewValues) {
  const std::string p = kPresets + "models/range_bearing.json";
  const std::string csv = data(p, "");
  const CsvTable baked = exported(p, "", "baked", csv);
  const CsvTable rt = exported(p, "--params-struct", "rt", csv);
  std::string where;
  EXPECT_EQ(worst_error(rt, baked, -INFINITY, false, where), 0.0) << where;
  const std::string d = dir_ + "/rt";
  const auto r =
      run_command(d + "/ex " + csv + " " + d + "/set.csv sigma_a=0.7 sigma_range=12 2>&1");
  ASSERT_EQ(r.code, 0) << r.text;
  const CsvTable ref = run(p, "--set sigma_a=0.7 --set sigma_range=12", csv);
  EXPECT_LE(worst_error(read_csv(d + "/set.csv"), ref, -INFINITY, false, where), 1e-9) << where;
  const auto bad = run_command(d + "/ex " + csv + " " + d + "/x.csv no_such=1 2>&1");
  EXPECT_EQ(bad.code, 2) << bad.text;
}

TEST_F(CExport, ReExportIsByteIdentical) {
  const std::string p = kPresets + "models/range_bearing.json";
  for (const std::string args : {"", " --set filter=ukf --float", " --set sigma_a=0.7"}) {
    for (const char* d : {"/a", "/b"}) {
      fs::create_directories(dir_ + d);
      ASSERT_EQ(cli("export-c " + p + args + " --out-dir " + dir_ + d).code, 0);
    }
    for (const char* f : {"/range_bearing.h", "/range_bearing.c", "/range_bearing_example.c"}) {
      const std::string a = slurp_text(dir_ + "/a" + f);
      EXPECT_FALSE(a.empty());
      EXPECT_EQ(a, slurp_text(dir_ + "/b" + f)) << f;
    }
  }
}

TEST_F(CExport, AModelThatCannotBeExportedSaysSoInOneLineAndWritesNothing) {
  const std::pair<std::string, std::string> cases[] = {
      {"underwater.json", "--set filter=ukf"},    // a stacked group in the UKF (as kfw)
      {"models/range_bearing.json", "--steady"},  // --steady on a nonlinear model
      {"radome.json", "--set Kp=0.1"},            // the IMM's renewal (not yet)
      {"models/cv_imm.json", "--steady"},         // an IMM has no single steady state
      {"models/cv1d.json", "--prefix 9lives"},    // not a C identifier
      {"models/cv1d.json", "--prefix int"},       // a keyword
      {"models/cv1d.json", "--dt 0.1"},           // --dt without --steady
      {"models/cv1d.json", "--steady --dt -1"},  {"models/cv1d.json", "--out-dir /nonexistent/dir"},
  };
  for (const auto& [preset, args] : cases) {
    SCOPED_TRACE(preset + " " + args);
    const std::string out = args.find("--out-dir") == std::string::npos ? " --out-dir " + dir_ : "";
    const auto c = cli("export-c " + kPresets + preset + " " + args + out);
    EXPECT_EQ(c.code, 2) << c.text;
    EXPECT_EQ(std::count(c.text.begin(), c.text.end(), '\n'), 1) << c.text;
    EXPECT_TRUE(fs::is_empty(dir_)) << c.text;
  }
  // An output that is an input (the data named like an export) is refused, the data kept.
  const std::string data_file = write("f.c", "t,z\n0,1\n0.1,2\n");
  const auto same = cli("export-c " + kPresets + "models/cv1d.json --data " + data_file +
                        " --prefix f --out-dir " + dir_);
  EXPECT_EQ(same.code, 2) << same.text;
  EXPECT_EQ(slurp_text(data_file), "t,z\n0,1\n0.1,2\n");
  const auto c = cli("export-c " + kPresets + "radome.json --set Kp=0.1 --out-dir " + dir_);
  EXPECT_NE(c.text.find("radome.json"), std::string::npos) << c.text;
  EXPECT_NE(c.text.find("model.modes.renewal"), std::string::npos) << c.text;
}

}  // namespace
}  // namespace kfw
