// Replay transport: play / pause / step / seek / speed over the time axis of a run, a typed time
// to seek to, and the following window (the last N seconds) the plots show while playing.
#pragma once

#include <QJsonObject>
#include <QTimer>
#include <QWidget>
#include <cstddef>
#include <vector>

class QToolButton;
class QSlider;
class QComboBox;
class QCheckBox;
class QLineEdit;

namespace kfw {

class TransportBar : public QWidget {
  Q_OBJECT
 public:
  explicit TransportBar(QWidget* parent = nullptr);

  // The time stamps of the current run; keeps the cursor time when possible. The first run
  // puts the cursor at the end (the plots show the whole run, up to the cursor).
  void setTimes(const std::vector<double>& t);
  // Another preset or session: stopped and without times, so its first run shows the whole run
  // (the cursor at the end) instead of the last preset's replay time.
  void reset();
  // The step shown; SIZE_MAX when "all" is on.
  std::size_t cursor() const;
  // The step the cursor is at, also with "all" on.
  std::size_t index() const { return index_; }
  bool showAll() const;
  void setShowAll(bool all);
  void seek(std::size_t index);
  // Seeks to the last step at or before t (seconds).
  void seekTime(double t);
  void stepBy(int steps);
  void play();
  void pause();
  void togglePlay() { playing() ? pause() : play(); }
  bool playing() const { return timer_.isActive(); }
  double speed() const;
  // The following window's length in s; 0 for the whole run.
  double windowSeconds() const;
  // The time window [t0, t1] the plots follow for the cursor (the window's length, the cursor
  // near its right edge); the whole run when the window is "whole run".
  std::pair<double, double> timeWindow() const;
  // What the text field shows ("t = 12.34 s", "all · 0–60 s").
  QString timeText() const;
  // The replay state for a session: cursor time, show all, speed, window.
  QJsonObject saveState() const;
  void restoreState(const QJsonObject& o);

 signals:
  void cursorChanged(std::size_t index);
  void playingChanged(bool playing);
  // While playing (and on "show all"): the time range every time plot should show.
  void timeWindowChanged(double t0, double t1);

 private:
  void tick();
  void emitCursor();

  QToolButton *play_ = nullptr, *back_ = nullptr, *fwd_ = nullptr, *start_ = nullptr;
  QSlider* seek_ = nullptr;
  QComboBox* speed_ = nullptr;
  QComboBox* window_ = nullptr;
  QCheckBox* all_ = nullptr;
  QLineEdit* time_ = nullptr;
  QTimer timer_;
  std::vector<double> t_;
  std::size_t index_ = 0;
  double play_time_ = 0.0;
};

}  // namespace kfw
