// The one value grammar: grids lo:hi:n[:log|:lin], integer sets 1..50 / 3,7,9, shards i/N.
#include "experiment/grammar.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace {

using kfw::parse_grid;
using kfw::parse_int_set;
using kfw::parse_shard;

TEST(Grammar, GridLinear) {
  auto g = parse_grid("0:1:5", "--param Q");
  ASSERT_TRUE(g.ok()) << g.error();
  EXPECT_EQ(g->n, 5u);
  EXPECT_EQ(g->spacing, kfw::Spacing::kDefault);
  EXPECT_EQ(g->values(false), (std::vector<double>{0, 0.25, 0.5, 0.75, 1}));
  auto lin = parse_grid("-2:2:3:lin", "--x");
  ASSERT_TRUE(lin.ok()) << lin.error();
  EXPECT_EQ(lin->spacing, kfw::Spacing::kLinear);
  EXPECT_EQ(lin->values(false), (std::vector<double>{-2, 0, 2}));
}

TEST(Grammar, GridLog) {
  auto g = parse_grid("1:1e4:5:log", "--param Q");
  ASSERT_TRUE(g.ok()) << g.error();
  EXPECT_EQ(g->spacing, kfw::Spacing::kLog);
  const auto v = g->values(true);
  ASSERT_EQ(v.size(), 5u);
  for (int i = 0; i < 5; ++i)
    EXPECT_NEAR(v[static_cast<std::size_t>(i)], std::pow(10.0, i), 1e-9 * std::pow(10.0, i));
  EXPECT_EQ(v.back(), 1e4);  // exactly hi
}

TEST(Grammar, GridOfOnePointIsLo) {
  auto g = parse_grid("3:9:1", "--x");
  ASSERT_TRUE(g.ok());
  EXPECT_EQ(g->values(false), std::vector<double>{3});
}

TEST(Grammar, GridRejectsNamingTheOption) {
  for (const char* bad :
       {"", "1:2", "1:2:3:4:5", "a:2:3", "1:b:3", "1:2:0", "1:2:2.5", "1:2:-1", "1:2:3:logg",
        "0:10:3:log", "-1:10:3:log", "1:2:2000000", "nan:1:2", "1:inf:2"}) {
    auto g = parse_grid(bad, "--param Q");
    ASSERT_FALSE(g.ok()) << bad;
    EXPECT_EQ(g.error().rfind("--param Q: ", 0), 0u) << g.error();
    EXPECT_EQ(g.err().exit_code, kfw::kExitInvalid);
  }
  EXPECT_NE(parse_grid("1:2:3:logg", "--x").error().find("did you mean 'log'"), std::string::npos);
  EXPECT_NE(parse_grid("0:10:3:log", "--x").error().find("lo, hi > 0"), std::string::npos);
}

TEST(Grammar, IntegerSets) {
  EXPECT_EQ(*parse_int_set("3,7,9", "--seeds"), (std::vector<long long>{3, 7, 9}));
  EXPECT_EQ(*parse_int_set("1..5", "--seeds"), (std::vector<long long>{1, 2, 3, 4, 5}));
  EXPECT_EQ(*parse_int_set("1..3,9", "--seeds"), (std::vector<long long>{1, 2, 3, 9}));
  EXPECT_EQ(*parse_int_set("9, 1..3 ,2", "--seeds"), (std::vector<long long>{1, 2, 3, 9}));
  EXPECT_EQ(*parse_int_set("7", "--seeds"), std::vector<long long>{7});
  EXPECT_EQ(*parse_int_set("5..5", "--seeds"), std::vector<long long>{5});
  EXPECT_EQ(*parse_int_set("-2..1", "--seeds"), (std::vector<long long>{-2, -1, 0, 1}));
  EXPECT_EQ(parse_int_set("1..50", "--seeds")->size(), 50u);
  EXPECT_EQ(parse_int_set("1..1000000", "--seeds")->size(), 1'000'000u);
}

TEST(Grammar, IntegerSetsRejectNamingTheOption) {
  for (const char* bad :
       {"", " ", ",", "1,", ",1", "1,,2", "5..1", "1.5", "1..2.5", "a", "1..", "..3", "1...3",
        "1..1000001", "1..600000,2..600000", "0..9223372036854775807",
        "-9223372036854775807..9223372036854775807", "99999999999999999999"}) {
    auto s = parse_int_set(bad, "--seeds");
    ASSERT_FALSE(s.ok()) << bad;
    EXPECT_EQ(s.error().rfind("--seeds: ", 0), 0u) << s.error();
  }
  EXPECT_NE(parse_int_set("5..1", "--seeds").error().find("reversed"), std::string::npos);
  EXPECT_NE(parse_int_set("", "--seeds").error().find("empty"), std::string::npos);
  EXPECT_NE(parse_int_set("1..2000000", "--seeds").error().find("1000000"), std::string::npos);
}

TEST(Grammar, HugeTokensAreNotEchoed) {
  const std::string huge = "1," + std::string(10'000'000, '7') + "x";
  auto s = parse_int_set(huge, "--seeds");
  ASSERT_FALSE(s.ok());
  EXPECT_LT(s.error().size(), 400u);
  auto g = parse_grid(std::string(10'000'000, '1'), "--param Q");
  ASSERT_FALSE(g.ok());
  EXPECT_LT(g.error().size(), 400u);
}

TEST(Grammar, Shards) {
  auto s = parse_shard("2/3", "--shard");
  ASSERT_TRUE(s.ok()) << s.error();
  EXPECT_EQ(s->index, 2u);
  EXPECT_EQ(s->count, 3u);
  EXPECT_TRUE(parse_shard("1/1", "--shard").ok());
  for (const char* bad :
       {"", "0/3", "4/3", "1/0", "1", "1/2/3", "a/2", "1/b", "-1/2", "1.5/2", "/"}) {
    auto b = parse_shard(bad, "--shard");
    ASSERT_FALSE(b.ok()) << bad;
    EXPECT_EQ(b.error().rfind("--shard: ", 0), 0u) << b.error();
  }
}

TEST(Grammar, ShardsPartitionTheWork) {
  // Item index goes to shard i when index mod N = i - 1: every item in exactly one shard.
  const std::size_t n = 3;
  for (std::size_t index = 0; index < 20; ++index) {
    int owners = 0;
    for (std::size_t i = 1; i <= n; ++i)
      owners += kfw::in_shard(index, kfw::Shard{i, n}) ? 1 : 0;
    EXPECT_EQ(owners, 1) << index;
    EXPECT_TRUE(kfw::in_shard(index, kfw::Shard{index % n + 1, n}));
  }
  EXPECT_TRUE(kfw::in_shard(0, kfw::Shard{1, 3}));
  EXPECT_TRUE(kfw::in_shard(4, kfw::Shard{2, 3}));
  EXPECT_FALSE(kfw::in_shard(4, kfw::Shard{1, 3}));
}

TEST(Grammar, HelpDocumentsEveryForm) {
  const std::string h = kfw::value_grammar_help();
  for (const char* s : {"lo:hi:n", ":log", ":lin", "1..50", "3,7,9", "i/N", "index mod N = i - 1"})
    EXPECT_NE(h.find(s), std::string::npos) << s;
}

}  // namespace
