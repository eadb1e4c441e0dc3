// The import tests' window: the broad_imu preset, and the real log's layouts written to a
// temporary directory (`rows` rows each), opened through the import dialog.
#pragma once

#include <gtest/gtest.h>

#include <QSettings>
#include <QTemporaryDir>
#include <functional>
#include <string>

#include "common/import_files.h"
#include "import_dialog.h"
#include "main_window.h"

namespace kfw::testing {

class ImportWindow : public ::testing::Test {
 protected:
  explicit ImportWindow(std::size_t rows) : rows_(rows) {}
  void SetUp() override {
    QSettings("kfw", "kfw").remove("columnMaps");
    if (!testing::make_import_files(dir.path().toStdString(), rows_, files))
      GTEST_SKIP() << "no real log";
    ASSERT_TRUE(w.loadPreset("broad_imu").ok());
    ASSERT_TRUE(w.waitForRun());
  }
  void TearDown() override { QSettings("kfw", "kfw").remove("columnMaps"); }

  // Opens `file` through the dialog, configured by `set`; returns the run's metrics.
  Metrics open(const std::string& file, const std::function<void(ImportDialog&)>& set) {
    w.setImportHook([&](ImportDialog& d) {
      set(d);
      EXPECT_EQ(d.problem(), QString()) << file;
      return true;
    });
    const auto st = w.openDataset(QString::fromStdString(file));
    EXPECT_TRUE(st.ok()) << st.error();
    EXPECT_TRUE(w.waitForRun());
    EXPECT_EQ(w.dataset()->source, file);
    return w.result() ? w.result()->metrics : Metrics{};
  }

  void expect_same(const Metrics& got, const Metrics& want, const char* what) {
    ASSERT_TRUE(want.count("rmse"));
    for (const auto& [k, v] : want) {
      ASSERT_TRUE(got.count(k)) << what << ": " << k;
      EXPECT_TRUE(testing::close12(got.at(k), v))
          << what << ": " << k << " " << got.at(k) << " vs " << v;
    }
  }

  std::size_t rows_;
  QTemporaryDir dir;
  testing::ImportFiles files;
  MainWindow w;
};

}  // namespace kfw::testing
