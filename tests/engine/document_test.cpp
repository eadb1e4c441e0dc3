// The Qt-free document: undo/redo restores values exactly; data, mapping and snapshot deletion
// are undoable; sessions serialise it with data by path.
#include "document/document.h"

#include <gtest/gtest.h>

#include <fstream>

namespace kfw {
namespace {

Document helicopter() {
  auto d = Document::open("helicopter", std::nullopt);
  EXPECT_TRUE(d.ok()) << d.error();
  return std::move(*d);
}

TEST(Document, UndoRedoRestoresValuesExactly) {
  Document d = helicopter();
  const ParamValues start = d.values();
  EXPECT_FALSE(d.dirty());
  ASSERT_TRUE(d.set_value("Q", 0.1 + 0.2).ok());
  ASSERT_TRUE(d.set_value("R", 1.0 / 3.0).ok());
  ASSERT_TRUE(d.set_values({{"Q", 1e-6}, {"gamma", 0.003}}, "tune").ok());
  const ParamValues tuned = d.values();
  EXPECT_TRUE(d.dirty());
  EXPECT_EQ(d.undo_depth(), 3u);
  EXPECT_EQ(d.undo_label(), "tune");
  ASSERT_TRUE(d.undo());
  EXPECT_EQ(d.values().at("Q"), 0.1 + 0.2);
  EXPECT_EQ(d.values().at("R"), 1.0 / 3.0);
  ASSERT_TRUE(d.undo());
  ASSERT_TRUE(d.undo());
  EXPECT_EQ(d.values(), start);  // bit for bit
  EXPECT_FALSE(d.dirty());       // back where it was opened: nothing to lose
  EXPECT_FALSE(d.undo());
  ASSERT_TRUE(d.redo());
  ASSERT_TRUE(d.redo());
  ASSERT_TRUE(d.redo());
  EXPECT_EQ(d.values(), tuned);
  EXPECT_FALSE(d.redo());
  // A new change after an undo drops the redo branch.
  ASSERT_TRUE(d.undo());
  ASSERT_TRUE(d.set_value("m", 5).ok());
  EXPECT_FALSE(d.can_redo());
}

TEST(Document, InvalidChangesChangeNothing) {
  Document d = helicopter();
  const ParamValues start = d.values();
  EXPECT_FALSE(d.set_value("R", -1).ok());
  EXPECT_FALSE(d.set_value("nope", 1).ok());
  EXPECT_FALSE(d.set_values({{"Q", 2}, {"R", -1}}, "bad").ok());
  EXPECT_FALSE(d.apply_assignment("Q=abc").ok());
  EXPECT_EQ(d.values(), start);
  EXPECT_FALSE(d.can_undo());
  EXPECT_FALSE(d.dirty());
}

TEST(Document, DragsJoinOneUndoStep) {
  Document d = helicopter();
  const double q0 = d.values().at("Q");
  for (double q : {10.0, 20.0, 30.0})
    ASSERT_TRUE(d.set_value("Q", q, UndoMerge::kMergeSameKey).ok());
  ASSERT_TRUE(d.set_value("R", 5.0, UndoMerge::kMergeSameKey).ok());
  EXPECT_EQ(d.undo_depth(), 2u);
  ASSERT_TRUE(d.undo());
  ASSERT_TRUE(d.undo());
  EXPECT_EQ(d.values().at("Q"), q0);
}

TEST(Document, DataMappingAndSnapshotDeletionAreUndoable) {
  Document d = helicopter();
  EXPECT_FALSE(d.data().has_value());
  EXPECT_FALSE(d.set_mapping({{"gyro", {"gx"}}}).ok());  // no dataset: nothing to map
  d.set_data(DataRef{"/logs/a.csv", {}});
  ASSERT_TRUE(d.set_mapping({{"gyro", {"gx", "rad/s"}}}).ok());
  d.add_snapshot({"loose", d.values()});
  d.add_snapshot({"tight", d.values()});
  ASSERT_TRUE(d.remove_snapshot(0).ok());
  EXPECT_FALSE(d.remove_snapshot(7).ok());
  ASSERT_EQ(d.snapshots().size(), 1u);
  EXPECT_EQ(d.snapshots()[0].name, "tight");
  ASSERT_TRUE(d.undo());  // the deletion
  ASSERT_EQ(d.snapshots().size(), 2u);
  EXPECT_EQ(d.snapshots()[0].name, "loose");
  ASSERT_TRUE(d.undo());
  ASSERT_TRUE(d.undo());
  ASSERT_TRUE(d.undo());  // the mapping
  ASSERT_TRUE(d.data().has_value());
  EXPECT_TRUE(d.data()->mapping.empty());
  ASSERT_TRUE(d.undo());  // the dataset
  EXPECT_FALSE(d.data().has_value());
}

TEST(Document, ResetToPresetKeepsSnapshots) {
  Document d = helicopter();
  ASSERT_TRUE(d.set_value("Q", 5).ok());
  d.add_snapshot({"pinned", d.values()});
  d.reset_to_preset();
  EXPECT_EQ(d.values(), d.preset().values);
  EXPECT_EQ(d.snapshots().size(), 1u);
  ASSERT_TRUE(d.undo());
  EXPECT_EQ(d.values().at("Q"), 5);
}

TEST(Document, SessionRoundTripKeepsEverythingByPath) {
  Document d = helicopter();
  ASSERT_TRUE(d.set_value("R", 4.5).ok());
  const std::string csv = ::testing::TempDir() + "/kfw_doc.csv";
  { std::ofstream(csv) << "t,gx,angle\n0,1,2\n0.02,1,2\n"; }
  d.set_data(DataRef{csv, {{"gyro", {"gx"}}}});
  d.set_tuning_set({{csv, {{"gyro", {"gx"}}}}});
  d.add_snapshot({"pinned", d.values()});
  d.set_view_state("zoom:0:10");
  const Session s = d.to_session();
  EXPECT_EQ(s.data_hash.size(), 16u);
  auto text = session_to_json(s);
  EXPECT_EQ(text.find("0.02,1,2"), std::string::npos);  // data by path, never the data
  auto parsed = parse_session(text, "s.json");
  ASSERT_TRUE(parsed.ok()) << parsed.error();
  auto back = Document::from_session(*parsed, "s.json");
  ASSERT_TRUE(back.ok()) << back.error();
  EXPECT_EQ(back->values(), d.values());
  EXPECT_EQ(back->data(), d.data());
  EXPECT_EQ(back->tuning_set(), d.tuning_set());
  EXPECT_EQ(back->snapshots(), d.snapshots());
  EXPECT_EQ(back->view_state(), "zoom:0:10");
  // A value outside the preset's table is refused with its key.
  Session bad = s;
  bad.values["R"] = -3;
  auto refused = Document::from_session(bad, "s.json");
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.error().find("s.json: values.R"), std::string::npos) << refused.error();
}

}  // namespace
}  // namespace kfw
