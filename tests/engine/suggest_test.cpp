// "Did you mean": the nearest valid name for a misspelt one, and tokens quoted short.
#include "core/suggest.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace {

using kfw::nearest;

const std::vector<std::string> kCommands = {"simulate", "run",    "gain", "tune", "sweep",
                                            "params",   "preset", "list", "help", "stats"};

TEST(Suggest, EditDistanceCountsSwapsAsOneEdit) {
  EXPECT_EQ(kfw::edit_distance("", ""), 0u);
  EXPECT_EQ(kfw::edit_distance("abc", ""), 3u);
  EXPECT_EQ(kfw::edit_distance("kitten", "sitting"), 3u);
  EXPECT_EQ(kfw::edit_distance("nis", "nsi"), 1u);  // one transposition
  EXPECT_EQ(kfw::edit_distance("--data", "--dat"), 1u);
}

TEST(Suggest, NearestFindsLikelyMisspellings) {
  EXPECT_EQ(nearest("simulte", kCommands), "simulate");
  EXPECT_EQ(nearest("rnu", kCommands), "run");
  EXPECT_EQ(nearest("sweeep", kCommands), "sweep");
  EXPECT_EQ(nearest("preest", kCommands), "preset");
  EXPECT_EQ(nearest("--dat", {"--data", "--set", "--out", "--metrics"}), "--data");
  EXPECT_EQ(nearest("--metrix", {"--data", "--metric", "--metrics"}), "--metric");
  EXPECT_EQ(nearest("nsi", {"rmse", "nll", "nis"}), "nis");
  EXPECT_EQ(nearest("q", {"Q", "R", "m"}), "Q");  // case only
  EXPECT_EQ(nearest("gama", {"Q", "R", "gamma"}), "gamma");
  // A prefix of three or more characters either way.
  EXPECT_EQ(nearest("sim", kCommands), "simulate");
  EXPECT_EQ(nearest("rmse_pos", {"nis_mean", "rmse", "rmse.theta"}), "rmse");
}

TEST(Suggest, NothingWhenNothingIsNear) {
  EXPECT_FALSE(nearest("frobnicate", kCommands));
  EXPECT_FALSE(nearest("bogus", {"Q", "R", "m", "gamma", "window"}));
  EXPECT_FALSE(nearest("X", {"Q", "R"}));  // one letter is not a misspelling of another
  EXPECT_FALSE(nearest("", kCommands));
  EXPECT_FALSE(nearest("run", {}));
  EXPECT_FALSE(nearest(std::string(10'000'000, 'r'), kCommands));  // and fast
}

TEST(Suggest, TiesGoToTheFirstCandidate) {
  EXPECT_EQ(nearest("ab", {"ac", "ad"}), "ac");
}

TEST(Suggest, MessagesQuoteShortAndSuggest) {
  EXPECT_EQ(kfw::did_you_mean("simulte", kCommands), " (did you mean 'simulate'?)");
  EXPECT_EQ(kfw::did_you_mean("frobnicate", kCommands), "");
  EXPECT_EQ(kfw::unknown_message("command", "rnu", kCommands),
            "unknown command 'rnu' (did you mean 'run'?)");
  EXPECT_EQ(kfw::unknown_message("command", "frobnicate", kCommands),
            "unknown command 'frobnicate'");
}

TEST(Suggest, HugeTokensAreTruncated) {
  const std::string huge(10'000'000, 'x');
  const std::string q = kfw::quote_token(huge);
  EXPECT_LE(q.size(), kfw::kMaxQuotedToken + 8);
  EXPECT_EQ(q.substr(q.size() - 4), "…'");
  EXPECT_EQ(kfw::quote_token("short"), "'short'");
  EXPECT_EQ(kfw::truncate_token(std::string(80, 'a')), std::string(80, 'a'));
  EXPECT_EQ(kfw::truncate_token(std::string(81, 'a')), std::string(79, 'a') + "…");
  const std::string m = kfw::unknown_message("parameter", huge, {"Q"});
  EXPECT_LT(m.size(), 120u);
}

TEST(Suggest, TruncationNeverSplitsAUtf8Character) {
  std::string s;
  for (int i = 0; i < 100; ++i)
    s += "σ";  // two bytes each
  const std::string t = kfw::truncate_token(s, 10);
  EXPECT_EQ(t, "σσσσ…");  // 9 bytes available: four whole characters
}

TEST(Suggest, OneLineFlattensAndShortensLongWords) {
  EXPECT_EQ(kfw::one_line("a\nb\n"), "a b");
  const std::string path = "/" + std::string(5000, 'd') + "/file.csv:12:3:";
  const std::string m = kfw::one_line(path + " time is not increasing");
  EXPECT_LT(m.size(), 200u);
  EXPECT_NE(m.find("file.csv:12:3: time is not increasing"), std::string::npos) << m;
  EXPECT_NE(m.find("…"), std::string::npos);
}

}  // namespace
