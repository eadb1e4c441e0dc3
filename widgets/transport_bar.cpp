#include "transport_bar.h"

#include <QCheckBox>
#include <QComboBox>
#include <QDoubleValidator>
#include <QHBoxLayout>
#include <QLabel>
#include <QLineEdit>
#include <QSignalBlocker>
#include <QSlider>
#include <QStyle>
#include <QToolButton>
#include <algorithm>

namespace kfw {

namespace {
constexpr int kTickMs = 33;
}

TransportBar::TransportBar(QWidget* parent) : QWidget(parent) {
  auto* lay = new QHBoxLayout(this);
  lay->setContentsMargins(4, 2, 4, 2);
  auto button = [this, lay](QStyle::StandardPixmap icon, const QString& tip, const char* name) {
    auto* b = new QToolButton(this);
    b->setIcon(style()->standardIcon(icon));
    b->setToolTip(tip);
    b->setObjectName(name);
    lay->addWidget(b);
    return b;
  };
  start_ = button(QStyle::SP_MediaSkipBackward, "Back to the start (Home)", "transport.start");
  back_ = button(QStyle::SP_MediaSeekBackward, "Step back one sample (←)", "transport.back");
  play_ = button(QStyle::SP_MediaPlay, "Play / pause from the cursor (Space)", "transport.play");
  fwd_ = button(QStyle::SP_MediaSeekForward, "Step forward one sample (→)", "transport.step");
  seek_ = new QSlider(Qt::Horizontal, this);
  seek_->setObjectName("transport.seek");
  seek_->setToolTip("Seek");
  seek_->setMinimumWidth(80);
  lay->addWidget(seek_, 1);
  time_ = new QLineEdit(this);
  time_->setObjectName("transport.time");
  time_->setToolTip("The cursor time; type a time in s and press Enter to go there");
  time_->setMinimumWidth(fontMetrics().horizontalAdvance("all · 0000.0–0000.0 s") + 12);
  time_->setMaximumWidth(time_->minimumWidth() + 20);
  lay->addWidget(time_);
  connect(time_, &QLineEdit::returnPressed, this, [this] {
    QString s = time_->text().trimmed();
    s.remove("t =").remove('s').remove(' ');
    bool ok = false;
    const double t = s.toDouble(&ok);
    if (ok) {
      seekTime(t);
    } else {
      time_->setText(timeText());
    }
    time_->selectAll();
  });
  connect(time_, &QLineEdit::editingFinished, this, [this] { time_->setText(timeText()); });
  speed_ = new QComboBox(this);
  speed_->setObjectName("transport.speed");
  speed_->setToolTip("Replay speed");
  for (double s : {0.25, 0.5, 1.0, 2.0, 5.0, 10.0, 50.0}) {
    speed_->addItem(QString("%1×").arg(s), s);
  }
  speed_->setCurrentIndex(2);
  lay->addWidget(speed_);
  window_ = new QComboBox(this);
  window_->setObjectName("transport.window");
  window_->setToolTip("While playing, the time plots follow the cursor over this window");
  window_->addItem("last 5 s", 5.0);
  window_->addItem("last 10 s", 10.0);
  window_->addItem("last 30 s", 30.0);
  window_->addItem("last 60 s", 60.0);
  window_->addItem("last 300 s", 300.0);
  window_->addItem("whole run", 0.0);
  window_->setCurrentIndex(1);
  lay->addWidget(window_);
  all_ = new QCheckBox("show all", this);
  all_->setObjectName("transport.all");
  all_->setToolTip("Show the whole run, ignoring the replay cursor");
  all_->setChecked(false);  // an explicit choice: ▶ then plays from the cursor
  lay->addWidget(all_);

  timer_.setInterval(kTickMs);
  connect(&timer_, &QTimer::timeout, this, &TransportBar::tick);
  connect(play_, &QToolButton::clicked, this, &TransportBar::togglePlay);
  connect(start_, &QToolButton::clicked, this, [this] { seek(0); });
  connect(back_, &QToolButton::clicked, this, [this] { stepBy(-1); });
  connect(fwd_, &QToolButton::clicked, this, [this] { stepBy(1); });
  connect(seek_, &QSlider::valueChanged, this, [this](int v) {
    if (static_cast<std::size_t>(v) != index_) seek(static_cast<std::size_t>(v));
  });
  connect(all_, &QCheckBox::toggled, this, [this](bool all) {
    if (all) pause();
    emitCursor();
    if (all && !t_.empty()) emit timeWindowChanged(t_.front(), t_.back());
  });
  time_->setText(timeText());
}

void TransportBar::setTimes(const std::vector<double>& t) {
  const bool first = t_.empty();
  const bool at_end = !t_.empty() && index_ + 1 >= t_.size();
  const double keep = index_ < t_.size() ? t_[index_] : 0.0;
  t_ = t;
  {
    const QSignalBlocker b(seek_);
    seek_->setRange(0, t_.empty() ? 0 : static_cast<int>(t_.size() - 1));
  }
  if (t_.empty()) {
    index_ = 0;
  } else if (first || at_end) {
    index_ = t_.size() - 1;  // the whole run, up to the (last) cursor
  } else {
    const auto it = std::upper_bound(t_.begin(), t_.end(), keep);
    index_ = it == t_.begin() ? 0 : static_cast<std::size_t>(it - t_.begin()) - 1;
  }
  const QSignalBlocker b(seek_);
  seek_->setValue(static_cast<int>(index_));
  if (!time_->hasFocus()) time_->setText(timeText());
}

void TransportBar::reset() {
  pause();
  setTimes({});
}

std::size_t TransportBar::cursor() const {
  return showAll() ? static_cast<std::size_t>(-1) : index_;
}

bool TransportBar::showAll() const {
  return all_->isChecked();
}
void TransportBar::setShowAll(bool all) {
  all_->setChecked(all);
}
double TransportBar::speed() const {
  return speed_->currentData().toDouble();
}
double TransportBar::windowSeconds() const {
  return window_->currentData().toDouble();
}

std::pair<double, double> TransportBar::timeWindow() const {
  if (t_.empty()) return {0.0, 0.0};
  const double first = t_.front(), last = t_.back();
  const double n = windowSeconds();
  if (n <= 0.0 || n >= last - first) return {first, last};
  // The cursor at 90 % of the window, so what comes next is in view too.
  double t0 = t_[index_] - 0.9 * n;
  t0 = std::clamp(t0, first, last - n);
  return {t0, t0 + n};
}

QString TransportBar::timeText() const {
  if (t_.empty()) return "t = – s";
  if (showAll()) {
    return QString("all · %1–%2 s").arg(t_.front(), 0, 'f', 1).arg(t_.back(), 0, 'f', 1);
  }
  return QString("t = %1 s").arg(t_[index_], 0, 'f', 2);
}

void TransportBar::seek(std::size_t index) {
  if (t_.empty()) return;
  index_ = std::min(index, t_.size() - 1);
  play_time_ = t_[index_];
  if (showAll()) {
    const QSignalBlocker b(all_);
    all_->setChecked(false);
  }
  emitCursor();
}

void TransportBar::seekTime(double t) {
  if (t_.empty()) return;
  const auto it = std::upper_bound(t_.begin(), t_.end(), t);
  seek(it == t_.begin() ? 0 : static_cast<std::size_t>(it - t_.begin()) - 1);
}

void TransportBar::stepBy(int steps) {
  if (t_.empty()) return;
  pause();
  const auto i = static_cast<long long>(index_) + steps;
  seek(
      static_cast<std::size_t>(std::clamp<long long>(i, 0, static_cast<long long>(t_.size()) - 1)));
}

void TransportBar::play() {
  if (t_.empty()) return;
  if (index_ + 1 >= t_.size()) index_ = 0;  // at the end: from the start
  play_time_ = t_[index_];
  if (showAll()) {
    const QSignalBlocker b(all_);
    all_->setChecked(false);
  }
  play_->setIcon(style()->standardIcon(QStyle::SP_MediaPause));
  const bool was = timer_.isActive();
  timer_.start();
  if (!was) emit playingChanged(true);
  emitCursor();
}

void TransportBar::pause() {
  const bool was = timer_.isActive();
  timer_.stop();
  play_->setIcon(style()->standardIcon(QStyle::SP_MediaPlay));
  if (was) emit playingChanged(false);
}

void TransportBar::tick() {
  if (t_.empty()) return pause();
  play_time_ += speed() * kTickMs / 1000.0;
  const auto it = std::upper_bound(t_.begin(), t_.end(), play_time_);
  const std::size_t next = it == t_.begin() ? 0 : static_cast<std::size_t>(it - t_.begin()) - 1;
  if (next + 1 >= t_.size()) {
    index_ = t_.size() - 1;
    pause();
  } else {
    index_ = next;
  }
  emitCursor();
}

void TransportBar::emitCursor() {
  {
    const QSignalBlocker b(seek_);
    seek_->setValue(static_cast<int>(index_));
  }
  if (!time_->hasFocus()) time_->setText(timeText());
  emit cursorChanged(cursor());
  if (playing() && !t_.empty()) {
    const auto [t0, t1] = timeWindow();
    emit timeWindowChanged(t0, t1);
  }
}

QJsonObject TransportBar::saveState() const {
  QJsonObject o;
  o["t"] = t_.empty() ? 0.0 : t_[index_];
  o["at_end"] = !t_.empty() && index_ + 1 >= t_.size();
  o["show_all"] = showAll();
  o["speed"] = speed();
  o["window_s"] = windowSeconds();
  return o;
}

void TransportBar::restoreState(const QJsonObject& o) {
  if (int i = speed_->findData(o["speed"].toDouble(1.0)); i >= 0) speed_->setCurrentIndex(i);
  if (int i = window_->findData(o["window_s"].toDouble(10.0)); i >= 0) window_->setCurrentIndex(i);
  pause();
  if (o["at_end"].toBool()) {
    seek(t_.empty() ? 0 : t_.size() - 1);
  } else {
    seekTime(o["t"].toDouble());
  }
  setShowAll(o["show_all"].toBool());
}

}  // namespace kfw
