// Replay transport: play / pause / step / seek / speed over the time axis of a run.
#pragma once

#include <QTimer>
#include <QWidget>
#include <cstddef>
#include <vector>

class QToolButton;
class QSlider;
class QComboBox;
class QCheckBox;
class QLabel;

namespace kfw {

class TransportBar : public QWidget {
  Q_OBJECT
 public:
  explicit TransportBar(QWidget* parent = nullptr);

  // The time stamps of the current run; keeps the cursor time when possible.
  void setTimes(const std::vector<double>& t);
  // The step shown; SIZE_MAX when "all" is on.
  std::size_t cursor() const;
  bool showAll() const;
  void setShowAll(bool all);
  void seek(std::size_t index);
  void play();
  void pause();
  bool playing() const { return timer_.isActive(); }
  double speed() const;

 signals:
  void cursorChanged(std::size_t index);

 private:
  void tick();
  void emitCursor();

  QToolButton *play_ = nullptr, *back_ = nullptr, *fwd_ = nullptr, *start_ = nullptr;
  QSlider* seek_ = nullptr;
  QComboBox* speed_ = nullptr;
  QCheckBox* all_ = nullptr;
  QLabel* time_ = nullptr;
  QTimer timer_;
  std::vector<double> t_;
  std::size_t index_ = 0;
  double play_time_ = 0.0;
};

}  // namespace kfw
